// DocumentLoader: opens a scene or cage off the UI thread — read, plan every face — so the
// window keeps drawing (with a progress bar) while a large cage loads. The UI thread adopts
// the result; the viewports' scheme instances are built from it there (scene_renderer.h).
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "document.h"

namespace qp::editor {

struct LoadedDocument {
    std::unique_ptr<Document> document;
    std::vector<std::string> warnings;
};

struct LoadRequest {
    std::string path;              // scene (.json) or cage (.obj)
    bool fromRecovery = false;     // path is the recovery directory; the document keeps `recoveredSource`
    std::string recoveredSource;
    bool untitled = false;         // e.g. the bundled default scene: Save asks for a name
    PlanOptions options;
};

class DocumentLoader {
public:
    ~DocumentLoader();
    // Starts loading; call only when idle (not busy() and the last result taken).
    void start(LoadRequest request);
    bool busy() const;
    // What the worker is doing and how far it is through its stages (0..1).
    std::string stage() const;
    float fraction() const;
    double secondsRunning() const;
    const LoadRequest& request() const { return request_; }
    // The result once the worker has finished (then the loader is idle again).
    std::optional<Result<LoadedDocument>> take();
    // Waits for a running load and drops what it made.
    void waitAndDiscard();

private:
    void run();
    void setStage(const char* stage, float fraction);

    LoadRequest request_;
    std::thread worker_;
    mutable std::mutex mutex_;
    bool running_ = false;
    std::string stage_;
    float fraction_ = 0.0f;
    std::chrono::steady_clock::time_point started_;
    std::optional<Result<LoadedDocument>> result_;
};

}  // namespace qp::editor
