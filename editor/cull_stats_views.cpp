#include "cull_stats_views.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "offscreen_target.h"
#include "scene/planned_scene.h"
#include "scheme_support.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

// The ID mesh's vertices of one cage (PartIdMesh): the scheme's drawn patches where it gives them,
// else its surface on the grid it draws (buildSubfaceGrid at its factor; displacedSchemeMesh's
// grids for a displaced object), each vertex numbered by its sub-face. No builder shares a vertex
// between parts, so every triangle has one number.
Result<std::vector<IdVertex>> idVertices(const SchemeInstance& scheme, const PlannedCage& cage, const Displacement& displacement,
                                         uint32_t factor, std::vector<uint32_t>& indices, PartIdMesh& parts) {
    std::vector<IdVertex> vertices;
    Result<PatchTriangles> patches = scheme.drawnPatches();
    if (!patches) return patches.error();
    if (!patches->indices.empty()) {
        parts.patches = true;
        parts.parts = patches->patchCount;
        vertices.resize(patches->positions.size());
        for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {patches->positions[i], patches->patchOfVertex[i]};
        indices = std::move(patches->indices);
        return vertices;
    }
    parts.parts = cage.subfaceCount();
    if (!displacement.empty()) {
        Result<DisplacedMesh> mesh =
            displacedSchemeMesh(scheme.scheme(), cage, displacement, displacedGridFactor(cage, displacement, factor));
        if (!mesh) return mesh.error();
        vertices.resize(mesh->positions.size());
        for (size_t g = 0; g < mesh->gridSubface.size(); ++g) {
            const uint32_t side = mesh->gridFactor[g] + 1;
            for (uint32_t k = 0; k < side * side; ++k)
                vertices[mesh->gridOffset[g] + k] = {mesh->positions[mesh->gridOffset[g] + k], mesh->gridSubface[g]};
        }
        indices = std::move(mesh->indices);
        return vertices;
    }
    const SubfaceGrid grid = buildSubfaceGrid(cage, factor);
    std::vector<SurfacePoint> points(grid.samples.size());
    if (Status evaluated = scheme.evaluate(grid.samples, points); !evaluated) return evaluated.error();
    vertices.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) vertices[i] = {points[i].position, grid.samples[i].subface};
    indices = grid.indices;
    return vertices;
}

// Pixels whose RGBA differ.
uint64_t differingPixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size()) / 4;
    uint64_t count = 0;
    for (size_t i = 0; i < a.size(); i += 4)
        count += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2] || a[i + 3] != b[i + 3];
    return count;
}

// Per part of `cage`'s ID mesh, the pixels it owns in `object`'s ID buffer.
Result<std::vector<uint32_t>> pixelsPerPart(HeadlessScene& h, const CullStatsRig& rig, uint32_t cage, const DrawView& object) {
    const PartIdMesh& parts = rig.meshes[cage];
    std::vector<uint32_t> owns(parts.parts, 0);
    if (parts.mesh.indexCount == 0) return owns;
    const RenderTarget target = renderTarget(*h.target);
    if (Status drawn = submitAndWait(h.ctx, [&](VkCommandBuffer cmd) {
            recordIdPass(cmd, rig.pass, target, object.viewProjection, true, parts.mesh);
        });
        !drawn)
        return drawn.error();
    Result<std::vector<uint8_t>> pixels = readPixels(h.ctx, *h.target);
    if (!pixels) return pixels.error();
    for (size_t i = 0; i < pixels->size(); i += 4)
        if (const uint32_t id = decodeId(pixels->data() + i); id < owns.size()) ++owns[id];
    return owns;
}

// Each object drawn alone with each method, the parts it reports culled (patches or sub-faces,
// as its ID mesh numbers them) checked against the object's ID buffer (objects without a cage of
// their own use their source's).
Status checkCulledParts(HeadlessScene& h, CullStatsRig& rig, const Scene& scene, const PlannedScene& planned,
                        const DrawView& view, ViewMeasurement& out) {
    const RenderTarget target = renderTarget(*h.target);
    for (uint32_t o = 0; o < scene.objects.size(); ++o) {
        if (!scene.objects[o].visible) continue;
        const uint32_t cage = planned.cageOfObject[o];
        DrawView object = objectView(view, scene.objects[o].transform);
        Result<std::vector<uint32_t>> owns = pixelsPerPart(h, rig, cage, object);
        if (!owns) return owns.error();
        out.visibleParts += uint64_t(owns->size() - size_t(std::count(owns->begin(), owns->end(), 0u)));
        const bool patches = rig.meshes[cage].patches;
        for (size_t m = 0; m < kMeasuredCullMethods.size(); ++m) {
            std::vector<uint32_t> culled;
            object.cull = kMeasuredCullMethods[m];
            object.culledSubfacesOut = patches ? nullptr : &culled;
            object.culledPatchesOut = patches ? &culled : nullptr;
            Result<DrawStats> drawn = DrawStats{};
            if (Status submitted = submitAndWait(h.ctx, [&](VkCommandBuffer cmd) {
                    drawn = h.schemes->cages[cage].instance.record(cmd, target, object);
                });
                !submitted)
                return submitted;
            if (!drawn) return drawn.error();
            MethodInView& result = out.methods[1 + m];
            result.culledParts += culled.size();
            for (uint32_t part : culled)
                if (part < owns->size() && (*owns)[part] > 0) result.visibleCulledParts.push_back({o, part, patches, (*owns)[part]});
        }
    }
    return success();
}

}  // namespace

