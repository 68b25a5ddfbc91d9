// The persistent plan cache (core/plans/plan_cache.h) and what PlanDatabase does for it: sessions
// saved with every plan, the least recently used dropped beyond a bound, a fallback database
// plans are copied from, stale or damaged files survived.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "plans/plan_cache.h"
#include "plans/planned_cage.h"
#include "test_cages.h"
#include "test_support.h"

namespace qp {
namespace {

namespace fs = std::filesystem;

// Sets an environment variable for one test and puts the old value back (the test environment
// has QUADPLAN_PLAN_CACHE=off, tests/test_environment.cpp).
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_) setenv(name_, old_->c_str(), 1);
        else unsetenv(name_);
    }

private:
    const char* name_;
    std::optional<std::string> old_;
};

uint32_t plansOf(const Cage& cage, PlanDatabase& database) {
    Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, "test");
    EXPECT_TRUE(planned.ok());
    return database.stats().plans;
}

// A directory of this process's own (tests run in parallel).
fs::path outputDir() {
    const fs::path dir = fs::temp_directory_path() / ("qp-plan-cache-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

fs::path freshPath(const std::string& name) {
    const fs::path path = outputDir() / name;
    fs::remove(path);
    return path;
}

}  // namespace

TEST(PlanCache, TheLeastRecentlyUsedPlansGoFirstWhenTheFileIsBounded) {
    const fs::path first = freshPath("lru_first.qpdb"), second = freshPath("lru_second.qpdb");
    PlanDatabase old;
    const uint32_t gridPlans = plansOf(test::makeGrid(5), old);
    ASSERT_TRUE(old.save(first.string()).ok());

    // A later session: loads the grid's plans, plans a cube (other configurations).
    PlanDatabase later;
    ASSERT_TRUE(later.load(first.string()).ok());
    const uint32_t cubePlans = plansOf(test::makeSubdividedCube(3), later) - gridPlans;
    ASSERT_GT(cubePlans, 0u);
    ASSERT_TRUE(later.save(second.string()).ok());  // unbounded: everything
    PlanDatabase all;
    ASSERT_TRUE(all.load(second.string()).ok());
    EXPECT_EQ(all.stats().plans, gridPlans + cubePlans);

    // Bounded to the cube's plans: the grid's, used a session earlier, are left out.
    PlanDatabase cubeOnly;
    plansOf(test::makeSubdividedCube(3), cubeOnly);
    ASSERT_TRUE(later.save(second.string(), cubeOnly.stats().bytes).ok());
    PlanDatabase trimmed;
    ASSERT_TRUE(trimmed.load(second.string()).ok());
    EXPECT_EQ(trimmed.stats().plans, cubeOnly.stats().plans);
    // ... and the cube plans from it without building one.
    PlanDatabase reuse;
    auto fallback = std::make_shared<PlanDatabase>();
    ASSERT_TRUE(fallback->load(second.string()).ok());
    reuse.setFallback(fallback);
    plansOf(test::makeSubdividedCube(3), reuse);
    EXPECT_EQ(reuse.stats().misses, 0u);
    EXPECT_EQ(reuse.stats().fromFallback, cubeOnly.stats().plans);
}

TEST(PlanCache, ASecondOpeningPlansFromTheCacheAndTheFileKeepsWhatOthersStored) {
    const fs::path path = freshPath("cache.qpdb");
    ScopedEnv cacheFile("QUADPLAN_PLAN_CACHE", path.string());
    ASSERT_TRUE(planCacheLocation().has_value());
    EXPECT_EQ(planCacheLocation()->path, path.string());

    PlanDatabase first;
    first.setFallback(sharedPlanCache());
    const uint32_t plans = plansOf(test::makeSubdividedCube(3), first);
    EXPECT_EQ(first.stats().misses, plans);  // an empty cache: every plan built
    ASSERT_TRUE(storeInPlanCache(first).ok());
    ASSERT_TRUE(fs::exists(path));

    PlanDatabase second;
    second.setFallback(sharedPlanCache());
    plansOf(test::makeSubdividedCube(3), second);
    EXPECT_EQ(second.stats().misses, 0u);
    EXPECT_EQ(second.stats().fromFallback, plans);
    EXPECT_EQ(second.stats().plans, plans);  // the document holds only what its cage uses

    // Another process adds a grid's plans to the file; storing from this one keeps them.
    PlanDatabase other;
    const uint32_t gridPlans = plansOf(test::makeGrid(4), other);
    PlanDatabase file;
    ASSERT_TRUE(file.load(path.string()).ok());
    file.mergeFrom(other);
    ASSERT_TRUE(file.save(path.string()).ok());
    PlanDatabase mixed;
    mixed.setFallback(sharedPlanCache());
    plansOf(test::makeMixedGrid(), mixed);  // some new configurations
    ASSERT_GT(mixed.stats().misses, 0u);
    ASSERT_TRUE(storeInPlanCache(mixed).ok());
    PlanDatabase stored;
    ASSERT_TRUE(stored.load(path.string()).ok());
    EXPECT_GE(stored.stats().plans, plans + gridPlans);
    PlanDatabase grid;
    grid.setFallback(sharedPlanCache());
    plansOf(test::makeGrid(4), grid);
    EXPECT_EQ(grid.stats().misses, 0u);
}

TEST(PlanCache, ADamagedOrStaleFileIsReportedAndReplaced) {
    const fs::path path = freshPath("damaged.qpdb");
    std::ofstream(path) << "QPPLANDB but not really";
    ScopedEnv cacheFile("QUADPLAN_PLAN_CACHE", path.string());
    std::string warning;
    std::shared_ptr<const PlanDatabase> cache = sharedPlanCache(&warning);
    ASSERT_NE(cache, nullptr);
    EXPECT_EQ(cache->stats().plans, 0u);
    EXPECT_NE(warning.find(path.string()), std::string::npos) << warning;
    PlanDatabase database;
    database.setFallback(cache);
    plansOf(test::makeGrid(3), database);
    ASSERT_TRUE(storeInPlanCache(database).ok());
    PlanDatabase reread;
    EXPECT_TRUE(reread.load(path.string()).ok());
    EXPECT_EQ(reread.stats().plans, database.stats().plans);

    // A directory where the file should be: storing fails with a message, nothing else breaks.
    const fs::path blocked = outputDir() / "blocked_cache";
    fs::create_directories(blocked / "plans.qpdb");
    ScopedEnv blockedFile("QUADPLAN_PLAN_CACHE", (blocked / "plans.qpdb").string());
    EXPECT_FALSE(storeInPlanCache(database).ok());
}

TEST(PlanCache, LocationFollowsTheEnvironment) {
    {
        ScopedEnv off("QUADPLAN_PLAN_CACHE", "off");
        EXPECT_FALSE(planCacheLocation().has_value());
        EXPECT_EQ(sharedPlanCache(), nullptr);
        PlanDatabase database;
        EXPECT_TRUE(storeInPlanCache(database).ok());
    }
    unsetenv("QUADPLAN_PLAN_CACHE");
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "/tmp/xdg-cache");
        ScopedEnv bound("QUADPLAN_PLAN_CACHE_MB", "64");
        ASSERT_TRUE(planCacheLocation().has_value());
        EXPECT_EQ(planCacheLocation()->path, "/tmp/xdg-cache/quadplan/plans.qpdb");
        EXPECT_EQ(planCacheLocation()->maxBytes, 64ull << 20);
    }
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "");
        ScopedEnv home("HOME", "/home/someone");
        ASSERT_TRUE(planCacheLocation().has_value());
        EXPECT_EQ(planCacheLocation()->path, "/home/someone/.cache/quadplan/plans.qpdb");
        EXPECT_EQ(planCacheLocation()->maxBytes, 256ull << 20);
    }
    setenv("QUADPLAN_PLAN_CACHE", "off", 1);
}

}  // namespace qp
