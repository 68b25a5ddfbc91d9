// Cage animation in the editor's document (issue 22; core/animation/cage_animation.h has the keys): the
// frame shown, going to a frame, and the edits of an animated cage, each one history entry made
// by core/animation/animation_edits.h.
//
// Rest positions: each object's scene cage holds them (scene.objects[i].cage.positions), which is
// what the scene file saves. The cages the document plans (`planned`, otherCages) show the
// current frame. For the objects not in edit mode the scene cage is kept as their rest anyway;
// the active object's scene cage is stale while it is edited (document.h), so its positions are
// kept as the rest while it has vertex keys, and taken from the cage as shown when its first keys
// are set (a cage without keys shows its rest).
//
// Going to a frame moves every cage with vertex keys (core/animation/animation_playback.h showFrame: a
// vertex move, nothing re-planned) and sets every keyed object transform; the revisions the
// renderer and pickers watch follow. Edits of a cage with keys: a move keys the moved vertices
// at the current frame (rounded: keys sit on whole frames), a topology edit carries the keys to
// the new vertices; undo and redo give the keys back and show the current frame, whatever frame
// the entry was made at.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "animation/animation_edits.h"
#include "document.h"

namespace qp::editor {

// Whether the object's cage has vertex keys (then its planned cage shows a frame, not its rest).
bool hasVertexKeys(const SceneObject& object);
// The frame keys are set at: the current frame, rounded.
int32_t keyFrame(const Document& document);
// The scene's timeline (its own, or the range of its keys at 24 fps).
Timeline documentTimeline(const Document& document);

// Shows `frame` on every cage with vertex keys and every object with transform keys. The report
// adds up the cages' moves (replannedFaces stays 0) and is kept as Document::lastFrameChange.
Result<EditReport> goToFrame(Document& document, double frame);
// Re-shows the current frame on the cage `planned` of object `object` (one just planned from its
// rest: an object added, or brought back by an undo).
Status showCurrentFrameOn(Document& document, uint32_t object, PlannedCage& planned);

// applyEdit's routes for an edited cage with vertex keys (no bookkeeping: applyEdit does it).
// A move at the current frame; a `continueDrag` step of the same vertices replaces the drag's
// entry, so that one drag is one entry.
Result<EditReport> performKeyedMove(Document& document, const std::string& name, std::span<const uint32_t> vertices,
                                    std::span<const glm::vec3> positions, bool continueDrag);
// A topology edit's entry that carries the keys (`edit` made from the cage as shown,
// doc.planned->cage()), and performing it, or an entry wrapping it (a displaced topology edit).
std::unique_ptr<CustomEdit> animatedTopologyStep(Document& document, const TopologyEdit& edit);
Result<EditReport> performAnimatedTopologyEdit(Document& document, const std::string& name, std::unique_ptr<CustomEdit> step);
// Before any edit: pauses playback and moves a fractional frame to its rounding (keys sit on
// whole frames, and the entry shows the current frame after it ran). Returns what it did, for the
// status line ("" when nothing).
std::string settleFrameForEdit(Document& document);

// The I key: keys `vertices` (all when empty) of the edited cage where they are shown, at the
// current frame; the first keys make the cage animated. Alt+I: removes every vertex key at the
// current frame (an error when there is none). Each one history entry.
Result<EditReport> insertKeys(Document& document, std::vector<uint32_t> vertices, uint64_t frame);
Result<EditReport> deleteKeysAtFrame(Document& document, uint64_t frame);
// Object mode's I and Alt+I: a key of the object's transform at the current frame, or its
// removal (an error when it has none there). Each one history entry.
Status insertTransformKey(Document& document, uint32_t object, uint64_t frame);
Status deleteTransformKey(Document& document, uint32_t object, uint64_t frame);

// How object `object`'s keys (of its vertices and its transform) are interpolated, as one
// history entry that shows the current frame again, done and undone (nothing when it is so
// already). "Linear interpolation of NAME" / "Catmull-Rom interpolation of NAME".
Status setInterpolation(Document& document, uint32_t object, Interpolation interpolation, uint64_t frame);

// A new frame range and rate stored in the scene, as one history entry. Refused unless
// first <= last and 0 < fps <= 1000.
Status setTimeline(Document& document, const Timeline& timeline, uint64_t frame);

}  // namespace qp::editor
