// Shared pipelines: pipelines, layouts and samplers made once per device and target formats and
// shared by every pass that asks for them.
//
// Why: a scheme instance used to create its pass's pipelines in createGpu and destroy them in
// destroyGpu, so every rebuild after an edit, every scheme switch and every new viewport made
// them again, and lavapipe compiles a pipeline at its first draw (render/pipeline_cache.h):
// about 130 ms on the frame after any tag or topology edit (issue 15). Now the first request for
// a kind of pass on a device creates its objects and later requests get the same handles;
// destroyContext (vk_context.h) releases them once the device is idle.
//
// Passes built on this (createPlanPass, createMeshPass, createTessPatchPass, ...) hand out the
// shared handles; their destroy functions forget them and free only what is the caller's own
// (descriptor pools and sets). Requests from several threads are safe: the first one creates.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "mesh/result.h"
#include "vk_context.h"

namespace qp {

struct SharedEntry {
    std::shared_ptr<void> value;
    std::function<void(const VulkanContext&)> release;  // called once, from destroyContext
};

// The entry stored under `key` for this context's device, made by `create` when absent. A failed
// create stores nothing (the next request tries again).
Result<std::shared_ptr<void>> acquireSharedEntry(const VulkanContext& context, const std::string& key,
                                                 const std::function<Result<SharedEntry>()>& create);

// Releases every entry of this context's device (destroyContext calls it, device idle).
void releaseSharedObjects(const VulkanContext& context);

// How many entries this device's registry has created so far (tests: a rebuild creates none).
uint64_t sharedObjectsCreated(const VulkanContext& context);

// Typed front end: `create()` returns a Result<T> of handles, `release(context, T&)` destroys them.
template <class T, class Create, class Release>
Result<T> sharedDeviceObject(const VulkanContext& context, const std::string& key, Create create, Release release) {
    Result<std::shared_ptr<void>> entry = acquireSharedEntry(context, key, [&]() -> Result<SharedEntry> {
        Result<T> made = create();
        if (!made) return made.error();
        auto value = std::make_shared<T>(std::move(*made));
        return SharedEntry{value, [value, release](const VulkanContext& c) { release(c, *value); }};
    });
    if (!entry) return entry.error();
    return *static_cast<const T*>(entry->get());
}

// "name:color:depth", the usual key of a pass for targets of these formats.
std::string sharedPassKey(const char* name, VkFormat colorFormat, VkFormat depthFormat);

// The usual shared pass: a T with its colorFormat and depthFormat set, completed by `init(T&)`
// (a Status; on failure `release` destroys what it made), kept under `key`.
template <class T, class Init, class Release>
Result<T> sharedPass(const VulkanContext& context, const std::string& key, VkFormat colorFormat, VkFormat depthFormat,
                     Init init, Release release) {
    return sharedDeviceObject<T>(
        context, key,
        [&]() -> Result<T> {
            T pass;
            pass.colorFormat = colorFormat;
            pass.depthFormat = depthFormat;
            if (Status s = init(pass); !s) {
                release(context, pass);
                return s.error();
            }
            return pass;
        },
        release);
}

}  // namespace qp
