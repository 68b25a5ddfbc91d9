// BackgroundJob: a long file job (File > Export, File > Bake) run off the UI thread, so the
// window keeps drawing its progress bar. While it runs the editor refuses every action (the
// worker reads the document's cages, which must not change under it; runAction says so).
// The UI thread takes the result and shows it as the status line or an error.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "result.h"
#include "scene_export.h"

namespace qp::editor {

class BackgroundJob {
public:
    // The work gets a progress function to call as it goes (false back: cancelled) and returns the
    // status line to show.
    using Work = std::function<Result<std::string>(const ExportProgress& progress)>;

    ~BackgroundJob();
    // Starts `work`; call only when idle (not busy() and the last result taken).
    void start(std::string title, Work work);
    bool busy() const;
    const std::string& title() const { return title_; }
    std::string stage() const;
    float fraction() const;
    double secondsRunning() const;
    // The result once the worker has finished (then the job is idle again).
    std::optional<Result<std::string>> take();
    // Asks the work to stop at its next progress report (it then fails, having written nothing).
    void cancel() { cancelled_ = true; }
    bool cancelled() const { return cancelled_; }

private:
    std::string title_;
    std::thread worker_;
    mutable std::mutex mutex_;
    bool running_ = false;
    std::atomic<bool> cancelled_ = false;
    std::string stage_;
    float fraction_ = 0.0f;
    std::chrono::steady_clock::time_point started_;
    std::optional<Result<std::string>> result_;
};

}  // namespace qp::editor
