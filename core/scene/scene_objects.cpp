#include "scene/scene_objects.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "displacement/displacement_io.h"

namespace qp {

uint32_t findObject(const std::vector<SceneObject>& objects, const std::string& name) {
    for (uint32_t i = 0; i < objects.size(); ++i)
        if (objects[i].name == name) return i;
    return UINT32_MAX;
}

Result<std::vector<uint32_t>> cageOwners(const std::vector<SceneObject>& objects) {
    std::vector<uint32_t> owner(objects.size());
    for (uint32_t i = 0; i < objects.size(); ++i) {
        uint32_t at = i;
        std::vector<uint32_t> chain{i};
        while (objects[at].isInstance()) {
            const uint32_t next = findObject(objects, objects[at].instanceOf);
            if (next == UINT32_MAX)
                return Error{"object \"" + objects[at].name + "\" is an instance of \"" + objects[at].instanceOf +
                             "\", which is not in the scene"};
            if (std::find(chain.begin(), chain.end(), next) != chain.end()) {
                std::string cycle;
                for (uint32_t c : chain) cycle += "\"" + objects[c].name + "\" -> ";
                return Error{"object \"" + objects[i].name + "\": its instance links go round in a cycle (" + cycle +
                             "\"" + objects[next].name + "\")"};
            }
            chain.push_back(next);
            at = next;
        }
        owner[i] = at;
    }
    return owner;
}

Status validateObjects(const std::vector<SceneObject>& objects, const std::string& source) {
    const std::string prefix = source.empty() ? "" : source + ": ";
    if (objects.empty()) return Error{prefix + "the scene has no objects"};
    std::set<std::string> names;
    for (const SceneObject& o : objects) {
        const std::string name = "object \"" + o.name + "\"";
        if (o.name.empty()) return Error{prefix + "an object has an empty name"};
        if (!names.insert(o.name).second) return Error{prefix + "two objects are called \"" + o.name + "\"; names must be unique"};
        const ObjectTransform& t = o.transform;
        for (const glm::vec3* v : {&t.translation, &t.rotationDegrees, &t.scale})
            for (int k = 0; k < 3; ++k)
                if (!std::isfinite((*v)[k])) return Error{prefix + name + ": its transform has a non-finite value"};
        for (int k = 0; k < 3; ++k)
            if (std::fabs(t.scale[k]) < 1e-20f) {
                char value[32];
                std::snprintf(value, sizeof value, "%g", double(t.scale[k]));
                return Error{prefix + name + ": scale " + value + " along " + "xyz"[k] +
                             " is zero (the object would have no volume and no normals)"};
            }
        if (o.isInstance()) {
            if (o.cage.vertexCount() > 0 || o.cage.faceCount() > 0)
                return Error{prefix + name + ": an instance draws its source's cage and cannot have one of its own"};
            if (!o.displacement.empty())
                return Error{prefix + name + ": an instance draws its source's displacement and cannot have one of its own"};
            if (!o.animation.vertexKeys.empty())
                return Error{prefix + name + ": an instance follows its source's cage and cannot key its positions"};
        } else if (!displacementFitsCage(o.displacement, o.cage)) {
            return Error{prefix + name + ": the displacement does not fit the cage's faces (resample it after adding "
                                         "or removing faces)"};
        }
        if (Status animation = validateAnimation(o.animation, o.cage.vertexCount(), prefix + name + ": animation"); !animation)
            return animation;
    }
    Result<std::vector<uint32_t>> owners = cageOwners(objects);
    if (!owners) return Error{prefix + owners.error().message};
    return Done{};
}

std::string uniqueObjectName(const std::vector<SceneObject>& objects, const std::string& base) {
    if (findObject(objects, base) == UINT32_MAX) return base;
    std::string stem = base;
    const size_t dot = stem.rfind('.');
    if (dot != std::string::npos && dot + 4 == stem.size() &&
        std::all_of(stem.begin() + long(dot) + 1, stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
        stem.resize(dot);
    for (int n = 1;; ++n) {
        char suffix[16];
        std::snprintf(suffix, sizeof suffix, ".%03d", n);
        std::string name = stem + suffix;
        if (findObject(objects, name) == UINT32_MAX) return name;
    }
}

Bounds objectBounds(const SceneObject& object, const Cage& cage) {
    return transformBounds(computeBounds(cage), object.transform.matrix());
}

Bounds transformBounds(const Bounds& local, const glm::mat4& m) {
    Bounds out{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? local.max.x : local.min.x, (corner & 2) ? local.max.y : local.min.y,
                          (corner & 4) ? local.max.z : local.min.z);
        const glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
        out.min = glm::min(out.min, w);
        out.max = glm::max(out.max, w);
    }
    return out;
}

}  // namespace qp
