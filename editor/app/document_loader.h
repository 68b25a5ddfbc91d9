// DocumentLoader: opens a scene or cage off the UI thread — read, plan every face, build the
// limit-surface picker — so the window keeps drawing (with a progress bar) while a large cage
// loads, and its first visible-only pick does not stall it (1.2 s at a million faces). The UI thread adopts
// the result; the viewports' scheme instances are built from it there (scene_renderer.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "background_job.h"
#include "document.h"
#include "pick_cache.h"

namespace qp::editor {

struct LoadedDocument {
    std::unique_ptr<Document> document;
    std::vector<std::string> warnings;
    PickCache picking;  // for `document`; its generation is set when the document is adopted
};

struct LoadRequest {
    std::string path;              // scene (.json) or cage (.obj)
    bool fromRecovery = false;     // path is the recovery directory; the document keeps `recoveredSource`
    std::string recoveredSource;
    bool untitled = false;         // e.g. the bundled default scene: Save asks for a name
    PlanOptions options;
};

class DocumentLoader : public BackgroundWork<LoadedDocument> {
public:
    // Starts loading; call only when idle (not busy() and the last result taken).
    void start(LoadRequest request);
    const LoadRequest& request() const { return request_; }

private:
    LoadRequest request_;  // not written while the work runs
};

}  // namespace qp::editor
