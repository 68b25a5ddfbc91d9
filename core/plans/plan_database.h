// PlanDatabase: plans shared by every face with the same configuration (B16 §4.4).
//
// Keys are FaceConfig keys; lookup is by hash, then by whole-key comparison, so two different
// configurations never share a plan. The database persists to a versioned binary file with a
// checksum; a missing, corrupt or stale file is reported as a warning and the database starts
// empty (plans are rebuilt as faces ask for them), never a crash.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "mesh/result.h"
#include "plans/face_config.h"
#include "plans/plan.h"

namespace qp {

struct PlanDatabaseStats {
    uint32_t plans = 0;  // held (released ones not counted)
    std::array<uint64_t, kNodeKindCount> nodesByKind{};
    uint64_t stencils = 0;
    uint64_t bytes = 0;  // plans (nodes, points, stencil weights) and keys
    uint64_t hits = 0, misses = 0;
    uint64_t fromFallback = 0;  // lookups answered by copying the fallback's plan (no build)
};

// The checksum a plan database file ends with (XXH3, 64 bits, of everything before it). Public
// so tools that forge files on purpose (the fuzzer) can reach the parser behind it.
uint64_t planDatabaseChecksum(const char* data, size_t size);

class PlanDatabase {
public:
    // Plan id for the configuration, building the plan on a miss (or copying the fallback's,
    // when it has one). Thread-safe.
    Result<uint32_t> findOrBuild(const FaceConfig& config);
    // Plans this database lacks are copied from `fallback` before any is built: the persistent
    // cache (plan_cache.h) sits behind a document's own database this way, so the document
    // holds only the plans its cage uses. Not while other threads plan with this database.
    void setFallback(std::shared_ptr<const PlanDatabase> fallback);
    // Plan id, or UINT32_MAX when the configuration has no plan yet. Thread-safe.
    uint32_t find(const FaceConfig& config) const;

    const Plan& plan(uint32_t id) const { return plans_[id]; }
    // One past the largest id (released ids included): the range of plan(id).
    uint32_t size() const { return uint32_t(plans_.size()); }
    // Frees the plans whose entry in `inUse` is false (ids past its end count as in use): their
    // memory goes and their configurations are forgotten, so a face that needs one again gets a
    // new plan under a new id. Ids are never reused: an id held elsewhere names either its plan
    // or an empty one that nothing draws. Without this the database keeps every configuration a
    // long editing session ever made (the soak test, tests/scenes/soak.py). Not while other
    // threads plan with this database. Returns the number of plans released.
    uint32_t releaseUnused(const std::vector<bool>& inUse);
    PlanDatabaseStats stats() const;  // walks every plan: not for hot paths
    uint64_t misses() const;

    // Writes the held plans, each with the session it was last used in (least recently used
    // first to go: beyond `maxBytes` of plans and keys the oldest are left out).
    Status save(const std::string& path, uint64_t maxBytes = std::numeric_limits<uint64_t>::max()) const;
    // A copy of `older`'s plans that this database lacks added to this one's (their ids after
    // this one's), for a cache that outlives the documents using it. Sessions stay ordered:
    // this database's plans count as used after all of `older`'s.
    void mergeFrom(const PlanDatabase& older);
    // Replaces the contents with the file's. On failure the database is left empty and the
    // error says why (the caller reports it as a warning and carries on).
    Status load(const std::string& path);
    // load() on bytes already read; `source` names them in the message.
    Status loadFromBytes(std::string_view bytes, const std::string& source);

private:
    uint32_t findLocked(const FaceConfig& config) const;
    uint32_t insertLocked(std::vector<uint32_t> key, uint64_t hash, Plan plan, uint32_t session);

    mutable std::shared_mutex mutex_;
    std::unordered_multimap<uint64_t, uint32_t> byHash_;
    std::vector<std::vector<uint32_t>> keys_;
    std::deque<Plan> plans_;  // deque: references stay valid while other threads insert
    // Per plan, the session it was last used in: sessions count up across save and load, and
    // this database's session is one past the newest it loaded.
    std::vector<uint32_t> lastUse_;
    uint32_t session_ = 1;
    std::shared_ptr<const PlanDatabase> fallback_;
    uint64_t hits_ = 0, misses_ = 0, fromFallback_ = 0;
};

}  // namespace qp
