// PlannedScene: the planned cage of every object of a scene that has a cage of its own, all
// planned through one plan database, so that objects with the same configurations share their
// plans (Brainerd et al. 2016 §4.3: plans are keyed by configuration, not by mesh) and an
// instance adds none at all: it draws its source's planned cage under its own transform.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plans/planned_cage.h"
#include "scene/scene.h"

namespace qp {

struct PlannedScene {
    std::vector<PlannedCage> cages;      // one per object with a cage of its own, in object order
    std::vector<uint32_t> cageOfObject;  // per object: the index in `cages` of the cage it draws
    std::vector<uint32_t> objectOfCage;  // per cage: the object that owns it
    std::vector<uint32_t> newPlansOfCage;  // per cage: plans its planning added to the database
    double planMs = 0.0;                   // wall time of planning every cage

    // Plans every cage (instance links resolved; validateObjects must hold). Errors name the
    // object. `source` names the scene file.
    static Result<PlannedScene> create(const Scene& scene, PlanDatabase& database, const PlanOptions& options,
                                       const std::string& source);
};

// sceneBounds (scene.h) with the cages as planned (a document's scene holds stale copies).
Bounds sceneBounds(const Scene& scene, const PlannedScene& planned);

// What plan-stats and info report per object and for the whole scene.
struct ObjectPlanStats {
    std::string name;
    std::string instanceOf;     // empty: the object has its own cage
    uint32_t cage = 0;          // index in PlannedScene::cages
    uint32_t faces = 0, subfaces = 0;
    uint32_t plans = 0;         // distinct plans its cage uses
    uint32_t sharedPlans = 0;   // of those, plans another object's cage uses too
    uint32_t newPlans = 0;      // plans planning its cage added (0 for an instance)
    uint64_t planBytes = 0;     // bytes of the plans its cage uses
};
struct ScenePlanStats {
    std::vector<ObjectPlanStats> objects;
    uint32_t cages = 0;          // distinct cages planned
    uint32_t uniquePlans = 0;    // distinct plans every cage together uses
    uint32_t sharedPlans = 0;    // plans used by two or more cages
    uint64_t planBytes = 0;      // bytes of the unique plans (each counted once)
    uint64_t instanceFaces = 0;  // faces drawn counting every object (instances included)
};
ScenePlanStats scenePlanStats(const Scene& scene, const PlannedScene& planned);

}  // namespace qp
