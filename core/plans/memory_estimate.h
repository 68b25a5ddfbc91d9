// What planning a cage is expected to cost in memory, so that a cage too large for the machine is
// refused before anything is allocated, with the estimate in the message (issue 21).
#pragma once

#include <cstdint>
#include <string>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

// Bytes PlannedCage::create is expected to hold at its peak for `cage`: per sub-face (a quad is
// one, an n-gon n), from the million-face generated cage's measured peak (docs/plan-engine.md (f):
// 1.54 GiB for 1,078,494 sub-faces, the OBJ file read included), rounded up.
inline constexpr uint64_t kPlanningBytesPerSubface = 1600;
uint64_t planningBytesEstimate(const Cage& cage);

// MemAvailable from /proc/meminfo, or 0 when it cannot be read.
uint64_t availableMemoryBytes();

// Hands the heap's free pages back to the system, after a large task's temporaries are freed:
// glibc keeps them in each thread's arena, where a later task on other threads cannot reuse them
// (a million faces: 150-420 MiB after planning, varying with which threads ran what). No-op
// elsewhere.
void releaseFreedMemory();

// An error naming `what`, the estimate and what is available when `needed` is more than
// `available` (0: unknown, never refused).
Status checkMemory(uint64_t needed, uint64_t available, const std::string& what);

}  // namespace qp
