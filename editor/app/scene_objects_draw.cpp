// The objects of a scene besides the active one, in every viewport (scene_renderer.h
// OtherObjectsView). The active cage's instances are drawn by the viewport's own scheme instance
// again under their transforms (DrawView::sameFrame: the layout the active object's draw made);
// the cages not in edit mode get an instance of the viewport's scheme each (and, in heat-map
// mode, its error heat map), made when the document, edit mode's cage or the viewport's scheme,
// factor or heat map changes; when an animation moves those cages, the instances and heat maps
// take the moved vertices as an edited cage's do.
#include <algorithm>
#include <cmath>

#include <glm/matrix.hpp>

#include "document_objects.h"
#include "scene_renderer.h"
#include "scene_schemes.h"
#include "scheme_host.h"

namespace qp::editor {

namespace {

void destroyOthers(const VulkanContext& ctx, OtherObjectsView& view) {
    for (PreparedScheme& p : view.cages) (void)p.instance.destroyGpu();
    view.cages.clear();
    for (HeatMap& heat : view.heat) destroyHeat(ctx, heat);
    view.heat.clear();
    view.positions.clear();
}

// The other cages moved (an animation frame): each instance and heat map re-evaluates what its
// moved vertices touch. The caller drained the queue.
void updateMovedOthers(const VulkanContext& ctx, OtherObjectsView& view, const Document& doc, uint32_t heatFactor) {
    for (uint32_t c = 0; c < view.cages.size() && c < doc.otherCages.size(); ++c) {
        const std::vector<glm::vec3>& now = doc.otherCages[c].cage().positions;
        if (view.positions[c].size() != now.size()) continue;  // a rebuild follows a new topology
        const std::vector<uint32_t> moved = movedVertices(view.positions[c], now);
        if (moved.empty()) continue;
        view.positions[c] = now;
        const std::string name = "object \"" + doc.scene.objects[ownerOfOtherCage(doc, c)].name + "\"";
        if (Status s = view.cages[c].instance.updateMoved(moved); !s) {
            view.problem = name + ": " + s.error().message;
            destroyOthers(ctx, view);
            return;
        }
        if (c < view.heat.size())
            if (Status s = updateHeatMap(ctx, doc.otherCages[c], view.cages[c].instance, heatFactor, view.heat[c], &moved); !s) {
                view.problem = name + ": heat map: " + s.error().message;
                destroyOthers(ctx, view);
                return;
            }
        ++view.drawRevision;
    }
}


}  // namespace

void releaseOtherObjects(const VulkanContext& ctx, SceneRenderer& r) {
    if (r.others.empty()) return;
    vkQueueWaitIdle(ctx.queue);
    for (OtherObjectsView& view : r.others) destroyOthers(ctx, view);
    r.others.clear();
}

void syncOtherObjects(const VulkanContext& ctx, SceneRenderer& r, const PluginCatalog& catalog, const Document& doc,
                      uint64_t generation, std::span<const SchemeRequest> requests) {
    r.objects.clear();
    for (uint32_t i = 0; i < doc.scene.objects.size() && i < doc.otherCageOfObject.size(); ++i)
        r.objects.push_back({doc.scene.objects[i].transform, doc.otherCageOfObject[i], i == doc.activeObject,
                             doc.scene.objects[i].visible});
    if (r.others.size() > requests.size()) {
        vkQueueWaitIdle(ctx.queue);
        for (size_t i = requests.size(); i < r.others.size(); ++i) destroyOthers(ctx, r.others[i]);
    }
    r.others.resize(requests.size());
    for (size_t i = 0; i < requests.size(); ++i) {
        OtherObjectsView& view = r.others[i];
        const SchemeRequest& request = requests[i];
        if (view.generation == generation && view.scheme == request.name && view.factor == request.settings.tessFactor &&
            view.adaptivePixels == request.settings.adaptivePixels && view.heatMap == request.heatMap &&
            (!request.heatMap || view.heatFactor == request.heatFactor)) {
            if (view.positionRevision != doc.otherPositionRevision && !view.cages.empty()) {
                vkQueueWaitIdle(ctx.queue);
                updateMovedOthers(ctx, view, doc, request.heatFactor);
            }
            view.positionRevision = doc.otherPositionRevision;
            continue;
        }
        if (!view.cages.empty()) vkQueueWaitIdle(ctx.queue);
        destroyOthers(ctx, view);
        view.generation = generation;
        view.scheme = request.name;
        view.factor = request.settings.tessFactor;
        view.adaptivePixels = request.settings.adaptivePixels;
        view.heatMap = request.heatMap;
        view.heatFactor = request.heatFactor;
        view.problem.clear();
        view.positionRevision = doc.otherPositionRevision;
        ++view.drawRevision;
        for (uint32_t c = 0; c < doc.otherCages.size(); ++c) {
            const PlannedCage& cage = doc.otherCages[c];
            const SceneObject& object = doc.scene.objects[ownerOfOtherCage(doc, c)];
            const std::string name = "object \"" + object.name + "\"";
            Result<PreparedScheme> prepared =
                prepareScheme(catalog, request.name, cage, analyzeCage(cage.cage(), cage.topology()), request.settings, r.gpu,
                              name, object.displacement.empty() ? nullptr : &object.displacement);
            if (!prepared) {
                view.problem = prepared.error().message;
                destroyOthers(ctx, view);
                break;
            }
            view.cages.push_back(std::move(prepared).value());
            view.positions.push_back(cage.cage().positions);
            if (!request.heatMap) continue;
            // Measured whole once; animation frames update it where the cage moved.
            view.heat.emplace_back();
            if (Status s = updateHeatMap(ctx, cage, view.cages.back().instance, request.heatFactor, view.heat.back(), nullptr); !s) {
                view.problem = name + ": heat map: " + s.error().message;
                destroyOthers(ctx, view);
                break;
            }
        }
    }
}

void recordOtherObjects(VkCommandBuffer cmd, SceneRenderer& r, uint32_t i, const RenderTarget& area,
                        const ViewportDraw& viewport, DrawView view, ViewportCounts& counts) {
    view.viewProjection = viewport.worldViewProjection;
    view.eye = viewport.worldEye;
    view.pixelsPerUnit = viewport.worldPixelsPerUnit;
    view.hiddenSubfaces = {};  // hidden faces are the active cage's
    view.clear = false;
    OtherObjectsView* others = i < r.others.size() ? &r.others[i] : nullptr;
    std::vector<bool> laidOut(others ? others->cages.size() : 0, false);
    for (const ObjectDraw& object : r.objects) {
        if (object.active || !object.visible) continue;
        DrawView drawn = objectView(view, object.transform);
        if (object.cage == kActiveCage) {
            drawn.sameFrame = true;  // the active object's draw laid the surface out
            if (Result<DrawStats> stats = r.views[i].instance->record(cmd, area, drawn)) addCullStats(counts, *stats);
        } else if (others && object.cage < others->cages.size()) {
            drawn.sameFrame = laidOut[object.cage];
            laidOut[object.cage] = true;
            if (Result<DrawStats> stats = others->cages[object.cage].instance.record(cmd, area, drawn))
                addCullStats(counts, *stats);
        }
    }
}

}  // namespace qp::editor

