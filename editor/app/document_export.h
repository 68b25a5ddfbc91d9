// File > Export: the document's scene (every object, the edited cage as it is now) through
// export/scene_export.h, as `quadplan export` writes it.
#pragma once

#include <string>

#include "document.h"
#include "scene_export.h"

namespace qp::editor {

// The cages of the document's objects as exportScene takes them.
SceneCages documentCages(const Document& document);

Result<ExportReport> exportDocument(const Document& document, const std::string& path, const ExportOptions& options);

// Where File > Export proposes to write: NAME.glb beside the document's file (untitled.glb in the
// working directory).
std::string proposedExportPath(const Document& document);

}  // namespace qp::editor
