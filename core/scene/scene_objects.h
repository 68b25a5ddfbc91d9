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

#include "animation/cage_animation.h"
#include "animation/object_transform.h"
#include "displacement/displacement.h"
#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

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
    // Keys of the cage's positions (empty for an instance, which follows its source's) and of
    // the object's transform (cage_animation.h); the cage holds the rest positions.
    ObjectAnimation animation;

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
