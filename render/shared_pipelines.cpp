#include "shared_pipelines.h"

#include <map>
#include <mutex>

namespace qp {

namespace {

struct DeviceRegistry {
    std::map<std::string, SharedEntry> entries;
    uint64_t created = 0;
};

// Recursive: a create function may itself ask for another shared object (a pass built on
// another pass's layouts).
std::recursive_mutex registryMutex;
std::map<VkDevice, DeviceRegistry>& registries() {
    static std::map<VkDevice, DeviceRegistry> map;
    return map;
}

}  // namespace

Result<std::shared_ptr<void>> acquireSharedEntry(const VulkanContext& ctx, const std::string& key,
                                                 const std::function<Result<SharedEntry>()>& create) {
    std::lock_guard lock(registryMutex);
    DeviceRegistry& registry = registries()[ctx.device];
    if (auto found = registry.entries.find(key); found != registry.entries.end()) return found->second.value;
    Result<SharedEntry> made = create();
    if (!made) return made.error();
    ++registry.created;
    std::shared_ptr<void> value = made->value;
    registry.entries.emplace(key, std::move(*made));
    return value;
}

void releaseSharedObjects(const VulkanContext& ctx) {
    std::lock_guard lock(registryMutex);
    auto found = registries().find(ctx.device);
    if (found == registries().end()) return;
    for (auto& [key, entry] : found->second.entries) entry.release(ctx);
    registries().erase(found);
}

uint64_t sharedObjectsCreated(const VulkanContext& ctx) {
    std::lock_guard lock(registryMutex);
    auto found = registries().find(ctx.device);
    return found == registries().end() ? 0 : found->second.created;
}

std::string sharedPassKey(const char* name, VkFormat colorFormat, VkFormat depthFormat) {
    return std::string(name) + ":" + std::to_string(int(colorFormat)) + ":" + std::to_string(int(depthFormat));
}

}  // namespace qp
