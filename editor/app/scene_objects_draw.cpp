// The objects of a scene besides the active one, in every viewport (scene_renderer.h
// OtherObjectsView). The active cage's instances are drawn by the viewport's own scheme instance
// again under their transforms (DrawView::sameFrame: the layout the active object's draw made);
// the other cages, which this editor shows but does not edit, get an instance of the viewport's
// scheme each, made when the document or the viewport's scheme or factor changes.
#include <glm/matrix.hpp>

#include "scene_renderer.h"
#include "scene_schemes.h"
#include "scheme_host.h"

namespace qp::editor {

namespace {

void destroyOthers(OtherObjectsView& view) {
    for (PreparedScheme& p : view.cages) (void)p.instance.destroyGpu();
    view.cages.clear();
}

}  // namespace

void releaseOtherObjects(const VulkanContext& ctx, SceneRenderer& r) {
    if (r.others.empty()) return;
    vkQueueWaitIdle(ctx.queue);
    for (OtherObjectsView& view : r.others) destroyOthers(view);
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
        for (size_t i = requests.size(); i < r.others.size(); ++i) destroyOthers(r.others[i]);
    }
    r.others.resize(requests.size());
    for (size_t i = 0; i < requests.size(); ++i) {
        OtherObjectsView& view = r.others[i];
        const SchemeRequest& request = requests[i];
        if (view.generation == generation && view.scheme == request.name && view.factor == request.settings.tessFactor &&
            view.adaptivePixels == request.settings.adaptivePixels)
            continue;
        if (!view.cages.empty()) vkQueueWaitIdle(ctx.queue);
        destroyOthers(view);
        view.generation = generation;
        view.scheme = request.name;
        view.factor = request.settings.tessFactor;
        view.adaptivePixels = request.settings.adaptivePixels;
        view.problem.clear();
        for (uint32_t c = 0; c < doc.otherCages.size(); ++c) {
            const PlannedCage& cage = doc.otherCages[c];
            uint32_t owner = 0;  // the object whose cage it is (instances may be listed before it)
            while (owner < doc.otherCageOfObject.size() &&
                   (doc.otherCageOfObject[owner] != c || doc.scene.objects[owner].isInstance()))
                ++owner;
            const SceneObject& object = doc.scene.objects[owner];
            Result<PreparedScheme> prepared =
                prepareScheme(catalog, request.name, cage, analyzeCage(cage.cage(), cage.topology()), request.settings, r.gpu,
                              "object \"" + object.name + "\"", object.displacement.empty() ? nullptr : &object.displacement);
            if (!prepared) {
                view.problem = prepared.error().message;
                destroyOthers(view);
                break;
            }
            view.cages.push_back(std::move(prepared).value());
        }
    }
}

void recordOtherObjects(VkCommandBuffer cmd, SceneRenderer& r, uint32_t i, const RenderTarget& area,
                        const ViewportDraw& viewport, DrawView view) {
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
            (void)r.views[i].instance->record(cmd, area, drawn);
        } else if (others && object.cage < others->cages.size()) {
            drawn.sameFrame = laidOut[object.cage];
            laidOut[object.cage] = true;
            (void)others->cages[object.cage].instance.record(cmd, area, drawn);
        }
    }
}

}  // namespace qp::editor
