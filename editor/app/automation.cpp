#include "automation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include "actions.h"
#include "document_objects.h"
#include "editor_app.h"
#include "mesh/file_io.h"
#include "playback.h"
#include "schemes.h"
#include "tools.h"
#include "viewport_input.h"

namespace qp::editor {

namespace {

using json = nlohmann::json;

const AutomationVocabulary& editorVocabulary() {
    static const AutomationVocabulary words{[](std::string_view id) { return findAction(id) != nullptr; }};
    return words;
}

json summaryJson(const Summary& s) { return {{"median", s.median}, {"p90", s.p90}, {"max", s.max}, {"count", s.count}}; }

}  // namespace

Result<std::vector<AutomationCommand>> parseAutomation(std::string_view text, const std::string& source) {
    return parseAutomation(text, source, editorVocabulary());
}

Result<std::unique_ptr<Automation>> loadAutomation(const std::string& path) {
    std::string text;
    if (path == "-") {
        text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    } else {
        Result<std::string> read = readFile(path);
        if (!read) return Error{"cannot read the automation script: " + read.error().message};
        text = std::move(read).value();
    }
    Result<std::vector<AutomationCommand>> commands = parseAutomation(text, path == "-" ? "<stdin>" : path);
    if (!commands) return commands.error();
    return std::make_unique<Automation>(std::move(commands).value());
}

bool Automation::busy() const {
    return waitFrames_ > 0 || waitIdle_ || !waitFile_.empty() || waitUntil_ || !pressLabel_.empty() || !screenshot_.empty() ||
           keyUpAfterFrame_ != 0 || measurement_.framesLeft > 0 || measurement_.settleFrames > 0;
}

void Automation::fail(const AutomationCommand& c, const std::string& message) {
    std::fprintf(stderr, "automation: line %d (%s): %s\n", c.line, c.name.c_str(), message.c_str());
    failed_ = true;
}

void Automation::beforeFrame(EditorApp& app) {
    if (failed_) return;
    writeFrameTimings(app);
    if (keyUpAfterFrame_) {
        std::erase(synthetic_.keysDown, keyUpAfterFrame_);
        keyUpAfterFrame_ = 0;
        return;
    }
    if (!pressLabel_.empty()) {
        if (app.ui.pressConsumed) {
            pressLabel_.clear();
            app.ui.pressLabel.clear();
        } else if (--pressFramesLeft_ <= 0) {
            AutomationCommand c{pressLine_, "click-button", {pressLabel_}};
            return fail(c, "no button, check box or menu item labelled '" + pressLabel_ + "' was shown within 60 frames");
        } else {
            return;
        }
    }
    if (!screenshot_.empty()) return;
    if (measurement_.framesLeft > 0 || measurement_.settleFrames > 0) return measureStep(app);
    if (waitFrames_ > 0 && --waitFrames_ > 0) return;
    if (waitUntil_) {
        if (std::chrono::steady_clock::now() < *waitUntil_) return;
        waitUntil_.reset();
    }
    if (waitIdle_) {
        if (app.loader.busy() || app.job.busy()) return;
        waitIdle_ = false;
    }
    if (!waitFile_.empty()) {
        if (!std::filesystem::exists(waitFile_)) {
            if (std::chrono::steady_clock::now() > waitFileDeadline_) {
                AutomationCommand c{0, "wait-file", {waitFile_}};
                return fail(c, "timed out waiting for " + waitFile_);
            }
            return;
        }
        waitFile_.clear();
    }
    while (next_ < commands_.size() && !failed_) {
        const AutomationCommand& c = commands_[next_++];
        if (!execute(app, c)) break;
    }
}

void Automation::applySyntheticInput() {
    Synthetic& s = synthetic_;
    const bool held = s.buttons[0] || s.buttons[1] || s.buttons[2] || !s.keysDown.empty();
    s.framesSinceRelease = held ? 0 : s.framesSinceRelease + 1;
    if (!s.active) return;
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(s.x, s.y);
    for (int b = 0; b < 3; ++b) io.MouseDown[b] = s.buttons[b];
    io.MouseWheel += s.wheel;
    s.wheel = 0;
    auto down = [&](int key) { return std::find(s.keysDown.begin(), s.keysDown.end(), key) != s.keysDown.end(); };
    for (int key : s.keysTouched) io.KeysDown[key] = down(key);
    io.KeyAlt = down(GLFW_KEY_LEFT_ALT);
    io.KeyCtrl = down(GLFW_KEY_LEFT_CONTROL);
    io.KeyShift = down(GLFW_KEY_LEFT_SHIFT);
    // Hand the devices back to the real ones a couple of frames after everything is released.
    if (!held && s.framesSinceRelease > 2 && s.wheel == 0) s.active = false;
}

void Automation::screenshotWritten(const std::string& path, const Status& status) {
    if (!status) {
        AutomationCommand c{0, "screenshot", {path}};
        fail(c, status.error().message);
    } else {
        std::fprintf(stderr, "automation: wrote %s\n", path.c_str());
    }
    screenshot_.clear();
}

bool Automation::execute(EditorApp& app, const AutomationCommand& c) {
    const std::string& n = c.name;
    const auto& a = c.args;
    auto integer = [&](size_t i) { return uint32_t(std::strtoul(a[i].c_str(), nullptr, 10)); };
    auto number = [&](size_t i) { return std::strtof(a[i].c_str(), nullptr); };
    auto needDocument = [&] {
        if (app.doc->planned) return true;
        fail(c, "no cage is open yet (add wait-idle before it)");
        return false;
    };
    auto report = [&](const Status& s) {
        if (!s) fail(c, s.error().message);
    };
    if (n == "wait-frames") {
        waitFrames_ = int(integer(0));
        return waitFrames_ == 0;
    }
    if (n == "wait-seconds") {
        waitUntil_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(int64_t(1000.0 * std::max(number(0), 0.0f)));
        return false;
    }
    if (n == "wait-idle") {
        waitIdle_ = true;
        return false;
    }
    if (n == "wait-file") {
        waitFile_ = a[0];
        waitFileDeadline_ = std::chrono::steady_clock::now() +
                            std::chrono::milliseconds(int64_t(1000.0 * (a.size() > 1 ? number(1) : 60.0)));
        return false;
    }
    if (n == "action") {
        runAction(app, a[0]);
        return true;
    }
    if (n == "click-button") {
        pressLabel_ = app.ui.pressLabel = a[0];
        app.ui.pressConsumed = false;
        pressFramesLeft_ = 60;
        pressLine_ = c.line;
        return false;
    }
    if (n == "open") {
        requestOpen(app, a[0]);
        return true;
    }
    if (n == "save") {
        if (needDocument()) runAction(app, "file.save");
        return true;
    }
    if (n == "save-as") {
        if (needDocument() && !saveTo(app, a[0])) fail(c, app.ui.errorMessage);
        return true;
    }
    if (n == "quit") {
        requestQuit(app);
        return false;
    }
    if (n == "autosave") {  // this frame's autosave starts at once (when there are unsaved changes)
        app.lastAutosave = std::chrono::steady_clock::time_point{};
        return false;
    }
    // A tool that refuses stops the script: its message is the status line.
    auto tool = [&](bool ok) {
        if (!ok) fail(c, app.ui.status.empty() ? app.ui.errorMessage : app.ui.status);
        return true;
    };
    if (n == "select-vertex") {
        if (needDocument()) report(selectVertex(*app.doc, integer(0), a.size() > 1));
        return true;
    }
    if (n == "select-edge") {
        if (needDocument()) report(selectEdge(*app.doc, integer(0), integer(1)));
        return true;
    }
    if (n == "clear-selection") {
        clearSelection(*app.doc);
        return true;
    }
    if (n == "select-mode") {
        setMode(app, *parseSelectionModeWord(a[0]));
        return true;
    }
    if (n == "select") {
        if (!needDocument()) return true;
        const SelectionMode mode = *parseSelectionModeWord(a[0]);
        const ElementList list = *parseElementList(a[1], mode);
        const SelectOp op = a.size() > 2 ? *parseSelectOpWord(a[2]) : SelectOp::Replace;
        report(mode == SelectionMode::Edge ? selectEdges(*app.doc, list.edges, op)
                                           : selectElements(*app.doc, mode, list.indices, op));
        return true;
    }
    if (n == "box-select") {
        if (!needDocument()) return true;
        const uint32_t v = integer(0);
        if (v >= app.viewports.size()) {
            fail(c, "there is no viewport " + a[0]);
            return true;
        }
        const float scale = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.0f;
        boxSelectIn(app, v, glm::vec2(number(1), number(2)) * scale, glm::vec2(number(3), number(4)) * scale,
                    a.size() > 5 ? *parseSelectOpWord(a[5]) : SelectOp::Replace);
        return true;
    }
    if (n == "move-selection") {
        if (!needDocument()) return true;
        const std::vector<uint32_t> vertices = selectedVertices(app.doc->selection, app.doc->planned->cage());
        if (vertices.empty()) {
            fail(c, "nothing is selected (select-vertex first)");
            return true;
        }
        MoveVertices move{vertices, {}};
        for (uint32_t v : move.vertices)
            move.positions.push_back(app.doc->planned->cage().positions[v] + glm::vec3(number(0), number(1), number(2)));
        if (!edit(app, move)) fail(c, app.ui.errorMessage);
        return true;
    }
    if (n == "set-tool") {
        runAction(app, "tool." + a[0]);
        return true;
    }
    if (n == "brush") {
        SculptSettings& s = app.tools.sculpt;
        s.kind = *brushKindFromName(a[0]);
        s.radius = number(1);
        s.strength = number(2);
        if (a.size() > 3) s.falloff = *falloffFromName(a[3]);
        if (a.size() > 4) s.mirror = *mirrorAxisFromName(a[4]);
        return true;
    }
    if (n == "displacement-resolution") {
        if (!needDocument()) return true;
        app.tools.sculpt.resolution = integer(0);
        return tool(applyDisplacementResolution(app));
    }
    if (n == "clear-displacement") return needDocument() ? tool(clearDisplacementTool(app)) : true;
    if (n == "set-space") {
        app.tools.space = a[0] == "world" ? TransformSpace::World : TransformSpace::Local;
        return true;
    }
    if (n == "transform") {
        if (!needDocument()) return true;
        const NumericTransform kind = a[0] == "move" ? NumericTransform::Move : a[0] == "rotate" ? NumericTransform::Rotate : NumericTransform::Scale;
        return tool(transformSelection(app, kind, glm::vec4(number(1), number(2), number(3), a.size() > 4 ? number(4) : 0.0f)));
    }
    if (n == "extrude") {
        if (!needDocument()) return true;
        if (!a.empty()) app.tools.extrudeDistance = number(0);
        return tool(extrudeSelection(app));
    }
    if (n == "delete") return needDocument() ? tool(deleteSelection(app)) : true;
    if (n == "split") return needDocument() ? tool(splitSelection(app)) : true;
    if (n == "loop") {
        if (!needDocument()) return true;
        if (a.empty()) return tool(loopOnSelectedEdge(app));
        return tool(insertLoop(app, integer(0), integer(1), a.size() > 2 ? number(2) : app.tools.loopFraction));
    }
    if (n == "merge") {
        if (!needDocument()) return true;
        if (!a.empty()) app.tools.mergeTarget = a[0] == "last" ? MergeTarget::Last : MergeTarget::Centroid;
        return tool(mergeSelection(app));
    }
    if (n == "make-face") return needDocument() ? tool(makeFaceFromSelection(app)) : true;
    if (n == "crease") return needDocument() ? tool(creaseSelection(app, number(0))) : true;
    if (n == "corner") return needDocument() ? tool(cornerSelection(app, number(0))) : true;
    if (n == "hole") return needDocument() ? tool(setSelectionHoles(app, a[0] == "on")) : true;
    if (n == "crease-method") {
        if (!needDocument()) return true;
        const CreaseMethod method = a[0] == "chaikin" ? CreaseMethod::Chaikin : CreaseMethod::Normal;
        if (app.doc->planned->cage().options.creaseMethod != method) tool(setCreaseMethodTool(app, method));
        return true;
    }
    if (n == "set-edge-sharpness") {
        if (!needDocument()) return true;
        if (!edit(app, SetEdgeSharpness{{{integer(0), integer(1), number(2)}}})) fail(c, app.ui.errorMessage);
        return true;
    }
    if (n == "set-frame") {
        if (!needDocument()) return true;
        pausePlayback(app);
        return tool(showFrameAt(app, std::strtod(a[0].c_str(), nullptr)));
    }
    if (n == "play" || n == "pause") {
        if (!needDocument()) return true;
        if (n == "play") startPlayback(app);
        else pausePlayback(app);
        return true;
    }
    if (n == "insert-key") return needDocument() ? tool(insertKeyTool(app)) : true;
    if (n == "set-interpolation") {
        if (!needDocument()) return true;
        return tool(setInterpolationTool(app, a[0] == "catmull-rom" ? Interpolation::CatmullRom : Interpolation::Linear));
    }
    if (n == "undo" || n == "redo") {
        if (!needDocument()) return true;
        return tool(n == "undo" ? undoTool(app) : redoTool(app));
    }
    if (n == "jump-history") return needDocument() ? tool(jumpHistoryTool(app, integer(0))) : true;
    if (n == "set-viewports") {
        const uint32_t count = integer(0);
        if (count != 1 && count != 2 && count != 4) fail(c, "the viewport count must be 1, 2 or 4");
        else setViewportCount(app, count);
        return true;
    }
    if (n == "set-scheme" || n == "set-color-by" || n == "set-cull" || n == "set-link" || n == "heatmap") {
        const uint32_t i = integer(0);
        if (i >= app.viewports.size()) {
            fail(c, "there is no viewport " + a[0] + " (" + std::to_string(app.viewports.size()) + " shown, from 0)");
            return true;
        }
        if (n == "set-scheme") {
            if (!app.catalog.find(a[1])) fail(c, "unknown scheme '" + a[1] + "'; loaded: " + app.catalog.names());
            else app.viewports[i].scheme = a[1];
        }
        if (n == "set-color-by") {
            // Each scheme lists its own modes, so the check waits until the viewport's scheme is up.
            const std::string mode = canonicalColorMode(a[1]);
            const std::vector<std::string>* modes = i < app.renderer.views.size() ? &app.renderer.views[i].colorModes : nullptr;
            if (modes && std::find(modes->begin(), modes->end(), mode) == modes->end()) {
                std::string known;
                for (const std::string& m : *modes) known += (known.empty() ? "" : ", ") + m;
                fail(c, "viewport " + a[0] + "'s scheme has no colour mode '" + a[1] + "'; it has: " + known);
            } else {
                app.viewports[i].colorBy = mode;
            }
        }
        if (n == "set-cull") {
            if (const std::optional<CullMethod> method = parseCullMethod(a[1])) app.viewports[i].cull = *method;
            else fail(c, "unknown culling method '" + a[1] + "'; use none, frustum, tcone, ncone or pplane");
        }
        if (n == "heatmap") app.viewports[i].heatMap = a[1] == "on";
        if (n == "set-link") {
            app.viewports[i].camera = app.sharedCamera;
            app.viewports[i].linked = a[1] == "linked";
        }
        return true;
    }
    if (n == "set-tessellation") {
        if (a[0] == "uniform") {
            app.tessellation.mode = TessellationMode::Uniform;
            app.tessellation.factor = std::clamp(int(number(1)), 1, 64);
        } else {
            app.tessellation.mode = TessellationMode::Adaptive;
            app.tessellation.pixelsPerEdge = std::max(number(1), 1.0f);
        }
        return true;
    }
    if (n == "set-plans-path" || n == "set-draw-path") {
        app.plansPath = a[0];
        return true;
    }
    if (n == "mouse-move" || n == "mouse-down" || n == "mouse-up" || n == "scroll" || n == "key-down" ||
        n == "key-up" || n == "key") {
        Synthetic& s = synthetic_;
        if (!s.active) {  // start from where the real pointer is
            s.x = ImGui::GetIO().MousePos.x;
            s.y = ImGui::GetIO().MousePos.y;
        }
        s.active = true;
        s.framesSinceRelease = 0;
        if (n == "mouse-move") s.x = number(0), s.y = number(1);
        if (n == "mouse-down") s.buttons[automationMouseButton(a[0])] = true;
        if (n == "mouse-up") s.buttons[automationMouseButton(a[0])] = false;
        if (n == "scroll") s.wheel += number(0);
        if (n == "key-down" || n == "key-up" || n == "key") {
            const int key = automationKeyCode(a[0]);
            if (std::find(s.keysTouched.begin(), s.keysTouched.end(), key) == s.keysTouched.end())
                s.keysTouched.push_back(key);
            std::erase(s.keysDown, key);
            if (n != "key-up") {
                s.keysDown.push_back(key);
                auto held = [&](int k) { return std::find(s.keysDown.begin(), s.keysDown.end(), k) != s.keysDown.end(); };
                app.keyPresses.push_back(
                    {key, held(GLFW_KEY_LEFT_CONTROL), held(GLFW_KEY_LEFT_SHIFT), held(GLFW_KEY_LEFT_ALT)});
            }
            if (n == "key") keyUpAfterFrame_ = key;
        }
        return false;  // one frame per input step, as a person's events arrive
    }
    if (n == "resize") {
        glfwSetWindowSize(app.window, int(integer(0)), int(integer(1)));
        waitFrames_ = 3;
        return false;
    }
    if (n == "screenshot") {
        screenshot_ = app.pendingScreenshot = a[0];
        return false;
    }
    if (n == "dump-state") {
        dumpState(app, c);
        return true;
    }
    if (n == "measure-frames") {
        if (a.size() > 2 && !needDocument()) return true;
        measurement_ = Measurement{int(integer(0)), 3, a.size() > 2 ? a[2] : std::string(), a[1], app.frame};
        app.stats.clear();
        return false;
    }
    if (n == "simulate-device-loss") {
        // What a drawFrame that returned VK_ERROR_DEVICE_LOST leads to (lavapipe cannot lose its
        // device on demand): the same handler, called from here.
        stopOnFatalError(app, "drawing failed: vkQueueSubmit: VK_ERROR_DEVICE_LOST (simulated by automation)");
        return false;
    }
    if (n == "time-frame") {
        // The next command runs in this frame (no yield), so the frame timed is the one it shows in.
        frameTimings_.push_back({a[1], a[0], app.frame});
        return true;
    }
    if (n == "log") {
        std::fprintf(stderr, "automation: %s\n", a.empty() ? "" : a[0].c_str());
        return true;
    }
    fail(c, "not implemented");
    return true;
}

void Automation::writeFrameTimings(EditorApp& app) {
    // stats.samples.back() is frame app.frame - 1; the timed frame and the one after must be in.
    const std::deque<FrameSample>& samples = app.stats.samples;
    std::erase_if(frameTimings_, [&](const FrameTiming& t) {
        if (app.frame < t.frame + 2) return false;
        const uint64_t age = app.frame - 1 - t.frame;  // of the timed frame
        json line = {{"label", t.label}, {"frame", t.frame}};
        if (age < samples.size() && age >= 1) {
            const FrameSample& shown = samples[samples.size() - 1 - age];
            const FrameSample& next = samples[samples.size() - age];
            line["cpu_ms"] = shown.cpuMs;
            line["device_wait_ms"] = shown.deviceWaitMs;
            line["interval_ms"] = next.intervalMs;
            line["scene_drawn"] = shown.sceneDrawn;
        } else {
            line["error"] = "the frame's statistics were cleared (measure-frames ran in between)";
        }
        if (app.doc && app.doc->lastEdit && app.doc->lastEdit->frame == t.frame)
            line["plan_engine_ms"] = app.doc->lastEdit->report.milliseconds;
        std::vector<json> views;
        for (const SchemeView& view : app.renderer.views)
            views.push_back({{"scheme", view.built.name}, {"plan_update_ms", view.planUpdateMs},
                             {"in_place", view.planUpdateInPlace}, {"note", view.planUpdateNote},
                             {"setup_ms", view.setupMs}});
        line["views"] = views;
        std::ofstream(t.path, std::ios::app) << line.dump() << "\n";
        return true;
    });
}

void Automation::measureStep(EditorApp& app) {
    Measurement& m = measurement_;
    if (m.framesLeft > 0) {
        --m.framesLeft;
        if (m.mode == "orbit") {
            orbit(cameraOf(app, app.activeViewport), 4.0f, 0.0f, 400.0f);
            noteCameraMoved(app);
        }
        if (m.mode == "drag" && app.doc->planned) {
            // A drag as a person does it: the selection (or vertex 0) moves a little every
            // frame, all of it one history entry.
            Document& doc = *app.doc;
            std::vector<uint32_t> vertices = selectedVertices(doc.selection, doc.planned->cage());
            if (vertices.empty()) vertices = {0};
            const float step = 0.002f * cageExtent(doc).bounds.diagonal() *
                               (((app.frame - m.firstFrame) / 20) % 2 == 0 ? 1.0f : -1.0f);
            MoveVertices move{vertices, {}, m.dragStarted};
            for (uint32_t v : vertices) move.positions.push_back(doc.planned->cage().positions[v] + glm::vec3(0, step, 0));
            m.dragStarted = edit(app, move);
        }
        if (m.mode == "sculpt" && app.doc->planned) {
            // A stroke with one dab every frame, at sample positions spread over the surface
            // (on the displaced surface, where the editor's pick puts dabs; the brush of the
            // Sculpt panel); the whole run is one history entry. The displaced picker follows
            // each dab as it does under the cursor.
            Document& doc = *app.doc;
            if (!m.dragStarted) m.dragStarted = beginStroke(doc, app.tools.sculpt.resolution, app.frame).ok();
            if (m.dragStarted) {
                const SculptSamples& samples = *doc.sculptSamples;
                uint32_t sample = uint32_t((app.frame - m.firstFrame) * 2654435761ull % samples.sampleCount());
                while (!samples.hasSite(sample)) sample = (sample + 1) % samples.sampleCount();
                const float d = displacementOf(doc).samples[sample];
                strokeDab(doc, sculptStrokeOptions(app, false, false), samples.position(sample) + d * samples.normal(sample));
                (void)displacedPicker(app.picking, doc, app.documentGeneration);
                if (m.framesLeft == 0) (void)endStroke(doc, "Measured stroke", app.frame);
            }
        }
        return;
    }
    if (--m.settleFrames > 0) return;  // GPU times arrive a frame or two later
    const size_t frames = size_t(app.frame - m.firstFrame);
    auto all = [&](FrameFilter filter) {
        return json{{"cpu_ms", summaryJson(summarize(app.stats, FrameField::Cpu, 0, filter))},
                    {"gpu_ms", summaryJson(summarize(app.stats, FrameField::Gpu, 0, filter))},
                    {"interval_ms", summaryJson(summarize(app.stats, FrameField::Interval, 0, filter))}};
    };
    json factors = json::array(), schemes = json::array();
    for (const ViewportState& v : app.viewports) factors.push_back(v.factor), schemes.push_back(v.scheme);
    json out = {{"frames", frames},
                {"all_frames", all(FrameFilter::All)},
                {"scene_drawn", all(FrameFilter::SceneDrawn)},
                {"scene_copied", all(FrameFilter::SceneCopied)},
                {"scene_drawn_full", all(FrameFilter::SceneDrawnFull)},
                {"scene_drawn_coarse", all(FrameFilter::SceneDrawnCoarse)},
                {"mode", m.mode.empty() ? "idle" : m.mode},
                {"plans_path", app.plansPath},
                {"factors", factors},
                {"schemes", schemes},
                {"last_sync_ms", app.renderer.lastSyncMs},
                {"viewports", app.viewports.size()},
                {"faces", app.doc->planned ? app.doc->planned->cage().faceCount() : 0},
                {"device", app.ctx.deviceName}};
    json triangles = json::array();
    for (const ViewportCounts& c : app.stats.viewportCounts) triangles.push_back(c.triangles);
    out["triangles"] = triangles;
    if (Status s = writeFileAtomically(m.path, out.dump(2) + "\n"); !s) {
        AutomationCommand c{0, "measure-frames", {m.path}};
        fail(c, s.error().message);
    }
    m = Measurement{};
}

}  // namespace qp::editor
