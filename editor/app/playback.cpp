#include "playback.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "document_animation.h"
#include "document_objects.h"
#include "editor_app.h"

namespace qp::editor {

namespace {

using Clock = std::chrono::steady_clock;

std::string frameText(double frame) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", frame);
    return text;
}

bool haveDocument(EditorApp& app) {
    if (app.doc->planned && !app.loader.busy()) return true;
    app.ui.status = "No scene is open (or a file is still loading).";
    return false;
}

// The achieved rate over the last second of shown frames (kept when playback stops).
void noteFrameShown(PlaybackClock& clock, Clock::time_point now) {
    clock.shown.push_back(now);
    while (clock.shown.size() > 2 && now - clock.shown.front() > std::chrono::seconds(1)) clock.shown.pop_front();
    const double span = std::chrono::duration<double>(clock.shown.back() - clock.shown.front()).count();
    if (clock.shown.size() >= 2 && span > 0.0) clock.fpsAchieved = double(clock.shown.size() - 1) / span;
}

// The object whose keys the timeline shows (keyMarks).
uint32_t markedObject(const EditorApp& app) {
    const Document& doc = *app.doc;
    if (!doc.planned) return kNoObject;
    return app.mode == EditorMode::Object ? selectedObject(doc) : doc.activeObject;
}

}  // namespace

bool showFrameAt(EditorApp& app, double frame) {
    if (!haveDocument(app)) return false;
    if (!std::isfinite(frame)) {
        app.ui.status = "Frame " + frameText(frame) + " is not a number.";
        return false;
    }
    Result<EditReport> shown = goToFrame(*app.doc, frame);
    if (!shown) {
        showError(app, "Showing frame " + frameText(frame) + " failed: " + shown.error().message);
        return false;
    }
    return true;
}

void startPlayback(EditorApp& app) {
    if (!haveDocument(app)) return;
    Document& doc = *app.doc;
    const Timeline timeline = documentTimeline(doc);
    if (doc.currentFrame < timeline.firstFrame || doc.currentFrame >= timeline.lastFrame)
        if (!showFrameAt(app, timeline.firstFrame)) return;
    doc.playing = true;
    app.playback.start = Clock::now();
    app.playback.startFrame = doc.currentFrame;
    app.playback.shown.assign(1, app.playback.start);
    app.playback.fpsAchieved = 0.0;
    app.ui.status = "Playing frames " + std::to_string(timeline.firstFrame) + "-" + std::to_string(timeline.lastFrame) + " at " +
                    frameText(timeline.framesPerSecond) + " fps (Space pauses)";
}

void pausePlayback(EditorApp& app) {
    if (!app.doc->playing) return;
    app.doc->playing = false;
    char text[96];
    std::snprintf(text, sizeof text, "Paused at frame %s (%.1f fps achieved)", frameText(app.doc->currentFrame).c_str(),
                  app.playback.fpsAchieved);
    app.ui.status = text;
}

void togglePlayback(EditorApp& app) {
    if (app.doc->playing) pausePlayback(app);
    else startPlayback(app);
}

void stepFrame(EditorApp& app, int delta) {
    if (!haveDocument(app)) return;
    pausePlayback(app);
    const Timeline t = documentTimeline(*app.doc);
    double frame = std::round(app.doc->currentFrame) + delta;
    if (app.doc->loopPlayback && frame > t.lastFrame) frame = t.firstFrame;
    if (app.doc->loopPlayback && frame < t.firstFrame) frame = t.lastFrame;
    showFrameAt(app, frame);
}

void jumpToEnd(EditorApp& app, bool last) {
    if (!haveDocument(app)) return;
    pausePlayback(app);
    const Timeline t = documentTimeline(*app.doc);
    showFrameAt(app, last ? t.lastFrame : t.firstFrame);
}

void jumpToKey(EditorApp& app, int direction) {
    if (!haveDocument(app)) return;
    pausePlayback(app);
    const std::vector<int32_t> keys = keyMarks(app);
    const double now = app.doc->currentFrame;
    auto next = direction > 0 ? std::upper_bound(keys.begin(), keys.end(), now,
                                                 [](double f, int32_t k) { return f < double(k); })
                              : std::lower_bound(keys.begin(), keys.end(), now,
                                                 [](int32_t k, double f) { return double(k) < f; });
    if (direction > 0 ? next == keys.end() : next == keys.begin()) {
        app.ui.status = std::string("No key ") + (direction > 0 ? "after" : "before") + " frame " + frameText(now);
        return;
    }
    showFrameAt(app, direction > 0 ? *next : *(next - 1));
}

