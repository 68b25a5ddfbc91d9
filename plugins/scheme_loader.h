// The host side of the plugin interface: finds scheme modules in a directory, loads them with
// dlopen, checks their interface version, and wraps every call into a scheme so that an
// error or an exception becomes a message naming the scheme, never a crash of the host.
//
// Plugin directory: the --plugin-dir flag of a command, else $QUADPLAN_PLUGIN_DIR, else
// <directory of the executable>/../plugins (build/plugins for build/bin/quadplan). Every file
// named quadplan-scheme-*.so there is a candidate; anything else is ignored.
// A module that cannot be used (dlopen fails, no entry symbol, another interface version or
// build, a name already taken) becomes a PluginProblem with a message; the others load.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scheme_api.h"

namespace qp {

inline constexpr const char* kPluginDirEnv = "QUADPLAN_PLUGIN_DIR";
inline constexpr const char* kPluginPrefix = "quadplan-scheme-";

struct SchemePlugin {
    std::string path;
    std::string name, summary;
    void* handle = nullptr;
    const SchemeModule* module = nullptr;

    SchemePlugin() = default;
    SchemePlugin(const SchemePlugin&) = delete;
    SchemePlugin& operator=(const SchemePlugin&) = delete;
    ~SchemePlugin();  // dlclose; instances keep their plugin alive through shared_ptr
};

struct PluginProblem {
    std::string path;
    std::string message;  // complete sentence naming the file
};

struct PluginCatalog {
    std::string directory;
    std::vector<std::shared_ptr<SchemePlugin>> plugins;  // sorted by name
    std::vector<PluginProblem> problems;

    std::shared_ptr<SchemePlugin> find(const std::string& name) const;
    std::string names() const;  // "osd-fas, plans, uniform" (or "none")
};

// `flag` when not empty, else $QUADPLAN_PLUGIN_DIR when set and not empty, else the default.
std::string pluginDirectory(const std::string& flag = "");

// Loads every candidate module in `directory` (a missing directory is one problem).
PluginCatalog loadPlugins(const std::string& directory);

// Loads one module file.
Result<std::shared_ptr<SchemePlugin>> loadPlugin(const std::string& path);

// One scheme instance behind guards: every call catches exceptions and reports them as
// "scheme 'NAME' threw during build: what()". Destroy the GPU part (destroyGpu) before the
// Vulkan context goes away; the instance keeps its module loaded until it is destroyed.
class SchemeInstance {
public:
    static Result<SchemeInstance> create(const std::shared_ptr<SchemePlugin>& plugin);
    SchemeInstance(SchemeInstance&&) noexcept = default;
    SchemeInstance& operator=(SchemeInstance&&) noexcept = default;
    ~SchemeInstance();

    const std::string& name() const { return plugin_->name; }
    const Scheme& scheme() const { return *scheme_; }

    Result<SupportReport> support(const CageFeatures& features, const SchemeSettings& settings) const;
    Status build(const PlannedCage& planned, const SchemeSettings& settings);
    Status createGpu(const GpuContext& gpu);
    Status update();
    Status setDisplacement(const Displacement* displacement);
    Status displacementChanged(std::span<const uint32_t> samples);
    Status updateMoved(std::span<const uint32_t> vertices);  // Scheme::updateMoved
    Result<PlanUpdate> updatePlans(const PlanChange& change);  // Scheme::updatePlans
    bool updatesPlansInPlace() const;
    bool updatesTopologyInPlace() const;
    bool hidesSubfaces() const;
    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view);
    // All requests, in parallel (scheme_support.h: evaluateParallel).
    Status evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const;
    Result<SchemeStats> stats() const;
    Result<PatchTriangles> drawnPatches() const;  // Scheme::drawnPatches
    Result<std::vector<std::string>> colorModes() const;
    Status destroyGpu();  // does nothing when no GPU part exists

private:
    SchemeInstance() = default;
    // Declared first, destroyed last: the scheme's code lives in the plugin's module.
    std::shared_ptr<SchemePlugin> plugin_;
    std::unique_ptr<Scheme> scheme_;
    bool gpuCreated_ = false;
};

}  // namespace qp