std::vector<RenderCamera> sphereCameras(const Bounds& bounds, uint32_t count, float aspect) {
    std::vector<RenderCamera> cameras;
    const float golden = 3.14159265f * (3.0f - std::sqrt(5.0f));
    for (uint32_t k = 0; k < count; ++k) {
        const float y = 1.0f - 2.0f * (float(k) + 0.5f) / float(count), r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const glm::vec3 direction{r * std::cos(golden * float(k)), y, r * std::sin(golden * float(k))};
        RenderCamera camera = frameBounds(bounds.min, bounds.max, aspect);
        camera.eye = camera.target + glm::length(camera.eye - camera.target) * direction;
        // lookAt needs an up vector that is not along the view direction (the poles).
        camera.up = std::abs(direction.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        cameras.push_back(camera);
    }
    return cameras;
}

Result<CullStatsRig> createCullStatsRig(HeadlessScene& h, const Scene& scene, const PlannedScene& planned, uint32_t tessFactor) {
    CullStatsRig rig;
    Result<IdPass> pass = createIdPass(h.ctx, h.gpu.cache, h.gpu.colorFormat, h.gpu.depthFormat);
    if (!pass) return Error{"cannot set up the ID buffer: " + pass.error().message};
    rig.pass = *pass;
    Result<GpuTimer> timer = createGpuTimer(h.ctx);
    if (!timer) return Error{"cannot time frames on this device: " + timer.error().message};
    rig.timer = *timer;
    for (uint32_t c = 0; c < planned.cages.size(); ++c) {
        const PlannedCage& cage = planned.cages[c];
        std::vector<uint32_t> indices;
        PartIdMesh parts;
        Result<std::vector<IdVertex>> vertices = idVertices(h.schemes->cages[c].instance, cage,
                                                            scene.objects[planned.objectOfCage[c]].displacement, tessFactor,
                                                            indices, parts);
        if (vertices && parts.parts > kMaxId + 1) {
            destroyCullStatsRig(h.ctx, rig);
            return Error{"the cage has " + std::to_string(parts.parts) + (parts.patches ? " patches" : " sub-faces") +
                         "; an ID buffer holds at most " + std::to_string(kMaxId + 1)};
        }
        Result<IdMesh> mesh = !vertices              ? Result<IdMesh>(vertices.error())
                              : vertices->empty()    ? Result<IdMesh>(IdMesh{})
                                                     : uploadIdMesh(h.ctx, *vertices, indices);
        if (!mesh) {
            destroyCullStatsRig(h.ctx, rig);
            return Error{"cannot build the ID buffer's mesh: " + mesh.error().message};
        }
        parts.mesh = *mesh;
        rig.meshes.push_back(parts);
    }
    return rig;
}

void destroyCullStatsRig(const VulkanContext& ctx, CullStatsRig& rig) {
    for (PartIdMesh& parts : rig.meshes)
        if (parts.mesh.indexCount) destroyIdMesh(ctx, parts.mesh);
    rig.meshes.clear();
    if (rig.timer.pool) destroyGpuTimer(ctx, rig.timer);
    destroyIdPass(ctx, rig.pass);
}

Result<ViewMeasurement> measureView(HeadlessScene& h, CullStatsRig& rig, const Scene& scene, const PlannedScene& planned,
                                    const DrawView& view, uint32_t repeats) {
    ViewMeasurement out;
    const RenderTarget target = renderTarget(*h.target);
    std::vector<uint8_t> unculled;
    // A hair: 1e-4 of the scene's size (not of the eye's distance from the origin, which a small
    // model far from it would make larger than the model).
    const Bounds bounds = sceneBounds(scene, planned);
    const glm::vec3 hair(1e-4f * glm::length(bounds.max - bounds.min));
    for (size_t m = 0; m < out.methods.size(); ++m) {
        DrawView culled = view;
        culled.cull = m == 0 ? CullMethod::None : kMeasuredCullMethods[m - 1];
        // Every other frame sees the scene moved by a hair, so that what depends on the view (the
        // patch tests, plans' triangle tests) runs in every timed frame, as while the camera
        // moves; the last frame, whose pixels are compared, sees the view itself.
        DrawView moved = culled;
        moved.viewProjection = view.viewProjection * glm::translate(glm::mat4(1.0f), hair);
        moved.eye = view.eye - hair;
        uint32_t k = 0;  // the frame being recorded: 0 the warm-up, `repeats` the last
        Result<SchemeFrameTimes> times = timeFrames(
            h.ctx, [] { return success(); },
            [&](VkCommandBuffer cmd) {
                const bool exact = (repeats - k++) % 2 == 0;
                return recordScene(cmd, *h.schemes, scene, planned, target, exact ? culled : moved);
            },
            rig.timer, repeats);
        if (!times) return times.error();
        Result<std::vector<uint8_t>> pixels = readPixels(h.ctx, *h.target);
        if (!pixels) return pixels.error();
        MethodInView& result = out.methods[m];
        result.draw = times->draw;
        result.frameMs = times->frameMs;
        result.gpuMs = times->drawMs;
        if (m == 0) unculled = std::move(*pixels);
        else result.differingPixels = differingPixels(unculled, *pixels);
    }
    if (Status checked = checkCulledParts(h, rig, scene, planned, view, out); !checked) return checked.error();
    return out;
}

}  // namespace qp::cli