namespace qp::editor {

void recordOtherHeatMaps(VkCommandBuffer cmd, SceneRenderer& r, uint32_t i, const RenderTarget& area,
                         const ViewportDraw& viewport, const DisplayOptions& options) {
    const OtherObjectsView* others = i < r.others.size() ? &r.others[i] : nullptr;
    for (const ObjectDraw& object : r.objects) {
        if (object.active || !object.visible) continue;
        const HeatMap* heat = object.cage == kActiveCage ? &r.views[i].heat
                              : others && object.cage < others->heat.size() ? &others->heat[object.cage]
                                                                             : nullptr;
        if (!heat || !heat->valid || !heat->mesh.indexCount) continue;
        const glm::mat4 matrix = object.transform.matrix();
        const glm::vec3 eye = glm::vec3(glm::inverse(matrix) * glm::vec4(viewport.worldEye, 1.0f));
        MeshView view{viewport.worldViewProjection * matrix, eye, options.background, options.shading};
        view.clear = false;
        const MeshDraw draw{&heat->mesh, glm::vec3(0.8f), true, options.wireframe};
        recordMeshPass(cmd, r.heatPass, area, view, std::span<const MeshDraw>(&draw, 1));
    }
}

SceneHeat sceneHeat(const SceneRenderer& r, uint32_t i) {
    SceneHeat total;
    double sumSquares = 0.0;
    auto add = [&](const HeatMap& heat) {
        if (!heat.valid) return;
        total.valid = true;
        ++total.cages;
        total.maxRelError = std::max(total.maxRelError, heat.maxRelError);
        sumSquares += heat.rmsRelError * heat.rmsRelError * double(heat.relError.size());
        total.samples += heat.relError.size();
    };
    if (i < r.views.size()) add(r.views[i].heat);
    if (i < r.others.size())
        for (const HeatMap& heat : r.others[i].heat) add(heat);
    total.rmsRelError = total.samples ? std::sqrt(sumSquares / double(total.samples)) : 0.0;
    return total;
}

}  // namespace qp::editor
