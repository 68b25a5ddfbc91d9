#include "plans/plan_database.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>

// Header-only: the hash compiled in, no library to link.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include "mesh/file_io.h"
#include "plans/plan_builder.h"

namespace qp {

namespace {

constexpr char kMagic[8] = {'Q', 'P', 'P', 'L', 'A', 'N', 'D', 'B'};
// Bump when the plan layout or the builder's output changes: older files are then stale.
// 2: exact tangent planes at darts (tangent_plane.h); 3: each plan's last session and its
// corner tangents; 4: the checksum is XXH3 (byte-wise FNV-1a took 1.5 s of a 546 MiB file's 2.3 s load).
constexpr uint32_t kFileVersion = 4;

void putWords(std::string& out, const uint32_t* words, size_t count) {
    out.append(reinterpret_cast<const char*>(words), count * sizeof(uint32_t));
}
void putWord(std::string& out, uint32_t word) { putWords(out, &word, 1); }

template <class T>
void putArray(std::string& out, const std::vector<T>& values) {
    static_assert(sizeof(T) % sizeof(uint32_t) == 0);
    putWord(out, uint32_t(values.size()));
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// Bounds-checked reader over the file contents.
struct Reader {
    const char* data;
    size_t size, at = 0;
    bool ok = true;

    uint32_t word() {
        uint32_t w = 0;
        if (at + 4 > size) { ok = false; return 0; }
        std::memcpy(&w, data + at, 4);
        at += 4;
        return w;
    }
    template <class T>
    void array(std::vector<T>& values, size_t maxCount) {
        uint32_t count = word();
        if (!ok || count > maxCount || at + size_t(count) * sizeof(T) > size) { ok = false; return; }
        values.resize(count);
        if (count > 0) std::memcpy(values.data(), data + at, count * sizeof(T));  // data() may be null
        at += count * sizeof(T);
    }
};

// A plan read from disk must be safe to evaluate: every index in range.
bool planIsConsistent(const Plan& plan) {
    if (plan.nodes.empty()) return plan.points.empty() && plan.stencilWeights.empty();
    if (plan.ringSize == 0 || plan.maxDepth > kMaxPlanDepth) return false;
    if (plan.stencilWeights.size() % plan.ringSize != 0) return false;
    for (float w : plan.stencilWeights)
        if (!std::isfinite(w)) return false;
    uint32_t stencils = plan.stencilCount();
    for (uint32_t p : plan.points)
        if (p >= stencils) return false;
    // The corner tangents are the first rows, in every level's prefix.
    if (plan.cornerTangents > 0xfu || 2u * uint32_t(std::popcount(plan.cornerTangents)) > plan.stencilCountByLevel[0])
        return false;
    for (uint32_t n = 0; n <= kMaxPlanDepth; ++n)
        if (plan.stencilCountByLevel[n] > stencils || (n > 0 && plan.stencilCountByLevel[n] < plan.stencilCountByLevel[n - 1]))
            return false;
    for (size_t i = 0; i < plan.nodes.size(); ++i) {
        const PlanNode& node = plan.nodes[i];
        size_t needed = 0;
        switch (node.kind) {
        case NodeKind::Internal:
            if (node.first <= i || node.first + 4 > plan.nodes.size()) return false;
            continue;
        case NodeKind::Regular: needed = 16; break;
        case NodeKind::Crease:
            if (!(node.sharpness > 0.0f && node.sharpness <= kInfiniteSharpness) || node.edge > 3) return false;
            needed = 16;
            break;
        case NodeKind::Terminal:
            if (node.edge > 3) return false;
            needed = size_t(kTerminalPointsPerLevel) * node.levels + kGregoryPoints; break;
        case NodeKind::Extraordinary: needed = kGregoryPoints; break;
        default: return false;
        }
        if (size_t(node.first) + needed > plan.points.size()) return false;
    }
    return true;
}

}  // namespace

uint64_t planDatabaseChecksum(const char* data, size_t size) { return XXH3_64bits(data, size); }

uint32_t PlanDatabase::findLocked(const FaceConfig& config) const {
    auto [begin, end] = byHash_.equal_range(config.hash);
    for (auto it = begin; it != end; ++it)
        if (keys_[it->second] == config.key) return it->second;
    return UINT32_MAX;
}

uint32_t PlanDatabase::find(const FaceConfig& config) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return findLocked(config);
}

uint32_t PlanDatabase::insertLocked(std::vector<uint32_t> key, uint64_t hash, Plan plan, uint32_t session) {
    const uint32_t id = uint32_t(plans_.size());
    plans_.push_back(std::move(plan));
    keys_.push_back(std::move(key));
    lastUse_.push_back(session);
    byHash_.emplace(hash, id);
    return id;
}

void PlanDatabase::setFallback(std::shared_ptr<const PlanDatabase> fallback) {
    std::lock_guard<std::mutex> lock(mutex_);
    fallback_ = std::move(fallback);
}

Result<uint32_t> PlanDatabase::findOrBuild(const FaceConfig& config) {
    std::shared_ptr<const PlanDatabase> fallback;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        uint32_t id = findLocked(config);
        if (id != UINT32_MAX) {
            ++hits_;
            lastUse_[id] = session_;
            return id;
        }
        fallback = fallback_;
    }
    if (fallback) {
        std::optional<Plan> cached;
        {
            std::lock_guard<std::mutex> lock(fallback->mutex_);
            if (const uint32_t at = fallback->findLocked(config); at != UINT32_MAX) cached = fallback->plans_[at];
        }
        if (cached) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (uint32_t id = findLocked(config); id != UINT32_MAX) return id;
            ++fromFallback_;
            return insertLocked(config.key, config.hash, std::move(*cached), session_);
        }
    }
    // Build outside the lock so several threads can build different plans at once.
    Result<Plan> plan = buildPlan(config.key);
    if (!plan) return plan.error();
    std::lock_guard<std::mutex> lock(mutex_);
    uint32_t id = findLocked(config);  // another thread may have built it meanwhile
    if (id != UINT32_MAX) {
        ++hits_;
        lastUse_[id] = session_;
        return id;
    }
    ++misses_;
    return insertLocked(config.key, config.hash, std::move(plan).value(), session_);
}

