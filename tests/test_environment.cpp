// No test reads or writes the user's plan cache (core/plans/plan_cache.h) unless it names its own
// file: a warm cache would change what the tests count (plans built, database misses). Compiled
// into the unit and the window tests; the editors the window tests start inherit it.
#include <cstdlib>

namespace {

const bool kPlanCacheOff = setenv("QUADPLAN_PLAN_CACHE", "off", 1) == 0;

}  // namespace
