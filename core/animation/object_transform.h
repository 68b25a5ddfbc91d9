// An object's placement in a scene: translation, XYZ Euler rotation and scale, with the matrix
// it stands for and the way back from a matrix (what object-mode handles produce).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "mesh/result.h"

namespace qp {

// Scale, then rotation about x, then y, then z (degrees, right-handed), then translation: the
// order Blender's "XYZ Euler" applies. Scale may be negative (a mirror) but not zero.
struct ObjectTransform {
    glm::vec3 translation{0.0f};
    glm::vec3 rotationDegrees{0.0f};
    glm::vec3 scale{1.0f};

    glm::mat4 matrix() const;
    bool isIdentity() const { return *this == ObjectTransform{}; }
    bool operator==(const ObjectTransform&) const = default;
};

// The transform whose matrix() is `matrix` (a rotation above 90 degrees about y comes back as
// its equal with the x and z angles turned by 180). Fails when the matrix shears (its axes are
// not orthogonal: a non-uniform scale along axes other than the object's own), has a zero axis or
// is not finite: what an object's transform cannot hold. Object-mode handles compose their
// change with the start matrix and store the result through this.
Result<ObjectTransform> decomposeTransform(const glm::mat4& matrix);

// The largest factor the transform stretches a length by (the largest |scale| component):
// what turns an object-space tolerance or a screen-size estimate into world units.
float maxScale(const ObjectTransform& transform);

}  // namespace qp