void PlanDatabase::mergeFrom(const PlanDatabase& older) {
    std::scoped_lock lock(mutex_, older.mutex_);
    // This database's sessions move past every one of `older`'s, keeping their order.
    uint32_t newest = 0;
    for (uint32_t s : older.lastUse_) newest = std::max(newest, s);
    if (session_ <= newest) {
        const uint32_t shift = newest + 1 - session_;
        for (uint32_t& s : lastUse_) s += shift;
        session_ += shift;
    }
    for (size_t i = 0; i < older.plans_.size(); ++i) {
        if (older.keys_[i].empty()) continue;  // released
        const uint64_t hash = hashKey(older.keys_[i]);
        bool have = false;
        auto [begin, end] = byHash_.equal_range(hash);
        for (auto it = begin; it != end && !have; ++it) have = keys_[it->second] == older.keys_[i];
        if (!have) insertLocked(older.keys_[i], hash, older.plans_[i], older.lastUse_[i]);
    }
}

uint64_t PlanDatabase::misses() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return misses_;
}

PlanDatabaseStats PlanDatabase::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    PlanDatabaseStats s;
    for (size_t i = 0; i < plans_.size(); ++i) {
        if (keys_[i].empty()) continue;  // released
        ++s.plans;
        auto counts = countNodes(plans_[i]);
        for (uint32_t k = 0; k < kNodeKindCount; ++k) s.nodesByKind[k] += counts[k];
        s.stencils += plans_[i].stencilCount();
        s.bytes += plans_[i].byteSize() + keys_[i].size() * sizeof(uint32_t);
    }
    s.hits = hits_;
    s.misses = misses_;
    s.fromFallback = fromFallback_;
    return s;
}

uint32_t PlanDatabase::releaseUnused(const std::vector<bool>& inUse) {
    std::lock_guard<std::mutex> lock(mutex_);
    uint32_t released = 0;
    for (uint32_t id = 0; id < uint32_t(std::min(inUse.size(), plans_.size())); ++id) {
        if (inUse[id] || keys_[id].empty()) continue;
        auto [begin, end] = byHash_.equal_range(hashKey(keys_[id]));
        for (auto it = begin; it != end; ++it)
            if (it->second == id) {
                byHash_.erase(it);
                break;
            }
        keys_[id] = {};  // an empty key marks a released id (real keys have > 5 words)
        plans_[id] = Plan{};
        ++released;
    }
    return released;
}

