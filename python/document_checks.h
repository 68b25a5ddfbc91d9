// Checks of a script's input shared by SceneDocument's files (internal to the Python module).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "scene/scene_objects.h"

namespace qp::py {

inline Status checkVertices(const Cage& cage, std::span<const uint32_t> vertices) {
    for (uint32_t v : vertices)
        if (v >= cage.vertexCount())
            return Error{"vertex " + std::to_string(uint64_t(v) + 1) + " does not exist (the cage has " +
                         std::to_string(cage.vertexCount()) + " vertices)"};
    return success();
}

// A transform an object can hold (finite, no zero scale), named in the message.
inline Status checkTransform(const std::string& name, const ObjectTransform& transform) {
    SceneObject probe;
    probe.name = name;
    probe.transform = transform;
    std::vector<SceneObject> check{probe};
    return validateObjects(check, "");
}

}  // namespace qp::py
