// The persistent plan cache: the configuration database the editor and the Python module keep
// across runs (Brainerd et al. 2016 §4.3: plans are keyed by configuration, not by mesh, so a
// cage opened before, or any cage with the same configurations, plans from it).
//
// Where: $QUADPLAN_PLAN_CACHE names the file ("off" or empty: no cache), else
// $XDG_CACHE_HOME/quadplan/plans.qpdb, else $HOME/.cache/quadplan/plans.qpdb. Bounded by
// $QUADPLAN_PLAN_CACHE_MB megabytes of plans (default 256): the plans used longest ago (by
// session) are dropped first. The file is PlanDatabase's (versioned, checksummed, written
// atomically); a damaged or stale one is reported once and replaced at the next store, and a
// cache that cannot be read or written never stops the product.
//
// How: a document's own PlanDatabase takes the process's cache as its fallback
// (PlanDatabase::setFallback), so it copies the plans it needs instead of building them and
// holds only those; what it built is stored back (merged with the file, then trimmed).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "mesh/result.h"
#include "plans/plan_database.h"

namespace qp {

struct PlanCacheLocation {
    std::string path;
    uint64_t maxBytes = 256ull << 20;
};
// Read from the environment each call; nothing when the cache is off or no directory is named.
std::optional<PlanCacheLocation> planCacheLocation();

// The process's cache, loaded from the file on first use (thread-safe); nullptr when the cache
// is off. A file that could not be used leaves an empty cache and its reason in `warning`
// (once per process; empty otherwise).
std::shared_ptr<const PlanDatabase> sharedPlanCache(std::string* warning = nullptr);

// Adds the plans `database` built (and the cache's that it used) to the process's cache and
// writes the file: merged with what the file holds now (another process may have written it),
// trimmed to the bound, atomically. Success without doing anything when the cache is off.
Status storeInPlanCache(const PlanDatabase& database);

}  // namespace qp
