// The objects of the editor's scene (object mode and the outliner): which cage edit mode acts
// on, which object is picked, and the edits of whole objects — transform, visibility, name,
// delete, duplicate, instance, add from a file — each one entry of the document's single undo
// history (document.h performObjectEdit), beside the cage edits.
//
// The Document keeps one cage in edit mode (`planned`, the active object's) and every other
// object's cage planned in `otherCages` through the same plan database. editObjectCage swaps
// the two (the plans go with their cage, nothing is re-planned); undo and redo of a cage edit
// made on another object first move edit mode back to it (editCageOfTag), as Blender's undo
// does. Adding or removing objects re-links instances to their cages and plans only a cage that
// is new (from the database: a duplicate adds no plans). Indices are 0-based object indices of
// document.scene.objects; messages name the objects.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "document.h"

namespace qp::editor {

inline constexpr uint32_t kNoObject = UINT32_MAX;

// The index of the object with this id, or kNoObject.
uint32_t objectIndexOfId(const Document& document, uint32_t id);
// The object whose cage `object` draws: itself, or where its instance links end.
uint32_t cageOwnerOf(const Document& document, uint32_t object);
// The object owning Document::otherCages[cage].
uint32_t ownerOfOtherCage(const Document& document, uint32_t cage);
// The cage `object` draws (the edited one for the active object and its instances).
const PlannedCage& plannedCageOf(const Document& document, uint32_t object);
// Its bounds in the object's own coordinates.
Bounds objectCageBounds(const Document& document, uint32_t object);
// The object picked in object mode, or kNoObject.
uint32_t selectedObject(const Document& document);
void selectObject(Document& document, uint32_t object);  // kNoObject: none

// Makes the cage `object` draws the one edit mode acts on (its owner's, for an instance). The
// selection, hidden faces and the brushes' samples are the old cage's and are cleared; not a
// history entry (a change of what is edited, not of the scene).
Status editObjectCage(Document& document, uint32_t object);
// For undo and redo: moves edit mode to the cage of the object with id `tag` (0: none needed).
Status editCageOfTag(Document& document, uint32_t tag);

// An object edit as one history entry: `apply` runs now and on redo, `revert` on undo; both
// change the document's objects (or the scene's settings), never the cage edit mode is on.
Result<EditReport> performObjectChange(Document& document, const std::string& name, std::function<Status()> apply,
                                       std::function<Status()> revert, size_t bytes, uint64_t frame);

// Object edits, each one history entry (or nothing and an error).
// A transform whose drag already showed it: `before` is where the drag started (undo returns
// there), the object is at `after` when it returns. An object with transform keys gets `after`
// keyed at the current frame in the same entry (else the next frame would take it back).
Status setObjectTransform(Document& document, uint32_t object, const ObjectTransform& before,
                          const ObjectTransform& after, uint64_t frame);
Status setObjectVisible(Document& document, uint32_t object, bool visible, uint64_t frame);
// Instance links to it follow the new name; refused when empty or taken.
Status renameObject(Document& document, uint32_t object, const std::string& name, uint64_t frame);
// Refused for the last object and while other objects instance it. Deleting the object edit
// mode is on moves edit mode to another cage first.
Status deleteObject(Document& document, uint32_t object, uint64_t frame);
// A copy beside it ("name.001"): with `linked`, an instance sharing its cage (Blender's Alt+D);
// otherwise a cage of its own, a copy of the one it draws, with its displacement and vertex keys
// (Shift+D; not its transform keys, which would put it back on the original).
// Returns the new object's index; it becomes the selected object.
Result<uint32_t> duplicateObject(Document& document, uint32_t object, bool linked, uint64_t frame);
// Every object of a scene file, or one object for a cage file (named after the file), with
// their instance links renamed with them; returns the index of the first added.
Result<uint32_t> addObjectsFromFile(Document& document, const std::string& path, uint64_t frame);

}  // namespace qp::editor
