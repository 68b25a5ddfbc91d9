#include "scheme_loader.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>

#include <dlfcn.h>

#include "scheme_support.h"

namespace qp {

namespace fs = std::filesystem;

namespace {

// Runs `call`, turning an exception into an Error that names the scheme and the step.
template <class F>
auto guarded(const std::string& scheme, const char* step, F&& call) -> decltype(call()) {
    try {
        return call();
    } catch (const std::exception& e) {
        return Error{"scheme '" + scheme + "' threw during " + step + ": " + e.what()};
    } catch (...) {
        return Error{"scheme '" + scheme + "' threw an unknown exception during " + step};
    }
}

bool validName(const char* name) {
    if (!name || !name[0] || std::strlen(name) > 64) return false;
    for (const char* c = name; *c; ++c)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-')) return false;
    return true;
}

std::string executableDirectory() {
    std::error_code error;
    fs::path exe = fs::read_symlink("/proc/self/exe", error);
    return error ? std::string(".") : exe.parent_path().string();
}

}  // namespace

SchemePlugin::~SchemePlugin() {
    if (handle) dlclose(handle);
}

std::shared_ptr<SchemePlugin> PluginCatalog::find(const std::string& name) const {
    for (const auto& p : plugins)
        if (p->name == name) return p;
    return nullptr;
}

std::string PluginCatalog::names() const {
    std::string text;
    for (const auto& p : plugins) text += (text.empty() ? "" : ", ") + p->name;
    return text.empty() ? "none" : text;
}

std::string pluginDirectory(const std::string& flag) {
    if (!flag.empty()) return flag;
    if (const char* env = std::getenv(kPluginDirEnv); env && env[0]) return env;
    return (fs::path(executableDirectory()).parent_path() / "plugins").string();
}

Result<std::shared_ptr<SchemePlugin>> loadPlugin(const std::string& path) {
    // RTLD_NOW: an unresolved symbol fails here, with the linker's message, not mid-draw.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = dlerror();
        return Error{"cannot load scheme plugin " + path + ": " + (why ? why : "dlopen failed")};
    }
    auto plugin = std::make_shared<SchemePlugin>();
    plugin->path = path;
    plugin->handle = handle;
    dlerror();
    auto entry = reinterpret_cast<SchemeEntryFunction>(dlsym(handle, QUADPLAN_SCHEME_ENTRY));
    if (!entry)
        return Error{"scheme plugin " + path + " has no entry point '" QUADPLAN_SCHEME_ENTRY
                     "': it is not a Quadplan scheme (plugins/README.md shows how to export one)"};
    const SchemeModule* module = entry();
    if (!module) return Error{"scheme plugin " + path + " returned no module description"};
    if (module->apiVersion != kSchemeApiVersion)
        return Error{"scheme plugin " + path + " was built for plugin interface version " +
                     std::to_string(module->apiVersion) + ", this quadplan uses version " +
                     std::to_string(kSchemeApiVersion) + ": rebuild the plugin against this quadplan"};
    if (!module->abiTag || std::strcmp(module->abiTag, QUADPLAN_SCHEME_ABI_TAG) != 0)
        return Error{"scheme plugin " + path + " was built with another compiler or standard library ('" +
                     std::string(module->abiTag ? module->abiTag : "?") + "', this quadplan: '" +
                     QUADPLAN_SCHEME_ABI_TAG + "'): rebuild the plugin with this quadplan"};
    if (module->layoutFingerprint != kSchemeLayoutFingerprint)
        return Error{"scheme plugin " + path +
                     " was built against other versions of the core or renderer headers: rebuild the plugin "
                     "with this quadplan"};
    if (!validName(module->name))
        return Error{"scheme plugin " + path + " has an invalid scheme name (use lower case letters, digits and '-')"};
    if (!module->create) return Error{"scheme plugin " + path + " has no create function"};
    plugin->module = module;
    plugin->name = module->name;
    plugin->summary = module->summary ? module->summary : "";
    return plugin;
}

PluginCatalog loadPlugins(const std::string& directory) {
    PluginCatalog catalog;
    catalog.directory = directory;
    std::error_code error;
    if (!fs::is_directory(directory, error)) {
        catalog.problems.push_back({directory, "the scheme plugin directory " + directory +
                                                   " does not exist; build the plugins or point --plugin-dir or " +
                                                   kPluginDirEnv + " at them"});
        return catalog;
    }
    std::vector<fs::path> candidates;
    for (const auto& entry : fs::directory_iterator(directory, error)) {
        const std::string file = entry.path().filename().string();
        if (file.rfind(kPluginPrefix, 0) == 0 && entry.path().extension() == ".so") candidates.push_back(entry.path());
    }
    std::sort(candidates.begin(), candidates.end());
    for (const fs::path& path : candidates) {
        Result<std::shared_ptr<SchemePlugin>> plugin = loadPlugin(path.string());
        if (!plugin) {
            catalog.problems.push_back({path.string(), plugin.error().message});
        } else if (auto existing = catalog.find((*plugin)->name)) {
            catalog.problems.push_back({path.string(), "scheme plugin " + path.string() + " names itself '" +
                                                           (*plugin)->name + "', which " + existing->path +
                                                           " already provides; it was not loaded"});
        } else {
            catalog.plugins.push_back(std::move(*plugin));
        }
    }
    std::sort(catalog.plugins.begin(), catalog.plugins.end(), [](const auto& a, const auto& b) { return a->name < b->name; });
    return catalog;
}

