// Viewport overlays drawn with Dear ImGui over the cached 3D picture, so hovering and dragging
// them needs no 3D redraw: the transform handle, the box of a box selection, the loop the loop
// tool would cut, the sculpt brush and mask, the readout of a drag, and the heat map's colour scale.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "document_objects.h"
#include "editor_app.h"
#include "overlays.h"
#include "surface_error.h"
#include "viewport_input.h"

namespace qp::editor {

namespace {

ImU32 rgba(float r, float g, float b, float a = 1.0f) { return ImGui::ColorConvertFloat4ToU32(ImVec4(r, g, b, a)); }

const ImU32 kAxisColors[3] = {rgba(0.92f, 0.22f, 0.2f), rgba(0.35f, 0.85f, 0.25f), rgba(0.25f, 0.5f, 1.0f)};
const ImU32 kHover = rgba(1.0f, 0.9f, 0.2f), kViewHandle = rgba(0.9f, 0.9f, 0.9f), kShadow = rgba(0, 0, 0, 0.45f);

struct ToWindow {
    glm::vec2 origin;  // viewport offset, framebuffer pixels
    float scale;       // framebuffer pixels per window pixel
    ImVec2 operator()(glm::vec2 p) const { return ImVec2((origin.x + p.x) / scale, (origin.y + p.y) / scale); }
};

float framebufferScale() {
    const ImGuiIO& io = ImGui::GetIO();
    return io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.0f;
}

void drawGizmo(ImDrawList* list, const GizmoShape& shape, const ToWindow& at, GizmoHandle hot, bool dragging) {
    auto colorOf = [&](GizmoHandle h, ImU32 base) { return h == hot ? kHover : base; };
    auto shown = [&](GizmoHandle h) { return !dragging || h == hot; };
    const ImVec2 centre = at(shape.centre);
    for (int i = 0; i < 3; ++i) {
        const GizmoHandle h = GizmoHandle(int(GizmoHandle::X) + i);
        if (!shown(h)) continue;
        const ImU32 color = colorOf(h, kAxisColors[i]);
        if (shape.mode == GizmoMode::Rotate) {
            std::vector<ImVec2> points;
            for (const glm::vec2& p : shape.ring[i]) points.push_back(at(p));
            list->AddPolyline(points.data(), int(points.size()), kShadow, 0, 4.5f);
            list->AddPolyline(points.data(), int(points.size()), color, 0, 2.5f);
            continue;
        }
        const ImVec2 end = at(shape.axisEnd[i]);
        list->AddLine(centre, end, kShadow, 5.0f);
        list->AddLine(centre, end, color, 3.0f);
        glm::vec2 direction(end.x - centre.x, end.y - centre.y);
        if (glm::length(direction) < 1.0f) continue;  // the axis points at the eye
        direction = glm::normalize(direction);
        const glm::vec2 across(-direction.y, direction.x), e(end.x, end.y);
        if (shape.mode == GizmoMode::Move) {
            const glm::vec2 tip = e + direction * 14.0f, left = e + across * 6.0f, right = e - across * 6.0f;
            list->AddTriangleFilled(ImVec2(tip.x, tip.y), ImVec2(left.x, left.y), ImVec2(right.x, right.y), color);
        } else {
            list->AddRectFilled(ImVec2(e.x - 6, e.y - 6), ImVec2(e.x + 6, e.y + 6), color);
        }
    }
    if (!shown(GizmoHandle::View)) return;
    const ImU32 view = colorOf(GizmoHandle::View, kViewHandle);
    if (shape.mode == GizmoMode::Rotate) {
        list->AddCircle(centre, shape.viewRingRadius / at.scale, kShadow, 96, 4.0f);
        list->AddCircle(centre, shape.viewRingRadius / at.scale, view, 96, 2.0f);
    } else {
        const float h = shape.centreHalf / at.scale;
        list->AddRectFilled(ImVec2(centre.x - h, centre.y - h), ImVec2(centre.x + h, centre.y + h), rgba(1, 1, 1, 0.25f));
        list->AddRect(ImVec2(centre.x - h, centre.y - h), ImVec2(centre.x + h, centre.y + h), view, 0.0f, 0, 2.0f);
    }
}

// The heat map's scale: one colour per decade (plugins/surface_error.h), labelled.
void drawHeatLegend(ImDrawList* list, const SceneHeat& heat, ImVec2 corner) {
    constexpr float kWidth = 280.0f, kHeight = 12.0f;
    const ImVec2 bar(corner.x + 10.0f, corner.y - 52.0f);
    list->AddRectFilled(ImVec2(bar.x - 6, bar.y - 22), ImVec2(bar.x + kWidth + 6, bar.y + kHeight + 30), rgba(0, 0, 0, 0.55f), 4.0f);
    const double decades = std::log10(kHeatHigh / kHeatLow);
    for (int x = 0; x < int(kWidth); ++x) {
        const double value = kHeatLow * std::pow(10.0, decades * (double(x) + 0.5) / double(kWidth));
        const glm::vec3 c = heatColorSrgb(value);
        list->AddRectFilled(ImVec2(bar.x + float(x), bar.y), ImVec2(bar.x + float(x) + 1.0f, bar.y + kHeight), rgba(c.r, c.g, c.b));
    }
    const int steps = int(std::lround(decades));
    for (int d = 0; d <= steps; ++d) {
        const float x = bar.x + kWidth * float(d) / float(steps);
        char label[16];
        std::snprintf(label, sizeof label, "1e%d", int(std::lround(std::log10(kHeatLow))) + d);
        list->AddLine(ImVec2(x, bar.y + kHeight), ImVec2(x, bar.y + kHeight + 3), rgba(1, 1, 1));
        list->AddText(ImVec2(x - 10.0f, bar.y + kHeight + 3), rgba(1, 1, 1), label);
    }
    char text[128];
    if (heat.cages > 1)
        std::snprintf(text, sizeof text, "error / diagonal, %u cages: max %.2e, rms %.2e", heat.cages, heat.maxRelError,
                      heat.rmsRelError);
    else
        std::snprintf(text, sizeof text, "error / diagonal: max %.2e, rms %.2e", heat.maxRelError, heat.rmsRelError);
    list->AddText(ImVec2(bar.x, bar.y - 18), rgba(1, 1, 1), text);
}

// The brush: a circle of its radius in the tangent plane of the displaced surface under the
// cursor, and a tick along its normal; in its stroke's colour while painting.
void drawBrushCircle(ImDrawList* list, const PickView& view, const ToWindow& at, const glm::vec3& centre,
                     const glm::vec3& normal, float radius, bool lowering, ImU32 color, float thickness) {
    const glm::vec3 t =
        glm::normalize(std::abs(normal.x) < 0.9f ? glm::cross(normal, glm::vec3(1, 0, 0)) : glm::cross(normal, glm::vec3(0, 1, 0)));
    const glm::vec3 b = glm::cross(normal, t);
    std::vector<ImVec2> points;
    constexpr int kSegments = 64;
    for (int k = 0; k < kSegments; ++k) {
        const float angle = 6.2831853f * float(k) / float(kSegments);
        const PickView::Projected p = view.project(centre + radius * (std::cos(angle) * t + std::sin(angle) * b));
        if (!p.inFront) return;
        points.push_back(at(p.pixel));
    }
    list->AddPolyline(points.data(), int(points.size()), kShadow, ImDrawFlags_Closed, thickness + 2.0f);
    list->AddPolyline(points.data(), int(points.size()), color, ImDrawFlags_Closed, thickness);
    const PickView::Projected c = view.project(centre), tip = view.project(centre + (lowering ? -0.5f : 0.5f) * radius * normal);
    if (c.inFront && tip.inFront) list->AddLine(at(c.pixel), at(tip.pixel), color, 1.5f);
}

// The brush: a circle of its radius in the tangent plane of the displaced surface under the
// cursor, a tick along its normal, in its stroke's colour while painting;
// with mirror symmetry a fainter one where the mirrored dab lands.
void drawBrush(ImDrawList* list, const EditorApp& app, const ViewportState& v, const ToWindow& at) {
    const SurfaceHit& hit = *app.ui.brushHover;
    const bool stroking = app.drag.kind == DragKind::Sculpt;
    const StrokeOptions options = stroking ? app.drag.stroke : sculptStrokeOptions(app, ImGui::GetIO().KeyCtrl, ImGui::GetIO().KeyShift);
    const PickView view{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const bool lowering = options.brush.kind == BrushKind::Lower;
    const glm::vec3 rgb = options.brush.kind == BrushKind::Raise ? glm::vec3(1.0f, 0.55f, 0.2f)
                          : lowering                             ? glm::vec3(0.35f, 0.65f, 1.0f)
                                                                 : glm::vec3(0.85f);
    const float radius = options.brush.radius;
    drawBrushCircle(list, view, at, hit.position, hit.normal, radius, lowering, rgba(rgb.r, rgb.g, rgb.b), stroking ? 2.0f : 1.5f);
    if (options.mirror == MirrorAxis::None) return;
    const int axis = int(options.mirror) - 1;
    const glm::vec3 mirrorCentre = mirrorCentreOf(*app.doc);
    glm::vec3 centre = hit.position, normal = hit.normal;
    centre[axis] = 2.0f * mirrorCentre[axis] - centre[axis];
    normal[axis] = -normal[axis];
    drawBrushCircle(list, view, at, centre, normal, radius, lowering, rgba(rgb.r, rgb.g, rgb.b, 0.5f), 1.0f);
}

// The mask: a dark square per masked sample facing the camera, alpha by its mask value. The
// camera's side is found per dot from the ray through its pixel (unprojecting the pixel at the
// near and far planes), which also holds for orthographic views.
void drawMaskDots(ImDrawList* list, const MaskDots& dots, const ViewportState& v, const ToWindow& at) {
    const PickView view{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const glm::mat4 inverse = glm::inverse(v.viewProjection);
    for (size_t k = 0; k < dots.positions.size(); ++k) {
        const glm::vec4 clip = v.viewProjection * glm::vec4(dots.positions[k], 1.0f);
        if (!(clip.w > 0.0f)) continue;
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        const glm::vec4 nearPoint = inverse * glm::vec4(ndc, 0.0f, 1.0f), farPoint = inverse * glm::vec4(ndc, 1.0f, 1.0f);
        const glm::vec3 direction = glm::vec3(farPoint) / farPoint.w - glm::vec3(nearPoint) / nearPoint.w;
        if (glm::dot(direction, dots.normals[k]) > 0.0f) continue;  // facing away
        const ImVec2 c = at((ndc + 1.0f) * 0.5f * view.size);
        list->AddRectFilled(ImVec2(c.x - 1.5f, c.y - 1.5f), ImVec2(c.x + 1.5f, c.y + 1.5f), rgba(0.05f, 0.05f, 0.12f, 0.25f + 0.65f * dots.values[k]));
    }
}

constexpr float kTriadLength = 30.0f, kTriadMargin = 44.0f;  // window pixels

// Farthest axis first, so the nearer ones are drawn over it.
void drawAxisTriad(ImDrawList* list, const glm::mat4& viewProjection, ImVec2 centre) {
    const AxisTriad triad = axisTriad(viewProjection);
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return triad.towardViewer[a] < triad.towardViewer[b]; });
    list->AddCircleFilled(centre, kTriadLength + 8.0f, rgba(0, 0, 0, 0.25f));
    for (int k : order) {
        const ImVec2 end(centre.x + kTriadLength * triad.screen[k].x, centre.y + kTriadLength * triad.screen[k].y);
        const float alpha = triad.towardViewer[k] < -0.2f ? 0.55f : 1.0f;  // pointing away: dimmer
        ImVec4 color = ImGui::ColorConvertU32ToFloat4(kAxisColors[k]);
        color.w = alpha;
        const ImU32 c = ImGui::ColorConvertFloat4ToU32(color);
        list->AddLine(centre, end, c, 2.5f);
        list->AddCircleFilled(end, 7.0f, c);
        const char label[2] = {char('X' + k), 0};
        list->AddText(ImVec2(end.x - 3.5f, end.y - 7.0f), rgba(0, 0, 0), label);
    }
}

}  // namespace

AxisTriad axisTriad(const glm::mat4& vp) {
    // The first two rows of a view-projection are the camera's right and up axes, scaled by the
    // projection (Vulkan flips y); as matcap.glsl reads them.
    const glm::vec3 right = glm::normalize(glm::vec3(vp[0][0], vp[1][0], vp[2][0]));
    const glm::vec3 up = -glm::normalize(glm::vec3(vp[0][1], vp[1][1], vp[2][1]));
    const glm::vec3 back = glm::cross(right, up);
    AxisTriad triad;
    for (int k = 0; k < 3; ++k) {
        triad.screen[k] = glm::vec2(right[k], -up[k]);
        triad.towardViewer[k] = back[k];
    }
    return triad;
}

// Object mode: the selected object's box (its cage's bounds under its transform), in orange
// as Blender outlines the selected object, so it reads at a glance which object the handle moves.
void drawSelectedObjectBox(ImDrawList* list, const EditorApp& app, const ViewportState& v, const ToWindow& at) {
    const Document& doc = *app.doc;
    const uint32_t object = doc.planned ? selectedObject(doc) : kNoObject;
    if (object == kNoObject || !doc.scene.objects[object].visible) return;
    const Bounds b = objectCageBounds(doc, object);
    const glm::mat4 matrix = doc.scene.objects[object].transform.matrix();
    const PickView view{v.worldViewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    PickView::Projected corners[8];
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 p((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z);
        corners[k] = view.project(glm::vec3(matrix * glm::vec4(p, 1.0f)));
    }
    const ImU32 orange = rgba(1.0f, 0.6f, 0.15f);
    for (int k = 0; k < 8; ++k)
        for (int axis = 1; axis < 8; axis <<= 1) {
            const int other = k | axis;
            if (other == k || !corners[k].inFront || !corners[other].inFront) continue;
            list->AddLine(at(corners[k].pixel), at(corners[other].pixel), orange, 1.5f);
        }
}

void drawViewportOverlays(EditorApp& app) {
    const float scale = framebufferScale();
    ImDrawList* list = ImGui::GetBackgroundDrawList();
    const Drag& d = app.drag;
    const bool showMask = app.ui.showMask && app.mode == EditorMode::Edit && app.tools.tool == Tool::Sculpt && app.doc;
    if (showMask) updateMaskDots(app.ui.maskDots, *app.doc, app.documentGeneration);
    for (uint32_t i = 0; i < app.viewports.size(); ++i) {
        const ViewportState& v = app.viewports[i];
        const ToWindow at{{float(v.rect.offset.x), float(v.rect.offset.y)}, scale};
        list->PushClipRect(at({0, 0}), at({float(v.rect.extent.width), float(v.rect.extent.height)}), true);
        if (const SceneHeat heat = sceneHeat(app.renderer, i); heat.valid)
            drawHeatLegend(list, heat, at({0, float(v.rect.extent.height)}));
        if (app.mode == EditorMode::Object) drawSelectedObjectBox(list, app, v, at);
        if (d.kind == DragKind::Gizmo && d.viewport == i) {
            drawGizmo(list, d.shape, at, d.handle, true);
        } else if (std::optional<GizmoShape> shape = gizmoIn(app, i)) {
            drawGizmo(list, *shape, at, i == app.activeViewport ? app.ui.gizmoHover : GizmoHandle::None, false);
        }
        if (app.tools.loopTool && i == app.activeViewport && !app.ui.loopPreview.empty()) {
            const PickView view{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
            for (size_t k = 0; k + 1 < app.ui.loopPreview.size(); k += 2) {
                const PickView::Projected a = view.project(app.ui.loopPreview[k]), b = view.project(app.ui.loopPreview[k + 1]);
                if (a.inFront && b.inFront) list->AddLine(at(a.pixel), at(b.pixel), kHover, 2.5f);
            }
        }
        if (showMask) drawMaskDots(list, app.ui.maskDots, v, at);
        if (app.ui.brushHover && app.ui.brushViewport == i) drawBrush(list, app, v, at);
        const ImVec2 corner = at({float(v.rect.extent.width), float(v.rect.extent.height)});
        drawAxisTriad(list, v.worldViewProjection, ImVec2(corner.x - kTriadMargin, corner.y - kTriadMargin));
        list->PopClipRect();
    }
    if (d.kind == DragKind::BoxSelect && glm::length(d.cursor - d.start) >= 4.0f) {
        const ImVec2 a(d.start.x / scale, d.start.y / scale), b(d.cursor.x / scale, d.cursor.y / scale);
        list->AddRectFilled(a, b, rgba(0.3f, 0.6f, 1.0f, 0.15f));
        list->AddRect(a, b, rgba(0.5f, 0.8f, 1.0f, 0.9f), 0.0f, 0, 1.5f);
    }
    if (!d.readout.empty() && (d.kind == DragKind::MoveSelection || d.kind == DragKind::Gizmo || d.kind == DragKind::Sculpt)) {
        const ImVec2 at(d.cursor.x / scale + 18.0f, d.cursor.y / scale + 8.0f);
        list->AddText(ImVec2(at.x + 1, at.y + 1), rgba(0, 0, 0), d.readout.c_str());
        list->AddText(at, rgba(1, 1, 1), d.readout.c_str());
    }
    if (app.extrude) {  // the distance beside the mouse, wherever it is
        const std::string text = extrudeReadout(*app.extrude);
        const ImVec2 mouse = ImGui::GetIO().MousePos, at(mouse.x + 18.0f, mouse.y + 8.0f);
        list->AddText(ImVec2(at.x + 1, at.y + 1), rgba(0, 0, 0), text.c_str());
        list->AddText(at, rgba(1, 1, 1), text.c_str());
    }
}

}  // namespace qp::editor
