// What the sculpting tests share: a planned cage with a displacement and its samples cache.
#pragma once

#include <optional>
#include <vector>

#include <glm/geometric.hpp>

#include "displacement/displacement.h"
#include "displacement/sculpt_samples.h"
#include "plans/planned_cage.h"

namespace qp::test {

struct Sculpt {
    PlanDatabase database;
    std::optional<PlannedCage> planned;
    Displacement displacement;
    std::optional<SculptSamples> samples;

    Sculpt(const Cage& cage, uint32_t resolution) {
        auto p = PlannedCage::create(cage, database, PlanOptions{}, "test cage");
        EXPECT_TRUE(p) << p.error().message;
        planned.emplace(std::move(p).value());
        displacement = makeDisplacement(planned->cage(), planned->topology(), resolution);
        samples.emplace(SculptSamples::build(*planned, displacement.layout));
    }

    // Samples with a site (those brushes reach).
    std::vector<uint32_t> sited() const {
        std::vector<uint32_t> out;
        for (uint32_t i = 0; i < samples->sampleCount(); ++i)
            if (samples->hasSite(i)) out.push_back(i);
        return out;
    }
    float distance(uint32_t sample, const glm::vec3& p) const { return glm::length(samples->position(sample) - p); }
    glm::vec3 displaced(uint32_t s) const { return samples->position(s) + displacement.samples[s] * samples->normal(s); }
};

}  // namespace qp::test
