#include "background_job.h"

#include <cassert>

namespace qp::editor {

// Quitting while a job runs cancels it (it stops at its next report, writing nothing) rather than
// waiting for it; declared after the document in EditorApp, the job is gone before the document.
BackgroundJob::~BackgroundJob() {
    cancelled_ = true;
    if (worker_.joinable()) worker_.join();
}

void BackgroundJob::start(std::string title, Work work) {
    assert(!busy() && !result_);
    if (worker_.joinable()) worker_.join();
    title_ = std::move(title);
    {
        std::lock_guard lock(mutex_);
        running_ = true;
        cancelled_ = false;
        stage_ = "Starting";
        fraction_ = 0.0f;
        started_ = std::chrono::steady_clock::now();
    }
    worker_ = std::thread([this, work = std::move(work)] {
        Result<std::string> result = work([this](const std::string& stage, float fraction) {
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

bool BackgroundJob::busy() const {
    std::lock_guard lock(mutex_);
    return running_;
}

std::string BackgroundJob::stage() const {
    std::lock_guard lock(mutex_);
    return stage_;
}

float BackgroundJob::fraction() const {
    std::lock_guard lock(mutex_);
    return fraction_;
}

double BackgroundJob::secondsRunning() const {
    std::lock_guard lock(mutex_);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

std::optional<Result<std::string>> BackgroundJob::take() {
    std::lock_guard lock(mutex_);
    if (running_ || !result_) return std::nullopt;
    std::optional<Result<std::string>> out = std::move(result_);
    result_.reset();
    return out;
}

}  // namespace qp::editor
