#include "document_loader.h"


#include "plan_cache.h"
#include "recovery.h"

namespace qp::editor {

DocumentLoader::~DocumentLoader() {
    if (worker_.joinable()) worker_.join();
}

void DocumentLoader::waitAndDiscard() {
    if (worker_.joinable()) worker_.join();
    std::lock_guard lock(mutex_);
    result_.reset();
    running_ = false;
}

void DocumentLoader::start(LoadRequest request) {
    if (worker_.joinable()) worker_.join();
    std::lock_guard lock(mutex_);
    request_ = std::move(request);
    result_.reset();
    running_ = true;
    stage_ = "Reading";
    fraction_ = 0.0f;
    started_ = std::chrono::steady_clock::now();
    worker_ = std::thread(&DocumentLoader::run, this);
}

bool DocumentLoader::busy() const {
    std::lock_guard lock(mutex_);
    return running_;
}

std::string DocumentLoader::stage() const {
    std::lock_guard lock(mutex_);
    return stage_;
}

float DocumentLoader::fraction() const {
    std::lock_guard lock(mutex_);
    return fraction_;
}

double DocumentLoader::secondsRunning() const {
    std::lock_guard lock(mutex_);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

std::optional<Result<LoadedDocument>> DocumentLoader::take() {
    {
        std::lock_guard lock(mutex_);
        if (running_ || !result_) return std::nullopt;
    }
    if (worker_.joinable()) worker_.join();
    std::optional<Result<LoadedDocument>> result = std::move(result_);
    result_.reset();
    return result;
}

void DocumentLoader::setStage(const char* stage, float fraction) {
    std::lock_guard lock(mutex_);
    stage_ = stage;
    fraction_ = fraction;
}

void DocumentLoader::run() {
    const LoadRequest& request = request_;  // not written while running
    auto finish = [&](Result<LoadedDocument> result) {
        std::lock_guard lock(mutex_);
        result_ = std::move(result);
        running_ = false;
    };
    std::vector<std::string> warnings;
    Result<Scene> scene = request.fromRecovery ? loadRecovery(request.path, &warnings)
                                               : loadSceneOrCage(request.path, &warnings);
    if (!scene) return finish(scene.error());
    Result<std::vector<uint32_t>> owners = cageOwners(scene->objects);
    if (!owners) return finish(Error{request.path + ": " + owners.error().message});
    uint32_t faces = 0;
    for (uint32_t i = 0; i < scene->objects.size(); ++i)
        if ((*owners)[i] == i) faces += scene->objects[i].cage.faceCount();
    setStage(("Planning " + std::to_string(faces) + " faces").c_str(), 0.2f);
    const std::string documentPath = request.fromRecovery ? request.recoveredSource
                                     : request.untitled  ? std::string()
                                                         : request.path;
    std::string cacheWarning;
    std::shared_ptr<const PlanDatabase> planCache = sharedPlanCache(&cacheWarning);
    if (!cacheWarning.empty()) warnings.push_back(cacheWarning);
    Result<std::unique_ptr<Document>> document =
        createDocument(std::move(scene).value(), documentPath, request.options, std::move(planCache));
    if (!document) return finish(document.error());
    setStage("Storing the new plans", 0.9f);
    if (std::optional<std::string> why = storeNewPlans(**document)) warnings.push_back(*why);
    LoadedDocument loaded{std::move(document).value(), std::move(warnings)};
    if (request.fromRecovery) {  // restored work is still unsaved
        loaded.document->dirty = true;
        loaded.document->savedPosition.reset();
    }
    setStage("Done", 1.0f);
    finish(std::move(loaded));
}

}  // namespace qp::editor
