#include "scene/planned_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace qp {

Result<PlannedScene> PlannedScene::create(const Scene& scene, PlanDatabase& database, const PlanOptions& options,
                                          const std::string& source) {
    Result<std::vector<uint32_t>> owners = cageOwners(scene.objects);
    if (!owners) return Error{source + ": " + owners.error().message};
    const auto start = std::chrono::steady_clock::now();
    PlannedScene out;
    out.cageOfObject.assign(scene.objects.size(), UINT32_MAX);
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        if ((*owners)[i] != i) continue;
        const uint64_t missesBefore = database.misses();
        const std::string name = scene.objects.size() == 1 ? source : source + ": object \"" + scene.objects[i].name + "\"";
        Result<PlannedCage> planned = PlannedCage::create(scene.objects[i].cage, database, options, name);
        if (!planned) return planned.error();
        out.cageOfObject[i] = uint32_t(out.cages.size());
        out.objectOfCage.push_back(i);
        out.newPlansOfCage.push_back(uint32_t(database.misses() - missesBefore));
        out.cages.push_back(std::move(planned).value());
    }
    for (uint32_t i = 0; i < scene.objects.size(); ++i) out.cageOfObject[i] = out.cageOfObject[(*owners)[i]];
    out.planMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

Bounds sceneBounds(const Scene& scene, const PlannedScene& planned) {
    const bool anyVisible =
        std::any_of(scene.objects.begin(), scene.objects.end(), [](const SceneObject& o) { return o.visible; });
    Bounds out{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        if (anyVisible && !scene.objects[i].visible) continue;
        const Bounds b = objectBounds(scene.objects[i], planned.cages[planned.cageOfObject[i]].cage());
        out.min = glm::min(out.min, b.min);
        out.max = glm::max(out.max, b.max);
    }
    return scene.objects.empty() ? Bounds{} : out;
}

namespace {

std::vector<uint32_t> plansOf(const PlannedCage& cage) {
    std::vector<uint32_t> plans;
    plans.reserve(cage.subfaceCount());
    for (uint32_t s = 0; s < cage.subfaceCount(); ++s)
        if (cage.subfacePlan(s) != kNoPlan) plans.push_back(cage.subfacePlan(s));
    std::sort(plans.begin(), plans.end());
    plans.erase(std::unique(plans.begin(), plans.end()), plans.end());
    return plans;
}

}  // namespace

ScenePlanStats scenePlanStats(const Scene& scene, const PlannedScene& planned) {
    ScenePlanStats out;
    out.cages = uint32_t(planned.cages.size());
    std::vector<std::vector<uint32_t>> plans;
    std::vector<uint32_t> cagesUsing;  // per plan id: how many cages use it
    for (const PlannedCage& cage : planned.cages) {
        plans.push_back(plansOf(cage));
        for (uint32_t id : plans.back()) {
            if (id >= cagesUsing.size()) cagesUsing.resize(id + 1, 0);
            ++cagesUsing[id];
        }
    }
    const PlanDatabase* database = planned.cages.empty() ? nullptr : &planned.cages.front().database();
    for (uint32_t id = 0; id < cagesUsing.size(); ++id) {
        if (cagesUsing[id] == 0) continue;
        ++out.uniquePlans;
        if (cagesUsing[id] > 1) ++out.sharedPlans;
        out.planBytes += database->plan(id).byteSize();
    }
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        const uint32_t c = planned.cageOfObject[i];
        const PlannedCage& cage = planned.cages[c];
        ObjectPlanStats o;
        o.name = scene.objects[i].name;
        o.instanceOf = scene.objects[i].instanceOf;
        o.cage = c;
        o.faces = cage.cage().faceCount();
        o.subfaces = cage.subfaceCount();
        o.plans = uint32_t(plans[c].size());
        for (uint32_t id : plans[c]) {
            if (cagesUsing[id] > 1) ++o.sharedPlans;
            o.planBytes += database->plan(id).byteSize();
        }
        o.newPlans = planned.objectOfCage[c] == i ? planned.newPlansOfCage[c] : 0;
        out.instanceFaces += o.faces;
        out.objects.push_back(std::move(o));
    }
    return out;
}

}  // namespace qp
