#include "plans/plan_cache.h"

#include <cstdlib>
#include <filesystem>
#include <mutex>

namespace qp {

namespace {

std::mutex cacheMutex;
std::shared_ptr<const PlanDatabase> cache;  // guarded by cacheMutex
std::string cachePath;                      // the file `cache` was loaded from
std::string warnedPath;                     // a bad file is reported once

std::string environment(const char* name) {
    const char* value = std::getenv(name);
    return value ? value : "";
}

// A database with the file's plans; a missing file is an empty cache, a bad one too, with why.
std::shared_ptr<PlanDatabase> loadCacheFile(const std::string& path, std::string* why) {
    auto database = std::make_shared<PlanDatabase>();
    std::error_code error;
    if (!std::filesystem::exists(path, error)) return database;
    if (Status loaded = database->load(path); !loaded && why) *why = loaded.error().message;
    return database;
}

}  // namespace

std::optional<PlanCacheLocation> planCacheLocation() {
    PlanCacheLocation location;
    if (const char* named = std::getenv("QUADPLAN_PLAN_CACHE")) {
        const std::string path = named;
        if (path.empty() || path == "off") return std::nullopt;
        location.path = path;
    } else if (const std::string xdg = environment("XDG_CACHE_HOME"); !xdg.empty()) {
        location.path = (std::filesystem::path(xdg) / "quadplan" / "plans.qpdb").string();
    } else if (const std::string home = environment("HOME"); !home.empty()) {
        location.path = (std::filesystem::path(home) / ".cache" / "quadplan" / "plans.qpdb").string();
    } else {
        return std::nullopt;
    }
    if (const std::string megabytes = environment("QUADPLAN_PLAN_CACHE_MB"); !megabytes.empty()) {
        char* end = nullptr;
        const unsigned long long value = std::strtoull(megabytes.c_str(), &end, 10);
        if (end && *end == '\0') location.maxBytes = uint64_t(value) << 20;
    }
    return location;
}

std::shared_ptr<const PlanDatabase> sharedPlanCache(std::string* warning) {
    const std::optional<PlanCacheLocation> location = planCacheLocation();
    if (!location) return nullptr;
    std::lock_guard<std::mutex> lock(cacheMutex);
    if (!cache || cachePath != location->path) {
        std::string why;
        cache = loadCacheFile(location->path, &why);
        cachePath = location->path;
        if (!why.empty() && warning && warnedPath != location->path) {
            *warning = "the plan cache: " + why;
            warnedPath = location->path;
        }
    }
    return cache;
}

Status storeInPlanCache(const PlanDatabase& database) {
    const std::optional<PlanCacheLocation> location = planCacheLocation();
    if (!location) return success();
    std::lock_guard<std::mutex> lock(cacheMutex);
    auto merged = std::make_shared<PlanDatabase>();
    merged->mergeFrom(database);
    // What the file holds now (another process may have added to it since this one read it),
    // then what this process knew: both older than the document's own plans.
    std::string ignored;
    merged->mergeFrom(*loadCacheFile(location->path, &ignored));
    if (cache && cachePath == location->path) merged->mergeFrom(*cache);
    std::error_code error;
    std::filesystem::create_directories(std::filesystem::path(location->path).parent_path(), error);
    if (Status saved = merged->save(location->path, location->maxBytes); !saved)
        return Error{"could not store the plan cache: " + saved.error().message};
    cache = std::move(merged);
    cachePath = location->path;
    return success();
}

}  // namespace qp
