#include "scene_schemes.h"

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "render_target.h"
#include "vk_buffer.h"

namespace qp {

DrawView objectView(const DrawView& world, const ObjectTransform& transform) {
    if (transform.isIdentity()) return world;
    const glm::mat4 model = transform.matrix();
    DrawView view = world;
    view.viewProjection = world.viewProjection * model;
    view.eye = glm::vec3(glm::inverse(model) * glm::vec4(world.eye, 1.0f));
    view.pixelsPerUnit = world.pixelsPerUnit * maxScale(transform);
    view.worldFromObject = glm::mat3(model);
    return view;
}

double SceneSchemes::setupMs() const {
    double total = 0.0;
    for (const PreparedScheme& p : cages) total += p.setupMs();
    return total;
}

Result<SceneSchemes> prepareSceneSchemes(const PluginCatalog& catalog, const std::string& name, const Scene& scene,
                                         const PlannedScene& planned, const SchemeSettings& settings,
                                         const GpuContext& gpu, const std::string& source) {
    SceneSchemes out;
    for (uint32_t c = 0; c < planned.cages.size(); ++c) {
        const SceneObject& owner = scene.objects[planned.objectOfCage[c]];
        const std::string where = scene.objects.size() == 1 ? source : source + ": object \"" + owner.name + "\"";
        const PlannedCage& cage = planned.cages[c];
        Result<PreparedScheme> prepared =
            prepareScheme(catalog, name, cage, analyzeCage(cage.cage(), cage.topology()), settings, gpu, where,
                          owner.displacement.empty() ? nullptr : &owner.displacement);
        if (!prepared) {
            (void)destroySceneSchemes(out);
            return prepared.error();
        }
        if (scene.objects.size() > 1)
            for (std::string& w : prepared->support.approximations) w = "object \"" + owner.name + "\": " + w;
        out.cages.push_back(std::move(prepared).value());
        out.bounds.push_back(computeBounds(cage.cage()));
    }
    return out;
}

namespace {

// How large an object looks: its transform's scale over its distance from the eye. The object of
// a cage that looks largest lays out the surface every object of that cage draws in the frame.
float apparentSize(const SceneObject& object, const Bounds& cage, const glm::vec3& eye) {
    const glm::vec3 centre = glm::vec3(object.transform.matrix() * glm::vec4(0.5f * (cage.min + cage.max), 1.0f));
    return maxScale(object.transform) / std::max(glm::distance(centre, eye), 1e-6f);
}

}  // namespace

Result<DrawStats> recordScene(VkCommandBuffer cmd, SceneSchemes& schemes, const Scene& scene, const PlannedScene& planned,
                              const RenderTarget& target, const DrawView& world) {
    // Cage by cage, each cage's largest-looking visible object first: the others of that cage draw
    // what it laid out (DrawView::sameFrame), so instances share one tessellation a frame, as
    // fine as their nearest needs.
    std::vector<std::vector<uint32_t>> objectsOfCage(planned.cages.size());
    for (uint32_t i = 0; i < scene.objects.size(); ++i)
        if (scene.objects[i].visible) objectsOfCage[planned.cageOfObject[i]].push_back(i);
    DrawStats total;
    bool cleared = false, trianglesKnown = true;
    for (uint32_t c = 0; c < objectsOfCage.size(); ++c) {
        std::vector<uint32_t>& objects = objectsOfCage[c];
        if (objects.size() > 1) {
            const Bounds& bounds = schemes.bounds[c];
            auto largest = std::max_element(objects.begin(), objects.end(), [&](uint32_t a, uint32_t b) {
                return apparentSize(scene.objects[a], bounds, world.eye) < apparentSize(scene.objects[b], bounds, world.eye);
            });
            std::iter_swap(objects.begin(), largest);
        }
        for (size_t k = 0; k < objects.size(); ++k) {
            const SceneObject& object = scene.objects[objects[k]];
            DrawView view = objectView(world, object.transform);
            view.clear = world.clear && !cleared;
            view.sameFrame = k > 0;
            Result<DrawStats> drawn = schemes.cages[c].instance.record(cmd, target, view);
            if (!drawn) return Error{"object \"" + object.name + "\": " + drawn.error().message};
            cleared = true;
            total.patches += drawn->patches;
            total.triangles += drawn->triangles;
            trianglesKnown = trianglesKnown && (drawn->triangles > 0 || drawn->patches == 0);
            total.drawnBy = drawn->drawnBy;
            total.cull += drawn->cull;
            total.cullMilliseconds += drawn->cullMilliseconds;
            total.sampleCulledTriangles += drawn->sampleCulledTriangles;
            total.facingAwayTriangles += drawn->facingAwayTriangles;
        }
    }
    if (!trianglesKnown) total.triangles = 0;  // the tessellator chose some counts at draw time
    if (!cleared && world.clear) {
        beginRendering(cmd, target, true, world.background);
        vkCmdEndRendering(cmd);
    }
    return total;
}

Result<SchemeFrameTimes> timeSceneFrames(const VulkanContext& context, SceneSchemes& schemes, const Scene& scene,
                                         const PlannedScene& planned, const RenderTarget& target, const DrawView& view,
                                         const GpuTimer& timer, uint32_t repeats) {
    auto update = [&]() -> Status {
        for (PreparedScheme& p : schemes.cages)
            if (Status updated = p.instance.update(); !updated) return updated;
        return success();
    };
    auto record = [&](VkCommandBuffer cmd) { return recordScene(cmd, schemes, scene, planned, target, view); };
    return timeFrames(context, update, record, timer, repeats);
}

Result<SceneCageLines> createSceneCageLines(const VulkanContext& context, const PlannedScene& planned) {
    SceneCageLines out;
    for (const PlannedCage& cage : planned.cages) {
        const std::vector<LineVertex> vertices = cageLines(cage.cage());
        Result<Buffer> buffer =
            createBuffer(context, std::max<size_t>(vertices.size(), 2) * sizeof(LineVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!buffer) {
            destroySceneCageLines(context, out);
            return buffer.error();
        }
        uploadBuffer(*buffer, vertices.data(), vertices.size() * sizeof(LineVertex));
        out.buffers.push_back(*buffer);
        out.counts.push_back(uint32_t(vertices.size()));
    }
    return out;
}

void recordSceneCageLines(VkCommandBuffer cmd, const LinePass& pass, const RenderTarget& target, const SceneCageLines& lines,
                          const Scene& scene, const PlannedScene& planned, const DrawView& world) {
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        const uint32_t c = planned.cageOfObject[i];
        if (!scene.objects[i].visible || lines.counts[c] == 0) continue;
        recordLines(cmd, pass, target, objectView(world, scene.objects[i].transform).viewProjection, lines.buffers[c],
                    lines.counts[c]);
    }
}

void destroySceneCageLines(const VulkanContext& context, SceneCageLines& lines) {
    for (Buffer& b : lines.buffers) destroyBuffer(context, b);
    lines = SceneCageLines{};
}

Status destroySceneSchemes(SceneSchemes& schemes) {
    Status status = success();
    for (PreparedScheme& p : schemes.cages)
        if (Status s = p.instance.destroyGpu(); !s && status) status = s;
    schemes.cages.clear();
    schemes.bounds.clear();
    return status;
}

}  // namespace qp
