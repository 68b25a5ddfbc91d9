#include "plans/plan_database.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

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

// One entry of a database file, read and checked.
struct FileEntry {
    std::vector<uint32_t> key;
    Plan plan;
    uint32_t lastUse = 0;
    uint64_t hash = 0;
    bool valid = false;
};

// Reads and checks every entry of `body` (the file without its checksum) into `entries`:
// empty when all are sound, else what is wrong. Bounds-checked, so damaged bytes are safe.
std::string parseEntries(std::string_view body, std::vector<FileEntry>& entries) {
    Reader in{body.data(), body.size(), sizeof(kMagic)};
    uint32_t version = in.word();
    if (version != kFileVersion)
        return "was written by another version (" + std::to_string(version) + ", expected " +
               std::to_string(kFileVersion) + ")";
    const uint32_t count = in.word();
    const size_t limit = body.size() / 4;

    // Where each entry starts, from its array lengths alone; the entries are then read and
    // checked on every core (half of a million-face database's load). The skips below and the
    // reads after them follow the entry layout save() writes: change the three together (and
    // kFileVersion).
    std::vector<size_t> entryAt;
    entryAt.reserve(std::min<size_t>(count, limit));
    for (uint32_t i = 0; i < count && in.ok; ++i) {
        const size_t at = in.at;
        auto skipArray = [&](size_t wordsEach) {
            const uint32_t n = in.word();
            if (!in.ok || n > limit || in.at + size_t(n) * wordsEach * 4 > in.size) in.ok = false;
            else in.at += size_t(n) * wordsEach * 4;
        };
        skipArray(1);                       // key
        in.at += 2 * 4;                     // ring size, depth
        skipArray(sizeof(PlanNode) / 4);    // nodes
        skipArray(1);                       // points
        skipArray(1);                       // stencil weights
        in.at += sizeof(Plan::stencilCountByLevel) + 2 * 4;  // counts by level, corner tangents, last use
        if (in.at > in.size) in.ok = false;
        if (in.ok) entryAt.push_back(at);
    }
    const size_t readable = entryAt.size();  // entries before the first one cut short

    entries.resize(readable);
    tbb::parallel_for(size_t(0), readable, [&](size_t i) {
        FileEntry& e = entries[i];
        Reader entry{body.data(), body.size(), entryAt[i]};
        entry.array(e.key, limit);
        e.plan.ringSize = entry.word();
        e.plan.maxDepth = entry.word();
        entry.array(e.plan.nodes, limit);
        entry.array(e.plan.points, limit);
        entry.array(e.plan.stencilWeights, limit);
        for (uint32_t& c : e.plan.stencilCountByLevel) c = entry.word();
        e.plan.cornerTangents = entry.word();
        e.lastUse = entry.word();
        // Word 4 of a key is its local vertex count (face_config.h): the columns the plan's
        // stencils must have, or applying them would read past the face's 1-ring.
        const bool matchesKey = e.key.size() > 5 && (e.plan.nodes.empty() || e.plan.ringSize == e.key[4]);
        e.valid = entry.ok && matchesKey && planIsConsistent(e.plan);
        if (e.valid) e.hash = hashKey(e.key);
    });
    for (size_t i = 0; i < readable; ++i)
        if (!entries[i].valid) return "has an invalid plan (entry " + std::to_string(i) + ")";
    if (readable < count) return "has an invalid plan (entry " + std::to_string(readable) + ")";
    if (in.at != in.size) return "is truncated or has trailing data";
    return {};
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
    std::lock_guard<std::shared_mutex> lock(mutex_);
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
    std::lock_guard<std::shared_mutex> lock(mutex_);
    fallback_ = std::move(fallback);
}

Result<uint32_t> PlanDatabase::findOrBuild(const FaceConfig& config) {
    std::shared_ptr<const PlanDatabase> fallback;
    {
        // Shared: a warm plan of a million faces is a million hits, which an exclusive lock made
        // the threads take in turn. The counters they touch are atomic; everything else that
        // writes them holds the lock exclusively.
        std::shared_lock<std::shared_mutex> lock(mutex_);
        uint32_t id = findLocked(config);
        if (id != UINT32_MAX) {
            std::atomic_ref<uint64_t>(hits_).fetch_add(1, std::memory_order_relaxed);
            std::atomic_ref<uint32_t>(lastUse_[id]).store(session_, std::memory_order_relaxed);
            return id;
        }
        fallback = fallback_;
    }
    if (fallback) {
        std::optional<Plan> cached;
        {
            std::lock_guard<std::shared_mutex> lock(fallback->mutex_);
            if (const uint32_t at = fallback->findLocked(config); at != UINT32_MAX) cached = fallback->plans_[at];
        }
        if (cached) {
            std::lock_guard<std::shared_mutex> lock(mutex_);
            if (uint32_t id = findLocked(config); id != UINT32_MAX) return id;
            ++fromFallback_;
            return insertLocked(config.key, config.hash, std::move(*cached), session_);
        }
    }
    // Build outside the lock so several threads can build different plans at once.
    Result<Plan> plan = buildPlan(config.key);
    if (!plan) return plan.error();
    std::lock_guard<std::shared_mutex> lock(mutex_);
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
    std::lock_guard<std::shared_mutex> lock(mutex_);
    return misses_;
}

PlanDatabaseStats PlanDatabase::stats() const {
    std::lock_guard<std::shared_mutex> lock(mutex_);
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
    std::lock_guard<std::shared_mutex> lock(mutex_);
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
    std::lock_guard<std::shared_mutex> lock(mutex_);
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
    Result<MappedFile> file = mapFile(path);
    if (!file) {
        std::lock_guard<std::shared_mutex> lock(mutex_);
        byHash_.clear();
        keys_.clear();
        plans_.clear();
        lastUse_.clear();
        return file.error();
    }
    return loadFromBytes(file->bytes(), path);
}

Status PlanDatabase::loadFromBytes(std::string_view bytes, const std::string& path) {
    std::lock_guard<std::shared_mutex> lock(mutex_);
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

    std::vector<FileEntry> entries;
    const std::string_view body = bytes.substr(0, bytes.size() - sizeof(stored));
    // The checksum (a fifth of a million-face database's load, on one core) is computed beside
    // the parsing, which is bounds-checked and safe on damaged bytes; a mismatch is told first.
    bool intact = false;
    std::string problem;
    tbb::parallel_invoke([&] { intact = stored == planDatabaseChecksum(body.data(), body.size()); },
                         [&] { problem = parseEntries(body, entries); });
    if (!intact) return corrupt("is damaged (checksum mismatch)");
    if (!problem.empty()) return corrupt(problem);
    const size_t readable = entries.size();
    byHash_.reserve(readable);
    keys_.reserve(readable);
    lastUse_.reserve(readable);
    for (FileEntry& e : entries) {
        insertLocked(std::move(e.key), e.hash, std::move(e.plan), e.lastUse);
        session_ = std::max(session_, e.lastUse + 1);
    }
    return success();
}

}  // namespace qp
