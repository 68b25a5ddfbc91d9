#include "vk_check.h"

#include <cstdio>
#include <cstdlib>

// 500 KB of generated switch statements: included here only.
#include <vulkan/vk_enum_string_helper.h>

namespace qp {

const char* vkResultName(VkResult result) { return string_VkResult(result); }

Error vkError(const char* expression, VkResult result) {
    return Error{std::string(expression) + " failed: " + vkResultName(result)};
}

void vkAssertFailed(const char* expression, VkResult result, const char* file, int line) {
    std::fprintf(stderr, "%s:%d: %s failed: %s\n", file, line, expression, vkResultName(result));
    std::abort();
}

}  // namespace qp
