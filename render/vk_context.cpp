#include "vk_context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "shared_pipelines.h"
#include "vk_check.h"

namespace qp {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void* user) {
    const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    const bool warning = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    if (!error && !warning) return VK_FALSE;
    std::string text = std::string(error ? "error: " : "warning: ") + (data->pMessage ? data->pMessage : "");
    std::fprintf(stderr, "[vulkan] %s\n", text.c_str());
    auto* log = static_cast<ValidationLog*>(user);
    std::lock_guard lock(log->mutex);
    (error ? log->errors : log->warnings)++;
    log->messages.push_back(std::move(text));
    return VK_FALSE;  // never abort the call that triggered the message
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(ValidationLog* log) {
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = debugCallback;
    info.pUserData = log;
    return info;
}

bool hasLayer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* layer, const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceExtensionProperties(layer, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateInstanceExtensionProperties(layer, &count, extensions.data());
    return std::any_of(extensions.begin(), extensions.end(),
                       [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

// VkPhysicalDeviceFeatures is a plain array of VkBool32.
constexpr size_t kFeatureCount = sizeof(VkPhysicalDeviceFeatures) / sizeof(VkBool32);
const VkBool32* featureArray(const VkPhysicalDeviceFeatures& f) { return reinterpret_cast<const VkBool32*>(&f); }
VkBool32* featureArray(VkPhysicalDeviceFeatures& f) { return reinterpret_cast<VkBool32*>(&f); }

// The features the renderer uses when the device has them.
VkPhysicalDeviceFeatures optionalFeatures(const VkPhysicalDeviceFeatures& supported) {
    VkPhysicalDeviceFeatures f{};
    f.tessellationShader = supported.tessellationShader;
    f.geometryShader = supported.geometryShader;
    f.fillModeNonSolid = supported.fillModeNonSolid;
    f.wideLines = supported.wideLines;
    f.pipelineStatisticsQuery = supported.pipelineStatisticsQuery;
    f.vertexPipelineStoresAndAtomics = supported.vertexPipelineStoresAndAtomics;
    f.shaderFloat64 = supported.shaderFloat64;
    return f;
}

struct Candidate {
    VkPhysicalDevice device = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceFeatures features{};
    uint32_t queueFamily = 0;
    VkDeviceSize maxBufferBytes = 0;
    int score = -1;
};

int typeScore(VkPhysicalDeviceType type, bool preferSoftware) {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return preferSoftware ? 5 : 1;
    default: return 0;
    }
}

// Fills a candidate, or returns why the device cannot be used.
std::string examine(VkPhysicalDevice device, const ContextOptions& options, Candidate& c) {
    c.device = device;
    vkGetPhysicalDeviceProperties(device, &c.properties);
    const std::string name = c.properties.deviceName;
    if (!options.forceDevice.empty() && name.find(options.forceDevice) == std::string::npos)
        return "its name does not contain '" + options.forceDevice + "'";
    if (c.properties.apiVersion < VK_API_VERSION_1_3) return "it does not support Vulkan 1.3";

    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &features13};
    VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};
    vkGetPhysicalDeviceFeatures2(device, &features2);
    c.features = features2.features;
    if (!features13.dynamicRendering || !features13.synchronization2 || !features13.maintenance4)
        return "it lacks dynamic rendering, synchronization2 or maintenance4";
    if (!features12.bufferDeviceAddress || !c.features.shaderInt64)
        return "it lacks bufferDeviceAddress or shaderInt64 (the plan shaders reach their buffers by address)";
    VkPhysicalDeviceMaintenance4Properties maintenance4{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
    VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES,
                                                        &maintenance4};
    VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &maintenance3};
    vkGetPhysicalDeviceProperties2(device, &properties2);
    c.maxBufferBytes = std::min(maintenance4.maxBufferSize, maintenance3.maxMemoryAllocationSize);
    for (size_t i = 0; i < kFeatureCount; ++i)
        if (featureArray(options.requiredFeatures)[i] && !featureArray(c.features)[i])
            return "it lacks a required feature (VkPhysicalDeviceFeatures member " + std::to_string(i) + ")";

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, families.data());
    const VkQueueFlags wanted = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    auto family = std::find_if(families.begin(), families.end(),
                               [&](const auto& f) { return (f.queueFlags & wanted) == wanted && f.queueCount > 0; });
    if (family == families.end()) return "it has no graphics + compute queue";
    c.queueFamily = uint32_t(family - families.begin());
    c.score = typeScore(c.properties.deviceType, options.preferSoftware);
    return {};
}

