// What quadplan.Scene's binding files share (bind_scene.cpp, bind_animation.cpp, bind_displacement.cpp).
#pragma once

#include <memory>
#include <vector>

#include "conversions.h"
#include "plans/plan_evaluator.h"
#include "scene_document.h"

namespace qp::py {

using Document = SceneDocument;
using SceneClass = py::class_<Document, std::unique_ptr<Document>>;

// A Selection (any mode: the vertices a transform of it moves) or vertex indices.
std::vector<uint32_t> verticesOf(const Document& doc, const py::object& target);
// Translation, rotation and scale given as 3-sequences (None: keep `base`'s).
ObjectTransform transformFrom(const py::object& translation, const py::object& rotation, const py::object& scale,
                              ObjectTransform base);

// (sub-faces, u, v) broadcast against each other (numpy rules), checked against the cage.
std::vector<SampleRequest> sampleRequests(const PlannedCage& planned, const py::object& subfaces, const py::object& u,
                                          const py::object& v);

// Scene's sculpted displacement: strokes, mask, resolution, evaluation (bind_displacement.cpp).
void bindSceneDisplacement(SceneClass& scene);

// Scene's animation: frame, frames, fps, set_frame, keys, transform keys, interpolation, timeline,
// sequences (bind_animation.cpp).
void bindSceneAnimation(SceneClass& scene);

}  // namespace qp::py
