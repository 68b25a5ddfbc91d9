// Document: what the editor has open — the scene settings, the planned cage, where it came
// from and whether it has unsaved changes — and the one function every edit goes through.
//
// applyEdit is the single route from any tool, shortcut or automation command to the cage: it
// calls the PlannedCage edit (which re-plans only the affected faces), bumps the revisions the
// renderer watches, marks the document dirty and records the edit's report for the stats
// panel. Undo/redo (core/edit_history) will hook in here. Vertex indices are 0-based.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <glm/vec3.hpp>

#include "plan_database.h"
#include "planned_cage.h"
#include "scene.h"

namespace qp::editor {

struct MoveVertices {
    std::vector<uint32_t> vertices;
    std::vector<glm::vec3> positions;  // new absolute positions, one per vertex
};
struct SetEdgeSharpness {
    uint32_t a = 0, b = 0;
    float sharpness = 0.0f;  // 0 clears the crease; >= kInfiniteSharpness is infinitely sharp
};
using Edit = std::variant<MoveVertices, SetEdgeSharpness>;

std::string describeEdit(const Edit& edit);

struct Selection {
    std::vector<uint32_t> vertices;                        // sorted, unique
    std::optional<std::pair<uint32_t, uint32_t>> edge;     // (a, b), a < b
    bool empty() const { return vertices.empty() && !edge; }
};

struct LastEdit {
    std::string description;
    EditReport report;
    uint64_t frame = 0;  // frame counter when it was applied
};

struct Document {
    // Camera, viewports, tessellation; its `cage` is stale after edits: `planned` holds the cage
    // (sceneToSave puts them together).
    Scene scene;
    std::unique_ptr<PlanDatabase> database;  // heap: `planned` points at it
    std::optional<PlannedCage> planned;
    std::string path;  // file loaded from or last saved to; empty: untitled
    bool dirty = false;
    // Revisions the renderer compares with what it uploaded.
    uint64_t positionRevision = 0;  // vertex positions changed
    uint64_t planRevision = 0;      // plans or tags changed: plan buffers must be rebuilt
    Selection selection;
    std::optional<LastEdit> lastEdit;
};

// Plans `scene`'s cage into a new document (planning runs in parallel; can take seconds).
Result<std::unique_ptr<Document>> createDocument(Scene scene, const std::string& path, const PlanOptions& options);

// "name.json" or "untitled", with "*" when dirty.
std::string documentTitle(const Document& document);

// Applies the edit (see the header comment). Fails, changing nothing, on bad input: indices out
// of range, no such edge, a negative or non-finite value.
Result<EditReport> applyEdit(Document& document, const Edit& edit, uint64_t frame);

// Selection helpers (the click tools and automation both use them).
Status selectVertex(Document& document, uint32_t vertex, bool add);
Status selectEdge(Document& document, uint32_t a, uint32_t b);
void clearSelection(Document& document);

// The scene as it would be saved now: the document's scene with the current cage.
Scene sceneToSave(const Document& document);

// Saves to `path` atomically (.json: scene, with the cage inline unless the scene references
// an OBJ, which is then written too; .obj: the cage alone). On success `path` becomes the
// document's path and it is no longer dirty.
Status saveDocument(Document& document, const std::string& path);

}  // namespace qp::editor
