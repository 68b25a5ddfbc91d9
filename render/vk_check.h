// Checking VkResult: VK_CHECK at fallible boundaries, VK_ASSERT for programmer errors.
//
// VK_CHECK(expr) returns qp::Error{"<expr> failed: VK_ERROR_..."} from the enclosing function,
// which must return a qp::Result<T> or qp::Status. Use it where failure comes from outside the
// program: device creation, allocation, a lost device.
//
// VK_ASSERT(expr) aborts with the same message. It is evaluated in every build type (unlike
// assert): a failing Vulkan call must never be ignored silently. Use it where failure means a
// bug in our code (recording commands, creating objects whose inputs we control).
#pragma once

#include <vulkan/vulkan.h>

#include "mesh/result.h"

namespace qp {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" and the like.
const char* vkResultName(VkResult result);

// The error VK_CHECK returns: names the failing expression and the result.
Error vkError(const char* expression, VkResult result);

[[noreturn]] void vkAssertFailed(const char* expression, VkResult result, const char* file, int line);

}  // namespace qp

#define VK_CHECK(expr)                                                   \
    do {                                                                 \
        const VkResult vkCheckResult_ = (expr);                          \
        if (vkCheckResult_ != VK_SUCCESS) return ::qp::vkError(#expr, vkCheckResult_); \
    } while (0)

#define VK_ASSERT(expr)                                                  \
    do {                                                                 \
        const VkResult vkAssertResult_ = (expr);                         \
        if (vkAssertResult_ != VK_SUCCESS)                               \
            ::qp::vkAssertFailed(#expr, vkAssertResult_, __FILE__, __LINE__); \
    } while (0)
