// Work off the UI thread, so the window keeps drawing its progress bar: opening a document
// (document_loader.h) and File > Export and Bake (BackgroundJob). The work reports its stage and
// the fraction done as it goes; the UI thread polls them and takes the result when it is done.
// While an export or bake runs the editor refuses every action (the worker reads the document's
// cages, which must not change under it; runAction says so).
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "mesh/result.h"

namespace qp::editor {

template <typename T>
class BackgroundWork {
public:
    // Called by the work as it goes; false back means the user cancelled (the work then stops at
    // its next report, writing nothing). The same type as export/scene_export.h's ExportProgress.
    using Progress = std::function<bool(const std::string& stage, float fraction)>;
    using Work = std::function<Result<T>(const Progress& progress)>;

    // A destroyed worker is cancelled (work that looks) and waited for.
    ~BackgroundWork() {
        cancelled_ = true;
        if (worker_.joinable()) worker_.join();
    }
    // Starts `work`; call only when idle (not busy() and the last result taken).
    void start(Work work) {
        if (worker_.joinable()) worker_.join();
        {
            std::lock_guard lock(mutex_);
            result_.reset();
            running_ = true;
            cancelled_ = false;
            stage_ = "Starting";
            fraction_ = 0.0f;
            started_ = std::chrono::steady_clock::now();
        }
        worker_ = std::thread([this, work = std::move(work)] {
            Result<T> result = work([this](const std::string& stage, float fraction) {
                std::lock_guard lock(mutex_);
                stage_ = stage;
                fraction_ = fraction;
                return !cancelled_;
            });
            std::lock_guard lock(mutex_);
            result_ = std::move(result);
            running_ = false;
        });
    }
    bool busy() const {
        std::lock_guard lock(mutex_);
        return running_;
    }
    std::string stage() const {
        std::lock_guard lock(mutex_);
        return stage_;
    }
    float fraction() const {
        std::lock_guard lock(mutex_);
        return fraction_;
    }
    double secondsRunning() const {
        std::lock_guard lock(mutex_);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    }
    // The result once the work has finished (then the worker is idle again).
    std::optional<Result<T>> take() {
        {
            std::lock_guard lock(mutex_);
            if (running_ || !result_) return std::nullopt;
        }
        if (worker_.joinable()) worker_.join();
        std::optional<Result<T>> out = std::move(result_);
        result_.reset();
        return out;
    }
    // Waits for running work and drops what it made.
    void waitAndDiscard() {
        if (worker_.joinable()) worker_.join();
        std::lock_guard lock(mutex_);
        result_.reset();
        running_ = false;
    }
    void cancel() { cancelled_ = true; }
    bool cancelled() const { return cancelled_; }

private:
    std::thread worker_;
    mutable std::mutex mutex_;
    bool running_ = false;
    std::atomic<bool> cancelled_ = false;
    std::string stage_;
    float fraction_ = 0.0f;
    std::chrono::steady_clock::time_point started_;
    std::optional<Result<T>> result_;
};

// File > Export or Bake: the work returns the status line to show. Declared after the document in
// EditorApp, so quitting while it runs cancels it before the document goes.
class BackgroundJob : public BackgroundWork<std::string> {
public:
    void start(std::string title, Work work) {
        title_ = std::move(title);
        BackgroundWork::start(std::move(work));
    }
    const std::string& title() const { return title_; }

private:
    std::string title_;
};

}  // namespace qp::editor
