#include "document.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "obj_io.h"

namespace qp::editor {

namespace {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

Status checkVertex(const Document& doc, uint32_t v) {
    if (v >= doc.planned->cage().vertexCount())
        return Error{"vertex " + std::to_string(v) + " does not exist (the cage has " +
                     std::to_string(doc.planned->cage().vertexCount()) + " vertices, numbered from 0)"};
    return success();
}

Status checkEdge(const Document& doc, uint32_t a, uint32_t b) {
    if (Status s = checkVertex(doc, a); !s) return s;
    if (Status s = checkVertex(doc, b); !s) return s;
    if (doc.planned->topology().findEdge(a, b) == UINT32_MAX)
        return Error{"vertices " + std::to_string(a) + " and " + std::to_string(b) + " (numbered from 0) share no edge"};
    return success();
}

Result<EditReport> apply(Document& doc, const MoveVertices& move) {
    if (move.vertices.size() != move.positions.size()) return Error{"move: one position per vertex is needed"};
    for (size_t i = 0; i < move.vertices.size(); ++i) {
        if (Status s = checkVertex(doc, move.vertices[i]); !s) return s.error();
        const glm::vec3& p = move.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return Error{"move: the new position of vertex " + std::to_string(move.vertices[i]) + " is not finite"};
    }
    Result<EditReport> report = doc.planned->moveVertices(move.vertices, move.positions);
    if (report) ++doc.positionRevision;
    return report;
}

Result<EditReport> apply(Document& doc, const SetEdgeSharpness& crease) {
    if (Status s = checkEdge(doc, crease.a, crease.b); !s) return s.error();
    if (!std::isfinite(crease.sharpness) || crease.sharpness < 0.0f)
        return Error{"edge sharpness must be a number >= 0"};
    Result<EditReport> report = doc.planned->setEdgeSharpness(crease.a, crease.b, crease.sharpness);
    if (report) ++doc.planRevision;
    return report;
}

}  // namespace

std::string describeEdit(const Edit& edit) {
    if (const auto* move = std::get_if<MoveVertices>(&edit))
        return move->vertices.size() == 1 ? "move vertex " + std::to_string(move->vertices[0])
                                          : "move " + std::to_string(move->vertices.size()) + " vertices";
    const auto& crease = std::get<SetEdgeSharpness>(edit);
    char text[96];
    std::snprintf(text, sizeof text, "sharpness of edge %u-%u = %g", crease.a, crease.b, double(crease.sharpness));
    return text;
}

Result<std::unique_ptr<Document>> createDocument(Scene scene, const std::string& path, const PlanOptions& options) {
    auto doc = std::make_unique<Document>();
    doc->database = std::make_unique<PlanDatabase>();
    Result<PlannedCage> planned = PlannedCage::create(scene.cage, *doc->database, options, path.empty() ? "cage" : path);
    if (!planned) return planned.error();
    doc->planned.emplace(std::move(planned).value());
    doc->scene = std::move(scene);
    doc->path = path;
    return doc;
}

std::string documentTitle(const Document& doc) {
    std::string name = doc.path.empty() ? "untitled" : std::filesystem::path(doc.path).filename().string();
    return doc.dirty ? name + "*" : name;
}

Result<EditReport> applyEdit(Document& doc, const Edit& edit, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    Result<EditReport> report = std::visit([&](const auto& e) { return apply(doc, e); }, edit);
    if (!report) return report;
    doc.dirty = true;
    doc.lastEdit = LastEdit{describeEdit(edit), *report, frame};
    return report;
}

Status selectVertex(Document& doc, uint32_t vertex, bool add) {
    if (Status s = checkVertex(doc, vertex); !s) return s;
    std::vector<uint32_t>& selected = doc.selection.vertices;
    if (!add) {
        doc.selection = Selection{};
        selected.push_back(vertex);
        return success();
    }
    auto at = std::lower_bound(selected.begin(), selected.end(), vertex);
    if (at != selected.end() && *at == vertex) selected.erase(at);  // toggles
    else selected.insert(at, vertex);
    return success();
}

Status selectEdge(Document& doc, uint32_t a, uint32_t b) {
    if (Status s = checkEdge(doc, a, b); !s) return s;
    doc.selection = Selection{};
    doc.selection.edge = std::make_pair(std::min(a, b), std::max(a, b));
    return success();
}

void clearSelection(Document& doc) { doc.selection = Selection{}; }

Scene sceneToSave(const Document& doc) {
    Scene scene = doc.scene;
    scene.cage = doc.planned->cage();
    return scene;
}

Status saveDocument(Document& doc, const std::string& path) {
    if (!doc.planned) return Error{"nothing to save"};
    const std::string ext = lowerExtension(path);
    Status saved = success();
    if (ext == ".obj") {
        saved = saveObj(doc.planned->cage(), path);
    } else if (ext == ".json") {
        Scene scene = sceneToSave(doc);
        saved = saveScene(scene, path, scene.cagePath.empty());
    } else {
        return Error{"cannot save as '" + path + "': the name must end in .json (scene) or .obj (cage only)"};
    }
    if (!saved) return saved;
    doc.path = path;
    doc.dirty = false;
    return success();
}

}  // namespace qp::editor
