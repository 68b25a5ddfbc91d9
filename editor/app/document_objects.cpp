#include "document_objects.h"

#include <algorithm>
#include <cassert>
#include <filesystem>
#include <functional>
#include <utility>

#include "document_animation.h"

namespace qp::editor {

namespace {

// An object edit in the history: `apply` and `revert` change the document's objects; the
// planned cage the history passes is not touched.
class ObjectEdit final : public CustomEdit {
public:
    ObjectEdit(std::function<Status()> apply, std::function<Status()> revert, size_t bytes)
        : apply_(std::move(apply)), revert_(std::move(revert)), bytes_(bytes) {}
    Result<EditReport> redo(PlannedCage&) override { return finish(apply_()); }
    Result<EditReport> undo(PlannedCage&) override { return finish(revert_()); }
    size_t bytes() const override { return bytes_; }

private:
    static Result<EditReport> finish(Status status) {
        if (!status) return status.error();
        return EditReport{};
    }
    std::function<Status()> apply_, revert_;
    size_t bytes_;
};

size_t objectBytes(const SceneObject& object, const Cage& cage) {
    return sizeof(SceneObject) + cage.positions.size() * sizeof(glm::vec3) + cage.faceVertices.size() * sizeof(uint32_t) +
           object.displacement.samples.size() * sizeof(float);
}

// What validateObjects needs to check names, links and transforms, without copying cages.
SceneObject withoutGeometry(const SceneObject& object) {
    SceneObject light;
    light.name = object.name;
    light.instanceOf = object.instanceOf;
    light.transform = object.transform;
    light.visible = object.visible;
    return light;
}

std::string inQuotes(const std::string& name) { return "\"" + name + "\""; }

// Every view of the edited cage starts afresh (another cage is in `planned`).
void cageReplaced(Document& doc) {
    ++doc.objectsRevision;
    ++doc.editedCageRevision;
    ++doc.sceneRevision;
    ++doc.positionRevision;
    ++doc.planRevision;
    ++doc.topologyRevision;
    ++doc.displacementRevision;
    doc.unsyncedPlanChange = {};
    doc.unsyncedSamples.clear();
}

// Objects were added or removed: each cage goes back to its owner (found by id), instances to
// their owners' cages; an owner whose cage is not planned yet (new, or back from an undo) is
// planned through the document's database. The object with `activeId` keeps edit mode.
Status relinkObjects(Document& doc, uint32_t activeId) {
    const std::vector<SceneObject>& objects = doc.scene.objects;
    Result<std::vector<uint32_t>> owners = cageOwners(objects);
    if (!owners) return owners.error();
    const uint32_t active = objectIndexOfId(doc, activeId);
    assert(active != kNoObject && "edit mode's object is kept");
    // New cages are planned first, so that a failure leaves the document as it was.
    std::vector<std::pair<uint32_t, PlannedCage>> planned;  // (object id, its cage)
    for (uint32_t i = 0; i < objects.size(); ++i) {
        if ((*owners)[i] != i || i == active) continue;
        const uint32_t id = doc.objectIds[i];
        if (std::find(doc.otherCageOwnerIds.begin(), doc.otherCageOwnerIds.end(), id) != doc.otherCageOwnerIds.end()) continue;
        Result<PlannedCage> cage = PlannedCage::create(objects[i].cage, *doc.database, doc.planOptions, "object " + inQuotes(objects[i].name));
        if (!cage) return cage.error();
        if (Status shown = showCurrentFrameOn(doc, i, *cage); !shown) return shown;  // planned at rest
        planned.push_back({id, std::move(cage).value()});
    }
    doc.activeObject = active;
    std::vector<PlannedCage> cages;
    std::vector<Bounds> bounds;
    std::vector<uint32_t> ownerIds;
    std::vector<uint32_t> cageOf(objects.size(), kActiveCage);
    for (uint32_t i = 0; i < objects.size(); ++i) {
        if ((*owners)[i] != i || i == active) continue;
        const uint32_t id = doc.objectIds[i];
        auto kept = std::find(doc.otherCageOwnerIds.begin(), doc.otherCageOwnerIds.end(), id);
        if (kept != doc.otherCageOwnerIds.end()) {
            const size_t k = size_t(kept - doc.otherCageOwnerIds.begin());
            cages.push_back(std::move(doc.otherCages[k]));
            bounds.push_back(doc.otherCageBounds[k]);
            *kept = 0;  // taken
        } else {
            auto made = std::find_if(planned.begin(), planned.end(), [&](const auto& p) { return p.first == id; });
            bounds.push_back(computeBounds(made->second.cage()));
            cages.push_back(std::move(made->second));
        }
        cageOf[i] = uint32_t(cages.size() - 1);
        ownerIds.push_back(id);
    }
    for (uint32_t i = 0; i < objects.size(); ++i) cageOf[i] = cageOf[(*owners)[i]];
    doc.otherCages = std::move(cages);
    doc.otherCageBounds = std::move(bounds);
    doc.otherCageOwnerIds = std::move(ownerIds);
    doc.otherCageOfObject = std::move(cageOf);
    ++doc.objectsRevision;
    ++doc.sceneRevision;
    return success();
}

// Puts `object` (with `id`) at `index` of the scene and plans its cage when it has one.
Status insertObject(Document& doc, uint32_t index, SceneObject object, uint32_t id) {
    const uint32_t activeId = doc.objectIds[doc.activeObject];
    doc.scene.objects.insert(doc.scene.objects.begin() + index, std::move(object));
    doc.objectIds.insert(doc.objectIds.begin() + index, id);
    Status linked = relinkObjects(doc, activeId);
    if (!linked) {  // nothing half done: the object goes again
        doc.scene.objects.erase(doc.scene.objects.begin() + index);
        doc.objectIds.erase(doc.objectIds.begin() + index);
        (void)relinkObjects(doc, activeId);
    }
    return linked;
}

// Takes the object with `id` out of the scene (edit mode moves to another cage first when it
// is on this one's) and returns it with its current cage.
Result<SceneObject> takeObject(Document& doc, uint32_t id) {
    const uint32_t index = objectIndexOfId(doc, id);
    if (index == kNoObject) return Error{"the object is gone"};
    if (index == doc.activeObject) {
        uint32_t other = kNoObject;
        for (uint32_t i = 0; i < doc.scene.objects.size() && other == kNoObject; ++i)
            if (i != index && cageOwnerOf(doc, i) != index) other = i;
        if (other == kNoObject) return Error{"no other cage to edit once " + inQuotes(doc.scene.objects[index].name) + " is gone"};
        if (Status moved = editObjectCage(doc, other); !moved) return moved.error();
    }
    const uint32_t activeId = doc.objectIds[doc.activeObject];
    SceneObject object = std::move(doc.scene.objects[index]);
    doc.scene.objects.erase(doc.scene.objects.begin() + index);
    doc.objectIds.erase(doc.objectIds.begin() + index);
    if (doc.selectedObjectId == id) doc.selectedObjectId = 0;
    Status linked = relinkObjects(doc, activeId);
    assert(linked && "removing an object nobody instances keeps every link");
    (void)linked;
    return object;
}

Status checkObject(const Document& doc, uint32_t object) {
    if (!doc.planned) return Error{"no scene is open"};
    if (object >= doc.scene.objects.size())
        return Error{"object " + std::to_string(object) + " does not exist (the scene has " +
                     std::to_string(doc.scene.objects.size()) + ", numbered from 0)"};
    return success();
}

// Where a duplicate goes: beside the original along x, clear of it.
ObjectTransform besideOf(const Document& doc, uint32_t object) {
    ObjectTransform t = doc.scene.objects[object].transform;
    const Bounds world = transformBounds(objectCageBounds(doc, object), t.matrix());
    t.translation.x += 1.2f * (world.max.x - world.min.x);
    return t;
}

// Appends `added` (names already unique) as one history entry; returns the first one's index.
Result<uint32_t> appendObjects(Document& doc, const std::string& entryName, std::vector<SceneObject> added, uint64_t frame) {
    std::vector<SceneObject> check;
    for (const SceneObject& o : doc.scene.objects) check.push_back(withoutGeometry(o));
    check.insert(check.end(), added.begin(), added.end());  // their cages and displacements checked too
    if (Status valid = validateObjects(check, "the scene"); !valid) return valid.error();
    std::vector<uint32_t> ids;
    size_t bytes = 0;
    for (const SceneObject& o : added) {
        ids.push_back(doc.nextObjectId++);
        bytes += objectBytes(o, o.cage);
    }
    const uint32_t previousSelection = doc.selectedObjectId;
    auto apply = [&doc, added, ids]() -> Status {
        for (size_t k = 0; k < added.size(); ++k) {
            if (Status inserted = insertObject(doc, uint32_t(doc.scene.objects.size()), added[k], ids[k]); !inserted) {
                while (k-- > 0) (void)takeObject(doc, ids[k]);
                return inserted;
            }
        }
        doc.selectedObjectId = ids.front();
        return success();
    };
    auto revert = [&doc, ids, previousSelection]() -> Status {
        for (size_t k = ids.size(); k-- > 0;)
            if (Result<SceneObject> taken = takeObject(doc, ids[k]); !taken) return taken.error();
        doc.selectedObjectId = previousSelection;
        return success();
    };
    Result<EditReport> done = performObjectEdit(doc, entryName, std::make_unique<ObjectEdit>(apply, revert, bytes), frame);
    if (!done) return done.error();
    return objectIndexOfId(doc, ids.front());
}

}  // namespace

Result<EditReport> performObjectChange(Document& doc, const std::string& name, std::function<Status()> apply,
                                       std::function<Status()> revert, size_t bytes, uint64_t frame) {
    return performObjectEdit(doc, name, std::make_unique<ObjectEdit>(std::move(apply), std::move(revert), bytes), frame);
}

uint32_t objectIndexOfId(const Document& doc, uint32_t id) {
    auto it = std::find(doc.objectIds.begin(), doc.objectIds.end(), id);
    return id == 0 || it == doc.objectIds.end() ? kNoObject : uint32_t(it - doc.objectIds.begin());
}

uint32_t cageOwnerOf(const Document& doc, uint32_t object) {
    const uint32_t c = doc.otherCageOfObject.at(object);
    if (c == kActiveCage) return doc.activeObject;
    return objectIndexOfId(doc, doc.otherCageOwnerIds[c]);
}

uint32_t ownerOfOtherCage(const Document& doc, uint32_t cage) { return objectIndexOfId(doc, doc.otherCageOwnerIds.at(cage)); }

const PlannedCage& plannedCageOf(const Document& doc, uint32_t object) {
    const uint32_t c = doc.otherCageOfObject.at(object);
    return c == kActiveCage ? *doc.planned : doc.otherCages[c];
}

Bounds objectCageBounds(const Document& doc, uint32_t object) {
    const uint32_t c = doc.otherCageOfObject.at(object);
    return c == kActiveCage ? computeBounds(doc.planned->cage()) : doc.otherCageBounds[c];
}

uint32_t selectedObject(const Document& doc) { return objectIndexOfId(doc, doc.selectedObjectId); }

void selectObject(Document& doc, uint32_t object) {
    const uint32_t id = object < doc.objectIds.size() ? doc.objectIds[object] : 0;
    if (id == doc.selectedObjectId) return;
    doc.selectedObjectId = id;
    ++doc.sceneRevision;
}

Status editObjectCage(Document& doc, uint32_t object) {
    if (Status valid = checkObject(doc, object); !valid) return valid;
    const uint32_t owner = cageOwnerOf(doc, object);
    if (owner == doc.activeObject) return success();
    const uint32_t c = doc.otherCageOfObject[owner];
    // It stays current while not edited; an animated cage shows a frame, and keeps its rest.
    SceneObject& leaving = doc.scene.objects[doc.activeObject];
    std::vector<glm::vec3> rest = std::move(leaving.cage.positions);
    leaving.cage = doc.planned->cage();
    if (hasVertexKeys(leaving)) leaving.cage.positions = std::move(rest);
    std::swap(*doc.planned, doc.otherCages[c]);
    doc.otherCageOwnerIds[c] = doc.objectIds[doc.activeObject];
    doc.otherCageBounds[c] = computeBounds(doc.otherCages[c].cage());
    for (uint32_t& cage : doc.otherCageOfObject) {
        if (cage == kActiveCage) cage = c;
        else if (cage == c) cage = kActiveCage;
    }
    doc.activeObject = owner;
    doc.history.setTag(doc.objectIds[owner]);
    // Selections and hidden faces are numbered in the old cage.
    doc.selection = Selection{doc.selection.mode};
    doc.hiddenFaces.clear();
    ++doc.hiddenRevision;
    doc.sculptSamples.reset();
    doc.sculptor.reset();
    cageReplaced(doc);
    return success();
}

Status editCageOfTag(Document& doc, uint32_t tag) {
    if (tag == 0 || (doc.activeObject < doc.objectIds.size() && doc.objectIds[doc.activeObject] == tag)) return success();
    const uint32_t object = objectIndexOfId(doc, tag);
    if (object == kNoObject) return Error{"the history entry's object is gone"};
    return editObjectCage(doc, object);
}

Status setObjectTransform(Document& doc, uint32_t object, const ObjectTransform& before, const ObjectTransform& after,
                          uint64_t frame) {
    if (Status valid = checkObject(doc, object); !valid) return valid;
    SceneObject moved;
    moved.name = doc.scene.objects[object].name;
    moved.transform = after;
    if (Status valid = validateObjects({moved}, "the scene"); !valid) return valid;
    const uint32_t id = doc.objectIds[object];
    const std::vector<TransformKey> keysBefore = doc.scene.objects[object].animation.transformKeys;
    ObjectAnimation keyed;
    keyed.transformKeys = keysBefore;
    if (!keysBefore.empty()) setTransformKey(keyed, keyFrame(doc), after);
    auto set = [&doc, id](const ObjectTransform& t, const std::vector<TransformKey>& keys) {
        return [&doc, id, t, keys]() -> Status {
            const uint32_t i = objectIndexOfId(doc, id);
            if (i == kNoObject) return Error{"the object is gone"};
            doc.scene.objects[i].transform = t;
            doc.scene.objects[i].animation.transformKeys = keys;
            ++doc.sceneRevision;
            return success();
        };
    };
    const std::string name = "Transform " + doc.scene.objects[object].name;
    const size_t bytes = 64 + (keysBefore.size() + keyed.transformKeys.size()) * sizeof(TransformKey);
    Result<EditReport> done = performObjectChange(doc, name, set(after, keyed.transformKeys), set(before, keysBefore), bytes, frame);
    if (!done) return done.error();
    return success();
}

Status setObjectVisible(Document& doc, uint32_t object, bool visible, uint64_t frame) {
    if (Status valid = checkObject(doc, object); !valid) return valid;
    if (doc.scene.objects[object].visible == visible) return success();
    const uint32_t id = doc.objectIds[object];
    auto set = [&doc, id](bool v) {
        return [&doc, id, v]() -> Status {
            const uint32_t i = objectIndexOfId(doc, id);
            if (i == kNoObject) return Error{"the object is gone"};
            doc.scene.objects[i].visible = v;
            ++doc.sceneRevision;
            return success();
        };
    };
    const std::string name = (visible ? "Show " : "Hide ") + doc.scene.objects[object].name;
    Result<EditReport> done = performObjectEdit(doc, name, std::make_unique<ObjectEdit>(set(visible), set(!visible), 32), frame);
    if (!done) return done.error();
    return success();
}

Status renameObject(Document& doc, uint32_t object, const std::string& name, uint64_t frame) {
    if (Status valid = checkObject(doc, object); !valid) return valid;
    const std::string old = doc.scene.objects[object].name;
    if (name == old) return success();
    if (name.empty()) return Error{"an object's name must not be empty"};
    if (findObject(doc.scene.objects, name) != UINT32_MAX) return Error{"another object is called " + inQuotes(name)};
    auto rename = [&doc](const std::string& from, const std::string& to) {
        return [&doc, from, to]() -> Status {
            const uint32_t i = findObject(doc.scene.objects, from);
            if (i == UINT32_MAX) return Error{"no object is called " + inQuotes(from)};
            doc.scene.objects[i].name = to;
            for (SceneObject& o : doc.scene.objects)
                if (o.instanceOf == from) o.instanceOf = to;
            ++doc.sceneRevision;
            return success();
        };
    };
    Result<EditReport> done = performObjectEdit(doc, "Rename " + old + " to " + name,
                                                std::make_unique<ObjectEdit>(rename(old, name), rename(name, old), 64), frame);
    if (!done) return done.error();
    return success();
}

Status deleteObject(Document& doc, uint32_t object, uint64_t frame) {
    if (Status valid = checkObject(doc, object); !valid) return valid;
    const std::vector<SceneObject>& objects = doc.scene.objects;
    const std::string& name = objects[object].name;
    if (objects.size() == 1) return Error{inQuotes(name) + " is the scene's only object"};
    for (const SceneObject& o : objects)
        if (o.instanceOf == name)
            return Error{inQuotes(o.name) + " is an instance of " + inQuotes(name) + ": delete it first, or delete " +
                         inQuotes(name) + "'s instances"};
    const uint32_t id = doc.objectIds[object];
    const bool wasSelected = doc.selectedObjectId == id;
    // Filled by the first apply: where the object was and what it was (its cage current).
    auto removed = std::make_shared<std::pair<uint32_t, SceneObject>>();
    auto apply = [&doc, id, removed]() -> Status {
        const uint32_t index = objectIndexOfId(doc, id);
        Result<SceneObject> taken = takeObject(doc, id);
        if (!taken) return taken.error();
        *removed = {index, std::move(taken).value()};
        return success();
    };
    auto revert = [&doc, id, removed, wasSelected]() -> Status {
        if (Status inserted = insertObject(doc, removed->first, removed->second, id); !inserted) return inserted;
        if (wasSelected) doc.selectedObjectId = id;
        return success();
    };
    const size_t bytes = objectBytes(objects[object], objects[object].isInstance() ? Cage{} : plannedCageOf(doc, object).cage());
    Result<EditReport> done = performObjectEdit(doc, "Delete " + name, std::make_unique<ObjectEdit>(apply, revert, bytes), frame);
    if (!done) return done.error();
    return success();
}

Result<uint32_t> duplicateObject(Document& doc, uint32_t object, bool linked, uint64_t frame) {
    if (Status valid = checkObject(doc, object); !valid) return valid.error();
    const uint32_t owner = cageOwnerOf(doc, object);
    SceneObject copy;
    copy.name = uniqueObjectName(doc.scene.objects, doc.scene.objects[object].name);
    copy.transform = besideOf(doc, object);
    copy.visible = true;
    if (linked) {
        copy.instanceOf = doc.scene.objects[owner].name;
    } else {
        const SceneObject& source = doc.scene.objects[owner];
        copy.cage = plannedCageOf(doc, object).cage();
        copy.displacement = source.displacement;
        if (hasVertexKeys(source)) {  // the cage shows a frame: the copy gets the rest and the keys
            copy.cage.positions = source.cage.positions;
            copy.animation.interpolation = source.animation.interpolation;
            copy.animation.vertexKeys = source.animation.vertexKeys;
        }
    }
    const std::string entry = (linked ? "Instance " : "Duplicate ") + doc.scene.objects[object].name;
    std::vector<SceneObject> added;
    added.push_back(std::move(copy));
    return appendObjects(doc, entry, std::move(added), frame);
}

Result<uint32_t> addObjectsFromFile(Document& doc, const std::string& path, uint64_t frame) {
    if (!doc.planned) return Error{"no scene is open"};
    std::vector<std::string> warnings;
    Result<Scene> loaded = loadSceneOrCage(path, &warnings);
    if (!loaded) return loaded.error();
    std::vector<SceneObject> added = std::move(loaded->objects);
    const bool cageFile = std::filesystem::path(path).extension() != ".json";
    std::vector<SceneObject> names = doc.scene.objects;  // the names taken so far
    for (SceneObject& o : added) {
        if (cageFile) o.name = std::filesystem::path(path).stem().string();
        const std::string wanted = uniqueObjectName(names, o.name);
        for (SceneObject& other : added)
            if (other.instanceOf == o.name) other.instanceOf = wanted;
        o.name = wanted;
        o.cagePath.clear();  // saved inline: the source file is never written
        names.push_back(SceneObject{o.name});
    }
    const std::string entry = "Add " + std::to_string(added.size()) + (added.size() == 1 ? " object" : " objects") +
                              " from " + std::filesystem::path(path).filename().string();
    return appendObjects(doc, entry, std::move(added), frame);
}

}  // namespace qp::editor
