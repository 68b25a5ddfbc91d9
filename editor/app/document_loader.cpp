#include "document_loader.h"


#include "plans/plan_cache.h"
#include "recovery.h"

namespace qp::editor {

namespace {

Result<LoadedDocument> load(const LoadRequest& request, const BackgroundWork<LoadedDocument>::Progress& setStage) {
    setStage("Reading", 0.0f);
    std::vector<std::string> warnings;
    Result<Scene> scene = request.fromRecovery ? loadRecovery(request.path, &warnings)
                                               : loadSceneOrCage(request.path, &warnings);
    if (!scene) return scene.error();
    Result<std::vector<uint32_t>> owners = cageOwners(scene->objects);
    if (!owners) return Error{request.path + ": " + owners.error().message};
    uint32_t faces = 0;
    for (uint32_t i = 0; i < scene->objects.size(); ++i)
        if ((*owners)[i] == i) faces += scene->objects[i].cage.faceCount();
    setStage("Planning " + std::to_string(faces) + " faces", 0.2f);
    const std::string documentPath = request.fromRecovery ? request.recoveredSource
                                     : request.untitled  ? std::string()
                                                         : request.path;
    std::string cacheWarning;
    std::shared_ptr<const PlanDatabase> planCache = sharedPlanCache(&cacheWarning);
    if (!cacheWarning.empty()) warnings.push_back(cacheWarning);
    Result<std::unique_ptr<Document>> document =
        createDocument(std::move(scene).value(), documentPath, request.options, std::move(planCache));
    if (!document) return document.error();
    setStage("Storing the new plans", 0.9f);
    if (std::optional<std::string> why = storeNewPlans(**document)) warnings.push_back(*why);
    setStage("Preparing picking", 0.95f);
    LoadedDocument loaded{std::move(document).value(), std::move(warnings), {}};
    (void)limitPicker(loaded.picking, *loaded.document, 0);
    if (request.fromRecovery) {  // restored work is still unsaved
        loaded.document->dirty = true;
        loaded.document->savedPosition.reset();
    }
    setStage("Done", 1.0f);
    return loaded;
}

}  // namespace

void DocumentLoader::start(LoadRequest request) {
    request_ = std::move(request);
    BackgroundWork::start([this](const Progress& progress) { return load(request_, progress); });
}

}  // namespace qp::editor