Status createInstance(VulkanContext& ctx, const ContextOptions& options) {
    uint32_t loaderVersion = 0;
    if (vkEnumerateInstanceVersion(&loaderVersion) != VK_SUCCESS || loaderVersion < VK_API_VERSION_1_3)
        return Error{"the Vulkan loader does not support Vulkan 1.3 (install libvulkan1 >= 1.3)"};

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    for (const std::string& e : options.instanceExtensions) extensions.push_back(e.c_str());
    bool syncValidation = false;
    if (options.validation) {
        if (!hasLayer(kValidationLayer))
            return Error{"validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                         "(Debian package vulkan-validationlayers)"};
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        syncValidation = hasInstanceExtension(kValidationLayer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        if (syncValidation) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    }

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "quadplan";
    app.pEngineName = "quadplan";
    app.apiVersion = VK_API_VERSION_1_3;

    // Chained into the instance so that vkCreateInstance and vkDestroyInstance are covered too.
    VkDebugUtilsMessengerCreateInfoEXT messenger = messengerInfo(ctx.validation.get());
    const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT validationFeatures{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    validationFeatures.enabledValidationFeatureCount = 1;
    validationFeatures.pEnabledValidationFeatures = enables;
    if (syncValidation) messenger.pNext = &validationFeatures;

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = options.validation ? &messenger : nullptr;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    const VkResult result = vkCreateInstance(&info, nullptr, &ctx.instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        return Error{"no Vulkan driver was found (for the CPU renderer install mesa-vulkan-drivers; "
                     "VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json selects lavapipe)"};
    VK_CHECK(result);

    if (options.validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) return Error{"VK_EXT_debug_utils is enabled but vkCreateDebugUtilsMessengerEXT is missing"};
        VkDebugUtilsMessengerCreateInfoEXT persistent = messengerInfo(ctx.validation.get());
        VK_CHECK(create(ctx.instance, &persistent, nullptr, &ctx.debugMessenger));
    }
    return success();
}

Status pickPhysicalDevice(VulkanContext& ctx, const ContextOptions& options, Candidate& best) {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(ctx.instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(ctx.instance, &count, devices.data()));
    if (devices.empty())
        return Error{"no Vulkan device was found (for the CPU renderer install mesa-vulkan-drivers)"};

    std::string rejected;
    for (VkPhysicalDevice device : devices) {
        Candidate c;
        std::string why = examine(device, options, c);
        if (!why.empty()) {
            rejected += std::string(rejected.empty() ? "" : "; ") + c.properties.deviceName + ": " + why;
            continue;
        }
        if (c.score > best.score) best = c;
    }
    if (best.score < 0) return Error{"no usable Vulkan device: " + rejected};
    return success();
}

// A CPU implementation allocates and frees working memory every frame (lavapipe: thousands of
// small blocks). glibc's malloc returns freed memory at the top of the heap to the system and
// then page-faults it back in on the next frame: 300-6,000 minor faults a frame measured on
// catmark_car, and large draws 2-4x slower, depending on what the process freed before (the
// dynamic mmap threshold). Keeping up to 512 MiB of freed memory makes it 0 faults.
void keepFreedMemory() {
#ifdef __GLIBC__
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

Status createDevice(VulkanContext& ctx, const ContextOptions& options, const Candidate& chosen) {
    ctx.physicalDevice = chosen.device;
    ctx.properties = chosen.properties;
    ctx.deviceName = chosen.properties.deviceName;
    ctx.isSoftware = chosen.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    if (ctx.isSoftware) keepFreedMemory();
    ctx.queueFamily = chosen.queueFamily;
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice, &ctx.memoryProperties);

    ctx.features = optionalFeatures(chosen.features);
    for (size_t i = 0; i < kFeatureCount; ++i)
        featureArray(ctx.features)[i] |= featureArray(options.requiredFeatures)[i];

    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.dynamicRendering = VK_TRUE;
    features13.synchronization2 = VK_TRUE;
    // SPIR-V 1.6 compute shaders (glslc --target-env=vulkan1.3) declare LocalSizeId.
    features13.maintenance4 = VK_TRUE;
    // Buffers larger than maxStorageBufferRange (a million-face cage's control points and grid)
    // are read by address in the plan shaders.
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &features13};
    features12.bufferDeviceAddress = VK_TRUE;
    ctx.features.shaderInt64 = VK_TRUE;
    ctx.maxBufferBytes = chosen.maxBufferBytes;
    VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};
    features2.features = ctx.features;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = ctx.queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    std::vector<const char*> extensions;
    for (const std::string& e : options.deviceExtensions) extensions.push_back(e.c_str());

    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features2};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queueInfo;
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VK_CHECK(vkCreateDevice(ctx.physicalDevice, &info, nullptr, &ctx.device));
    vkGetDeviceQueue(ctx.device, ctx.queueFamily, 0, &ctx.queue);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = ctx.queueFamily;
    VK_CHECK(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &ctx.commandPool));
    return success();
}