Status PlanDatabase::save(const std::string& path, uint64_t maxBytes) const {
    std::string out(kMagic, sizeof(kMagic));
    std::lock_guard<std::mutex> lock(mutex_);
    // The most recently used first, until the bound; written in id order.
    std::vector<uint32_t> held;
    for (uint32_t i = 0; i < uint32_t(plans_.size()); ++i)
        if (!keys_[i].empty()) held.push_back(i);  // not released
    std::stable_sort(held.begin(), held.end(), [&](uint32_t a, uint32_t b) { return lastUse_[a] > lastUse_[b]; });
    uint64_t bytes = 0;
    size_t kept = 0;
    for (; kept < held.size(); ++kept) {
        const uint64_t size = plans_[held[kept]].byteSize() + keys_[held[kept]].size() * sizeof(uint32_t);
        if (bytes + size > maxBytes) break;
        bytes += size;
    }
    held.resize(kept);
    std::sort(held.begin(), held.end());
    putWord(out, kFileVersion);
    putWord(out, uint32_t(held.size()));
    for (uint32_t i : held) {
        const Plan& plan = plans_[i];
        putArray(out, keys_[i]);
        putWord(out, plan.ringSize);
        putWord(out, plan.maxDepth);
        putArray(out, plan.nodes);
        putArray(out, plan.points);
        putArray(out, plan.stencilWeights);
        putWords(out, plan.stencilCountByLevel.data(), plan.stencilCountByLevel.size());
        putWord(out, plan.cornerTangents);
        putWord(out, lastUse_[i]);
    }
    uint64_t sum = planDatabaseChecksum(out.data(), out.size());
    out.append(reinterpret_cast<const char*>(&sum), sizeof(sum));
    return writeFileAtomically(path, out);
}

Status PlanDatabase::load(const std::string& path) {
    Result<std::string> file = readFile(path);
    if (!file) {
        std::lock_guard<std::mutex> lock(mutex_);
        byHash_.clear();
        keys_.clear();
        plans_.clear();
        lastUse_.clear();
        return file.error();
    }
    return loadFromBytes(*file, path);
}

Status PlanDatabase::loadFromBytes(const std::string& bytes, const std::string& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    byHash_.clear();
    keys_.clear();
    plans_.clear();
    lastUse_.clear();
    session_ = 1;

    auto corrupt = [&](const std::string& why) {
        byHash_.clear();
        keys_.clear();
        plans_.clear();
        lastUse_.clear();
        return Error{"plan database '" + path + "' " + why + "; plans will be rebuilt"};
    };
    if (bytes.size() < sizeof(kMagic) + 8 + sizeof(uint64_t) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
        return corrupt("is not a Quadplan plan database");
    uint64_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - sizeof(stored), sizeof(stored));
    if (stored != planDatabaseChecksum(bytes.data(), bytes.size() - sizeof(stored))) return corrupt("is damaged (checksum mismatch)");

    Reader in{bytes.data(), bytes.size() - sizeof(stored), sizeof(kMagic)};
    uint32_t version = in.word();
    if (version != kFileVersion)
        return corrupt("was written by another version (" + std::to_string(version) + ", expected " +
                       std::to_string(kFileVersion) + ")");
    uint32_t count = in.word();
    const size_t limit = bytes.size() / 4;
    for (uint32_t i = 0; i < count && in.ok; ++i) {
        std::vector<uint32_t> key;
        Plan plan;
        in.array(key, limit);
        plan.ringSize = in.word();
        plan.maxDepth = in.word();
        in.array(plan.nodes, limit);
        in.array(plan.points, limit);
        in.array(plan.stencilWeights, limit);
        for (uint32_t& c : plan.stencilCountByLevel) c = in.word();
        plan.cornerTangents = in.word();
        const uint32_t lastUse = in.word();
        // Word 4 of a key is its local vertex count (face_config.h): the columns the plan's
        // stencils must have, or applying them would read past the face's 1-ring.
        const bool matchesKey = key.size() > 5 && (plan.nodes.empty() || plan.ringSize == key[4]);
        if (!in.ok || !matchesKey || !planIsConsistent(plan))
            return corrupt("has an invalid plan (entry " + std::to_string(i) + ")");
        const uint64_t hash = hashKey(key);
        insertLocked(std::move(key), hash, std::move(plan), lastUse);
        session_ = std::max(session_, lastUse + 1);
    }
    if (!in.ok || in.at != in.size) return corrupt("is truncated or has trailing data");
    return success();
}

}  // namespace qp