bool insertKeyTool(EditorApp& app) {
    if (!haveDocument(app)) return false;
    Document& doc = *app.doc;
    if (app.mode == EditorMode::Object) {
        const uint32_t object = selectedObject(doc);
        if (Status done = insertTransformKey(doc, object, app.frame); !done) {
            app.ui.status = "Insert key: " + done.error().message;
            return false;
        }
        app.ui.status = "Keyed the transform of \"" + doc.scene.objects[object].name + "\" at frame " + std::to_string(keyFrame(doc));
        return true;
    }
    std::vector<uint32_t> vertices = selectedVertices(doc.selection, doc.planned->cage());
    if (Result<EditReport> done = insertKeys(doc, std::move(vertices), app.frame); !done) {
        showError(app, "Insert key failed: " + done.error().message);
        return false;
    }
    app.ui.status = "Insert key: " + doc.animationNote;
    return true;
}

bool deleteKeysTool(EditorApp& app) {
    if (!haveDocument(app)) return false;
    Document& doc = *app.doc;
    Status done = success();
    if (app.mode == EditorMode::Object) done = deleteTransformKey(doc, selectedObject(doc), app.frame);
    else if (Result<EditReport> deleted = deleteKeysAtFrame(doc, app.frame); !deleted) done = deleted.error();
    app.ui.status = done ? "Deleted the keys at frame " + std::to_string(keyFrame(doc)) : "Delete keys: " + done.error().message;
    return done.ok();
}

std::optional<Interpolation> timelineInterpolation(const EditorApp& app) {
    const uint32_t object = markedObject(app);
    if (object == kNoObject) return std::nullopt;
    return app.doc->scene.objects[object].animation.interpolation;
}

bool setInterpolationTool(EditorApp& app, Interpolation interpolation) {
    if (!haveDocument(app)) return false;
    Document& doc = *app.doc;
    const uint32_t object = markedObject(app);
    const char* name = interpolation == Interpolation::CatmullRom ? "Catmull-Rom" : "linear";
    if (Status done = setInterpolation(doc, object, interpolation, app.frame); !done) {
        app.ui.status = std::string("Interpolation: ") + done.error().message;
        return false;
    }
    app.ui.status = "\"" + doc.scene.objects[object].name + "\": " + name + " interpolation between keys";
    return true;
}

bool toggleInterpolationTool(EditorApp& app) {
    const std::optional<Interpolation> now = timelineInterpolation(app);
    if (!now) {
        app.ui.status = "Interpolation: no object is selected";
        return false;
    }
    return setInterpolationTool(app, *now == Interpolation::Linear ? Interpolation::CatmullRom : Interpolation::Linear);
}

std::vector<int32_t> keyMarks(const EditorApp& app) {
    const uint32_t object = markedObject(app);
    if (object == kNoObject) return {};
    return keyedFrames(app.doc->scene.objects[object].animation);
}

void advancePlayback(EditorApp& app) {
    Document& doc = *app.doc;
    if (!doc.playing) return;
    if (!doc.planned || app.loader.busy()) {
        doc.playing = false;
        return;
    }
    const Timeline t = documentTimeline(doc);
    const Clock::time_point now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - app.playback.start).count();
    // Whole frames only, as keys sit on them; those a slow frame skipped are never shown.
    double frame = app.playback.startFrame + std::floor(elapsed * t.framesPerSecond);
    if (frame > t.lastFrame) {
        if (doc.loopPlayback) {
            const double span = double(t.lastFrame - t.firstFrame + 1);
            frame = t.firstFrame + std::fmod(frame - t.firstFrame, span);
        } else {
            frame = t.lastFrame;
            doc.playing = false;
            app.ui.status = "Played to the last frame, " + std::to_string(t.lastFrame);
        }
    }
    if (frame == doc.currentFrame) return;
    if (!showFrameAt(app, frame)) {
        doc.playing = false;
        return;
    }
    noteFrameShown(app.playback, now);
}

double secondsToNextFrame(const EditorApp& app) {
    const Document& doc = *app.doc;
    if (!doc.playing) return -1.0;
    const double fps = documentTimeline(doc).framesPerSecond;
    const double elapsed = std::chrono::duration<double>(Clock::now() - app.playback.start).count();
    const double due = (std::floor(elapsed * fps) + 1.0) / fps;
    return std::max(0.0, due - elapsed);
}

}  // namespace qp::editor
