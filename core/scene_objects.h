// The objects of a scene: each a named cage (its own, or an instance of another object's) placed
// by a transform. What the scene file (scene.h, docs/scene-format.md) stores per object, and the
// checks that make a set of objects drawable: unique names, instance links that end at an object
// with a cage, finite transforms with non-zero scale.
//
// Instances share their source's cage, its tags and its sculpted displacement (as Blender's
// linked duplicates share their mesh data): a renderer plans and builds one surface per cage and
// draws it once per object, each with its own transform, so an instance adds no plans and an
// object move changes nothing but a matrix.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "cage.h"
#include "displacement.h"
#include "result.h"

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

struct SceneObject {
    std::string name;
    // The object's own cage; empty for an instance (it draws the cage of `instanceOf`).
    Cage cage;
    std::string cagePath;    // as written in the scene file; empty: inline (or an instance)
    std::string instanceOf;  // non-empty: the name of the object whose cage this one shares
    ObjectTransform transform;
    bool visible = true;
    // Sculpted displacement over the cage's sub-faces (displacement.h); empty for an instance,
    // which draws its source's. Its layout follows the cage's topology: rebuild it
    // (resampleDisplacement, makeDisplacement) after topology edits.
    Displacement displacement;

    bool isInstance() const { return !instanceOf.empty(); }
};

// Index of the object called `name`, or UINT32_MAX.
uint32_t findObject(const std::vector<SceneObject>& objects, const std::string& name);

// Per object, the index of the object whose cage it draws: itself, or where its chain of instance
// links ends. Fails naming the object when a link names no object or goes round in a cycle.
Result<std::vector<uint32_t>> cageOwners(const std::vector<SceneObject>& objects);

// Everything a drawable set of objects must satisfy, each failure naming the object (and
// `source`): at least one object; names non-empty and unique; instance links resolvable
// (cageOwners); an instance carries no cage or displacement of its own; transforms finite with
// every scale component non-zero; displacements fitting their cages. Cages themselves are
// checked where they are read (validateCage).
Status validateObjects(const std::vector<SceneObject>& objects, const std::string& source);

// A name not used by any object: `base` itself, else "base.001", "base.002", ... (Blender's
// way of naming duplicates). A trailing ".NNN" of `base` is replaced, not extended.
std::string uniqueObjectName(const std::vector<SceneObject>& objects, const std::string& base);

// The box holding `bounds` carried by `matrix` (its eight corners' bounds).
Bounds transformBounds(const Bounds& bounds, const glm::mat4& matrix);
// Bounds of `cage` (the one the object draws) under the object's transform.
Bounds objectBounds(const SceneObject& object, const Cage& cage);

}  // namespace qp