Result<SchemeInstance> SchemeInstance::create(const std::shared_ptr<SchemePlugin>& plugin) {
    SchemeInstance instance;
    instance.plugin_ = plugin;
    Status created = guarded(plugin->name, "creation", [&]() -> Status {
        instance.scheme_.reset(plugin->module->create());
        if (!instance.scheme_) return Error{"scheme '" + plugin->name + "' (" + plugin->path + ") created no instance"};
        return success();
    });
    if (!created) return created.error();
    return instance;
}

SchemeInstance::~SchemeInstance() {
    // The scheme's destructor is the module's code: run it while the module is loaded.
    if (scheme_) {
        try {
            scheme_.reset();
        } catch (...) {
        }
    }
}

Result<SupportReport> SchemeInstance::support(const CageFeatures& features, const SchemeSettings& settings) const {
    return guarded(name(), "support", [&]() -> Result<SupportReport> { return scheme_->support(features, settings); });
}

Status SchemeInstance::build(const PlannedCage& planned, const SchemeSettings& settings) {
    return guarded(name(), "build", [&]() -> Status { return scheme_->build(planned, settings); });
}

Status SchemeInstance::createGpu(const GpuContext& gpu) {
    gpuCreated_ = true;  // even a failed createGpu may have made objects: destroyGpu cleans up
    return guarded(name(), "GPU setup", [&]() -> Status { return scheme_->createGpu(gpu); });
}

Status SchemeInstance::update() {
    return guarded(name(), "update", [&]() -> Status { return scheme_->update(); });
}

Status SchemeInstance::setDisplacement(const Displacement* displacement) {
    return guarded(name(), "displacement", [&]() -> Status { return scheme_->setDisplacement(displacement); });
}

Status SchemeInstance::displacementChanged(std::span<const uint32_t> samples) {
    return guarded(name(), "displacement update", [&]() -> Status { return scheme_->displacementChanged(samples); });
}

Status SchemeInstance::updateMoved(std::span<const uint32_t> vertices) {
    return guarded(name(), "update", [&]() -> Status { return scheme_->updateMoved(vertices); });
}

Result<PlanUpdate> SchemeInstance::updatePlans(const PlanChange& change) {
    return guarded(name(), "plan update", [&]() -> Result<PlanUpdate> { return scheme_->updatePlans(change); });
}

bool SchemeInstance::updatesPlansInPlace() const {
    try {
        return scheme_->updatesPlansInPlace();
    } catch (...) {
        return false;
    }
}

bool SchemeInstance::updatesTopologyInPlace() const {
    try {
        return scheme_->updatesTopologyInPlace();
    } catch (...) {
        return false;
    }
}

bool SchemeInstance::hidesSubfaces() const {
    try {
        return scheme_->hidesSubfaces();
    } catch (...) {
        return false;
    }
}

Result<DrawStats> SchemeInstance::record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) {
    return guarded(name(), "recording", [&]() -> Result<DrawStats> { return scheme_->record(cmd, target, view); });
}

Status SchemeInstance::evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const {
    return guarded(name(), "evaluation", [&]() -> Status {
        evaluateParallel(*scheme_, requests, out);
        return success();
    });
}

Result<SchemeStats> SchemeInstance::stats() const {
    return guarded(name(), "statistics", [&]() -> Result<SchemeStats> { return scheme_->stats(); });
}

Result<PatchTriangles> SchemeInstance::drawnPatches() const {
    return guarded(name(), "drawnPatches", [&]() -> Result<PatchTriangles> { return scheme_->drawnPatches(); });
}

Result<std::vector<std::string>> SchemeInstance::colorModes() const {
    return guarded(name(), "colorModes", [&]() -> Result<std::vector<std::string>> { return scheme_->colorModes(); });
}

Status SchemeInstance::destroyGpu() {
    if (!gpuCreated_) return success();
    gpuCreated_ = false;
    return guarded(name(), "GPU teardown", [&]() -> Status {
        scheme_->destroyGpu();
        return success();
    });
}

}  // namespace qp