Status initContext(VulkanContext& ctx, const ContextOptions& options) {
    if (Status s = createInstance(ctx, options); !s) return s;
    Candidate chosen;
    if (Status s = pickPhysicalDevice(ctx, options, chosen); !s) return s;
    return createDevice(ctx, options, chosen);
}

bool validationForcedByEnvironment() {
    const char* value = std::getenv("QUADPLAN_VALIDATE");
    return value && value[0] && std::strcmp(value, "0") != 0;
}

}  // namespace

Result<VulkanContext> createContext(const ContextOptions& requested) {
    VulkanContext ctx;
    ctx.validation = std::make_unique<ValidationLog>();
    ContextOptions options = requested;
    if (!options.validation && validationForcedByEnvironment()) {
        options.validation = true;
        ctx.validation->fatal = true;
    }
    if (Status s = initContext(ctx, options); !s) {
        ctx.validation->fatal = false;  // the failure is the error to report, with its own message
        destroyContext(ctx);
        return Error{"cannot initialise Vulkan: " + s.error().message};
    }
    return ctx;
}

void destroyContext(VulkanContext& ctx) {
    if (ctx.device) {
        vkDeviceWaitIdle(ctx.device);
        releaseSharedObjects(ctx);
        if (ctx.commandPool) vkDestroyCommandPool(ctx.device, ctx.commandPool, nullptr);
        vkDestroyDevice(ctx.device, nullptr);
    }
    if (ctx.debugMessenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx.instance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(ctx.instance, ctx.debugMessenger, nullptr);
    }
    if (ctx.instance) vkDestroyInstance(ctx.instance, nullptr);
    ctx.commandPool = VK_NULL_HANDLE;
    ctx.device = VK_NULL_HANDLE;
    ctx.queue = VK_NULL_HANDLE;
    ctx.debugMessenger = VK_NULL_HANDLE;
    ctx.physicalDevice = VK_NULL_HANDLE;
    ctx.instance = VK_NULL_HANDLE;
    if (const uint32_t count = validationMessageCount(ctx); count > 0 && ctx.validation->fatal) {
        std::fprintf(stderr, "quadplan: %u Vulkan validation message(s) with QUADPLAN_VALIDATE set\n", count);
        std::fflush(nullptr);
        std::_Exit(4);
    }
}

uint32_t validationMessageCount(const VulkanContext& ctx) {
    if (!ctx.validation) return 0;
    std::lock_guard lock(ctx.validation->mutex);
    return ctx.validation->warnings + ctx.validation->errors;
}

std::vector<std::string> validationMessages(const VulkanContext& ctx) {
    if (!ctx.validation) return {};
    std::lock_guard lock(ctx.validation->mutex);
    return ctx.validation->messages;
}

}  // namespace qp
