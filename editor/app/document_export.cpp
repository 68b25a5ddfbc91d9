#include "document_export.h"

#include <filesystem>

#include "document_objects.h"

namespace qp::editor {

SceneCages documentCages(const Document& doc) {
    SceneCages out;
    const std::vector<SceneObject>& objects = doc.scene.objects;
    // One entry per cage: the edited one first, then the others; objects map onto them.
    out.cages.push_back(&*doc.planned);
    out.objectOfCage.push_back(doc.activeObject);
    for (uint32_t c = 0; c < doc.otherCages.size(); ++c) {
        out.cages.push_back(&doc.otherCages[c]);
        out.objectOfCage.push_back(ownerOfOtherCage(doc, c));
    }
    for (uint32_t i = 0; i < objects.size(); ++i)
        out.cageOfObject.push_back(doc.otherCageOfObject[i] == kActiveCage ? 0 : doc.otherCageOfObject[i] + 1);
    return out;
}

Result<ExportReport> exportDocument(const Document& doc, const std::string& path, const ExportOptions& options) {
    if (!doc.planned) return Error{"nothing to export: no scene is open"};
    return exportScene(sceneToSave(doc), documentCages(doc), path, options, doc.path.empty() ? "untitled" : doc.path);
}

std::string proposedExportPath(const Document& doc) {
    if (doc.path.empty()) return (std::filesystem::current_path() / "untitled.glb").string();
    std::filesystem::path path(doc.path);
    return path.replace_extension(".glb").string();
}

}  // namespace qp::editor
