#include "scene_renderer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <tbb/task_group.h>

#include "edit/transform.h"
#include "ground_grid.h"
#include "plans/face_config.h"
#include "scheme_host.h"
#include "surface_error.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp::editor {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

constexpr VkQueryPipelineStatisticFlags kStatistics =
    VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_PRIMITIVES_BIT | VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT;

const glm::vec3 kSelectedColor(1.0f, 0.35f, 0.0f), kSelectedEdgeColor(0.0f, 0.85f, 1.0f);
const glm::vec3 kVertexDotColor(0.02f, 0.02f, 0.02f), kHoleColor(0.35f, 0.45f, 0.75f);
constexpr float kCageDepthBias = 0.002f, kOverlayDepthBias = 0.004f;

// Writes `vertices` into `buffer`, growing it when needed (the caller made sure it is idle).
Status fillLineBuffer(const VulkanContext& ctx, Buffer& buffer, uint32_t& count, const std::vector<LineVertex>& vertices) {
    const VkDeviceSize bytes = std::max<VkDeviceSize>(vertices.size(), 2) * sizeof(LineVertex);
    if (buffer.size < bytes) {
        destroyBuffer(ctx, buffer);
        Result<Buffer> created = createBuffer(ctx, bytes * 2, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!created) return created.error();
        buffer = *created;
    }
    if (!vertices.empty()) uploadBuffer(buffer, vertices.data(), vertices.size() * sizeof(LineVertex));
    count = uint32_t(vertices.size());
    return success();
}

void cross(std::vector<LineVertex>& lines, const glm::vec3& p, float size, const glm::vec3& color) {
    for (int axis = 0; axis < 3; ++axis) {
        glm::vec3 offset(0.0f);
        offset[axis] = size;
        lines.push_back({p - offset, color});
        lines.push_back({p + offset, color});
    }
}

// A polyline on the limit surface: `at(t)` gives (sub-face, u, v) for t in [0, 1].
template <class At>
void limitCurve(const PlannedCage& planned, At at, int segments, const glm::vec3& color, std::vector<LineVertex>& lines) {
    glm::vec3 previous(0.0f);
    bool havePrevious = false;
    for (int i = 0; i <= segments; ++i) {
        const auto [subface, u, v] = at(float(i) / float(segments));
        if (!planned.hasSurface(subface)) {
            havePrevious = false;
            continue;
        }
        const glm::vec3 p = planned.evaluate(subface, u, v).position;
        if (havePrevious) {
            lines.push_back({previous, color});
            lines.push_back({p, color});
        }
        previous = p;
        havePrevious = true;
    }
}

struct SubfacePoint {
    uint32_t subface;
    float u, v;
};

// The limit curve over edge k (corner k to k + 1) of face f: the boundary of its limit patch.
void limitEdgeCurve(const PlannedCage& planned, uint32_t f, uint32_t k, const glm::vec3& color, std::vector<LineVertex>& lines) {
    const uint32_t n = planned.cage().faceSize(f), first = planned.firstSubface(f);
    constexpr int kSegments = 8;
    if (n == 4) {
        limitCurve(planned, [&](float t) {
            const float uv[4][2] = {{t, 0.0f}, {1.0f, t}, {1.0f - t, 1.0f}, {0.0f, 1.0f - t}};
            return SubfacePoint{first, uv[k][0], uv[k][1]};
        }, kSegments, color, lines);
        return;
    }
    // n-gon: sub-face k holds the first half (corner 0 to 1), sub-face k + 1 the second (corner 3 to 0).
    limitCurve(planned, [&](float t) { return SubfacePoint{first + k, t, 0.0f}; }, kSegments / 2, color, lines);
    limitCurve(planned, [&](float t) { return SubfacePoint{first + (k + 1) % n, 0.0f, 1.0f - t}; }, kSegments / 2, color, lines);
}

// A selected face: its limit patch's outline and a few iso-lines across it, so the highlight
// lies on the surface whichever scheme draws it.
void limitFaceHatch(const PlannedCage& planned, uint32_t f, const glm::vec3& color, std::vector<LineVertex>& lines) {
    const uint32_t n = planned.cage().faceSize(f), first = planned.firstSubface(f);
    for (uint32_t k = 0; k < n; ++k) limitEdgeCurve(planned, f, k, color, lines);
    const std::vector<float> levels = n == 4 ? std::vector<float>{0.25f, 0.5f, 0.75f} : std::vector<float>{0.5f};
    for (uint32_t s = first; s < first + subfaceCount(n); ++s)
        for (float level : levels) {
            limitCurve(planned, [&](float t) { return SubfacePoint{s, level, t}; }, 6, color, lines);
            limitCurve(planned, [&](float t) { return SubfacePoint{s, t, level}; }, 6, color, lines);
        }
}

// Selection, corners, holes and (in vertex mode) every vertex, drawn over the cage.
std::vector<LineVertex> overlayLines(const Document& doc) {
    std::vector<LineVertex> lines;
    const PlannedCage& planned = *doc.planned;
    const Cage& cage = planned.cage();
    const Topology& topology = planned.topology();
    const float size = 0.012f * std::max(cageExtent(doc).bounds.diagonal(), 1e-3f);
    const Selection& s = doc.selection;
    if (s.mode == SelectionMode::Vertex && cage.vertexCount() <= 20000)
        for (const glm::vec3& p : cage.positions) cross(lines, p, 0.25f * size, kVertexDotColor);
    for (uint32_t f : cage.holes) {  // a hole: its diagonals, from each corner to the centre
        if (isFaceHidden(doc, f)) continue;
        const glm::vec3 centre = centroid(cage, std::span<const uint32_t>(cage.faceBegin(f), cage.faceSize(f)));
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) {
            lines.push_back({glm::mix(cage.positions[cage.faceBegin(f)[k]], centre, 0.15f), kHoleColor});
            lines.push_back({glm::mix(cage.positions[cage.faceBegin(f)[k]], centre, 0.85f), kHoleColor});
        }
    }
    for (const VertexCorner& c : cage.corners)  // a corner: a star in its sharpness's colour
        if (c.vertex < cage.vertexCount() && !isVertexHidden(doc, c.vertex)) cross(lines, cage.positions[c.vertex], 1.3f * size, sharpnessRampColor(c.sharpness));
    for (uint32_t v : s.vertices)
        if (v < cage.vertexCount()) cross(lines, cage.positions[v], size, kSelectedColor);
    for (const EdgeKey& e : s.edges) {
        const uint32_t edge = e.v1 < cage.vertexCount() ? topology.findEdge(e.v0, e.v1) : UINT32_MAX;
        if (edge == UINT32_MAX) continue;
        lines.push_back({cage.positions[e.v0], kSelectedEdgeColor});
        lines.push_back({cage.positions[e.v1], kSelectedEdgeColor});
        // ... and the limit curve it shapes (through the first face that has it)
        const uint32_t f = topology.edgeFaces[topology.edgeFaceOffsets[edge]];
        for (uint32_t k = 0; k < cage.faceSize(f); ++k)
            if (topology.faceEdges[cage.faceOffsets[f] + k] == edge) {
                limitEdgeCurve(planned, f, k, kSelectedEdgeColor, lines);
                break;
            }
    }
    for (uint32_t f : s.faces) {
        if (f >= cage.faceCount()) continue;
        const uint32_t n = cage.faceSize(f);
        for (uint32_t k = 0; k < n; ++k) {  // the cage face's outline
            lines.push_back({cage.positions[cage.faceBegin(f)[k]], kSelectedColor});
            lines.push_back({cage.positions[cage.faceBegin(f)[(k + 1) % n]], kSelectedColor});
        }
        limitFaceHatch(planned, f, kSelectedColor, lines);
    }
    return lines;
}

// The cage's edges to draw: all but those only hidden faces have (an empty function: all).
std::function<bool(uint32_t)> shownEdges(const Document& doc) {
    if (doc.hiddenFaces.empty()) return {};
    return [&doc](uint32_t e) {
        const Topology& topology = doc.planned->topology();
        return !isEdgeHidden(doc, makeEdgeKey(topology.edgeVertices[2 * e], topology.edgeVertices[2 * e + 1]));
    };
}

// One set of the cage's lines into its buffer: the lines that changed, or all of it when it
// is new or outgrew the buffer.
Status syncLineSet(const VulkanContext& ctx, Buffer& buffer, uint32_t& count, const std::vector<LineVertex>& set,
                   std::vector<uint32_t>& changed, bool& whole) {
    const VkDeviceSize bytes = std::max<VkDeviceSize>(set.size(), 2) * sizeof(LineVertex);
    if (whole || buffer.size < bytes) {
        if (Status s = fillLineBuffer(ctx, buffer, count, set); !s) return s;
    } else {
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
        for (uint32_t line : changed)
            if (2 * size_t(line) < set.size())
                uploadBuffer(buffer, &set[2 * size_t(line)], 2 * sizeof(LineVertex), 2 * size_t(line) * sizeof(LineVertex));
        count = uint32_t(set.size());
    }
    changed.clear();
    whole = false;
    return success();
}

// The sub-faces of the hidden faces, sorted (DrawView::hiddenSubfaces).
std::vector<uint32_t> hiddenSubfacesOf(const Document& doc) {
    std::vector<uint32_t> subfaces;
    const PlannedCage& planned = *doc.planned;
    for (uint32_t f : doc.hiddenFaces) {
        if (f >= planned.cage().faceCount()) continue;
        const uint32_t first = planned.firstSubface(f);
        for (uint32_t s = first; s < first + subfaceCount(planned.cage().faceSize(f)); ++s) subfaces.push_back(s);
    }
    return subfaces;  // faces are sorted and own consecutive sub-faces in face order
}

// Lines are drawn depth-tested against the surface; this pulls them toward the eye by a small
// constant in normalized depth so lines on or just under the surface (the highlight's limit
// curves, cage edges where the surface bulges out) still show. The screen position is unchanged.
glm::mat4 withDepthBias(const glm::mat4& viewProjection, float bias) {
    glm::mat4 shift(1.0f);
    shift[3][2] = -bias;  // z_clip - bias * w
    return shift * viewProjection;
}

std::string selectionKey(const Document& doc) {
    const Selection& s = doc.selection;
    std::string key(1, char(s.mode));
    key.append(reinterpret_cast<const char*>(s.vertices.data()), s.vertices.size() * sizeof(uint32_t));
    key.push_back('|');
    key.append(reinterpret_cast<const char*>(s.edges.data()), s.edges.size() * sizeof(EdgeKey));
    key.push_back('|');
    key.append(reinterpret_cast<const char*>(s.faces.data()), s.faces.size() * sizeof(uint32_t));
    return key;
}

// The plans' GPU paths evaluate in compute passes that rewrite buffers the previous frame's
// (or viewport's) draws read: those reads must finish first. Harmless for the other schemes.
void barrierBeforeEvaluation(VkCommandBuffer cmd) {
    memoryBarrier(cmd,
                  VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
                      VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                      VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

bool sameSettings(const SchemeSettings& a, const SchemeSettings& b) {
    return a.tessFactor == b.tessFactor && a.adaptivePixels == b.adaptivePixels && a.planDepth == b.planDepth &&
           a.options == b.options;
}


void destroyView(const VulkanContext& ctx, SchemeView& view) {
    if (view.instance) (void)view.instance->destroyGpu();
    view.instance.reset();
    destroyHeat(ctx, view.heat);
}

const Displacement* drawnDisplacement(const Document& doc) {
    return displacementOf(doc).empty() ? nullptr : &displacementOf(doc);
}

// A new displacement (or none) for an instance, or samples changed in place.
Status syncDisplacement(SchemeView& view, const Document& doc, bool newDisplacement,
                        std::span<const uint32_t> changedSamples) {
    if (newDisplacement) {
        if (Status s = view.instance->setDisplacement(drawnDisplacement(doc)); !s) return s;
        return view.instance->update();
    }
    if (displacementOf(doc).empty() || changedSamples.empty()) return success();
    return view.instance->displacementChanged(changedSamples);
}

// A new instance for the request (failures become view.problem).
void buildView(SceneRenderer& r, const PluginCatalog& catalog, const Document& doc, SchemeView& view,
               const SchemeRequest& request) {
    const VulkanContext& ctx = *r.gpu.vulkan;
    destroyView(ctx, view);
    view.built = request;
    view.problem.clear();
    view.support = SupportReport{};
    view.colorModes = {"shading"};
    ++view.drawRevision;
    const auto start = Clock::now();
    if (r.featuresStale) {  // only builds read them: an edit taken in place need not scan the cage
        r.features = analyzeCage(doc.planned->cage(), doc.planned->topology());
        r.featuresStale = false;
    }
    Result<PreparedScheme> prepared = prepareScheme(catalog, request.name, *doc.planned, r.features, request.settings,
                                                    r.gpu, doc.path.empty() ? "the cage" : doc.path,
                                                    drawnDisplacement(doc));
    view.setupMs = msSince(start);
    if (!prepared) {
        view.problem = prepared.error().message;
        return;
    }
    view.support = prepared->support;
    view.instance.emplace(std::move(prepared->instance));
    if (Result<std::vector<std::string>> modes = view.instance->colorModes(); modes && !modes->empty())
        view.colorModes = *modes;
}

// Keeps `view`'s instance for later (evicting the oldest parked one); `view` is left empty.
void park(const VulkanContext& ctx, SceneRenderer& r, const Document& doc, SchemeView& view) {
    if (!view.instance) return destroyView(ctx, view);
    if (r.parked.size() == kMaxParkedInstances) {
        destroyView(ctx, r.parked.front().view);
        r.parked.erase(r.parked.begin());
    }
    destroyHeat(ctx, view.heat);
    r.parked.push_back({std::move(view), doc.positionRevision, doc.displacementRevision, doc.sampleRevision});
    view = SchemeView{};
}

// Parked instances of another document, or made before the plans or the displacement changed,
// show what no longer is: destroyed (the device is idle).
void dropStaleParked(const VulkanContext& ctx, SceneRenderer& r, const Document& doc, uint64_t generation) {
    std::erase_if(r.parked, [&](ParkedInstance& p) {
        const bool stale = p.view.generation != generation || p.view.planRevision != doc.planRevision ||
                           p.displacementRevision != doc.displacementRevision || p.sampleRevision != doc.sampleRevision;
        if (stale) destroyView(ctx, p.view);
        return stale;
    });
}

// A parked instance for `request` into `view` (brought to the current positions): true when
// there was one.
bool unpark(SceneRenderer& r, const Document& doc, uint64_t generation, const SchemeRequest& request, SchemeView& view) {
    for (auto p = r.parked.begin(); p != r.parked.end(); ++p) {
        if (p->view.built.name != request.name || !sameSettings(p->view.built.settings, request.settings) ||
            p->view.generation != generation || p->view.planRevision != doc.planRevision ||
            p->displacementRevision != doc.displacementRevision || p->sampleRevision != doc.sampleRevision)
            continue;
        const auto start = Clock::now();
        if (p->positionRevision != doc.positionRevision)
            if (Status s = p->view.instance->update(); !s) return false;  // stays parked; dropped as stale later
        view = std::move(p->view);
        r.parked.erase(p);
        view.setupMs = msSince(start);
        view.planUpdateNote = "reused (the viewport showed it before)";
        ++view.drawRevision;
        return true;
    }
    return false;
}

// A tag or topology edit for an instance that may take it in place: true when it did
// (Scheme::updatePlans); false when it must be rebuilt, planUpdateNote saying why.
bool updatePlansInPlace(SchemeView& view, const Document& doc, const EditReport& change) {
    const auto start = Clock::now();
    const std::vector<uint32_t> subfaces = changedSubfaces(*doc.planned, change);
    Result<PlanUpdate> updated =
        view.instance->updatePlans(PlanChange{subfaces, change.topologyChanged, change.previousSubfaceOf});
    view.planUpdateMs = msSince(start);
    view.planUpdateInPlace = updated && *updated == PlanUpdate::Updated;
    if (view.planUpdateInPlace) {
        view.planUpdateNote = "in place, " + std::to_string(subfaces.size()) + " sub-faces";
        ++view.drawRevision;
        return true;
    }
    view.planUpdateNote = !updated ? "rebuilt: the update in place failed (" + updated.error().message + ")"
                          : !view.instance->updatesPlansInPlace() ? "rebuilt (the scheme does not update plans in place)"
                          : change.topologyChanged && !view.instance->updatesTopologyInPlace()
                              ? "rebuilt (the scheme rebuilds after topology edits)"
                              : "rebuilt (the scheme asked for it)";
    if (!updated) std::fprintf(stderr, "%s: %s\n", view.built.name.c_str(), view.planUpdateNote.c_str());
    return false;
}

// Heat map of the view's scheme over the edited cage.
Status updateHeat(const VulkanContext& ctx, const Document& doc, SchemeView& view, const std::vector<uint32_t>* moved) {
    if (Status s = updateHeatMap(ctx, *doc.planned, *view.instance, view.built.heatFactor, view.heat, moved); !s) return s;
    ++view.drawRevision;
    return success();
}

}  // namespace

void destroyHeat(const VulkanContext& ctx, HeatMap& heat) {
    if (heat.mesh.indexCount) destroyMesh(ctx, heat.mesh);
    heat = HeatMap{};
}

Status updateHeatMap(const VulkanContext& ctx, const PlannedCage& planned, SchemeInstance& instance, uint32_t factor,
                     HeatMap& heat, const std::vector<uint32_t>* moved) {
    const auto start = Clock::now();
    const bool whole = !moved || !heat.valid;
    if (whole) {
        destroyHeat(ctx, heat);
        heat.grid = buildSubfaceGrid(planned, std::max(1u, factor));
        heat.index = VertexSubfaceIndex(planned, heat.grid.subfaces);
        heat.relError.assign(heat.grid.samples.size(), 0.0f);
    }
    std::vector<uint32_t> touched;  // positions in heat.grid.subfaces
    std::vector<SampleRequest> samples;
    if (whole) {
        samples = heat.grid.samples;
    } else {
        touched = heat.index.touched(*moved);
        for (uint32_t i : touched)
            samples.insert(samples.end(), heat.grid.samples.begin() + heat.grid.firstSample[i],
                           heat.grid.samples.begin() + heat.grid.firstSample[i + 1]);
    }
    std::vector<SurfacePoint> points(samples.size());
    if (!samples.empty())
        if (Status s = instance.evaluate(samples, points); !s) return s;
    const double diagonal = std::max(double(computeBounds(planned.cage()).diagonal()), 1e-12);
    const SurfaceError error = measureSurfaceError(planned, samples, points, diagonal);
    std::vector<MeshVertex> vertices = meshVertices(points);
    std::vector<glm::vec3> colors(points.size());
    for (size_t k = 0; k < points.size(); ++k) colors[k] = heatColorLinear(error.relError[k]);
    if (whole) {
        heat.relError = error.relError;
        if (!vertices.empty()) {
            Result<GpuMesh> mesh = uploadMesh(ctx, vertices, heat.grid.indices, colors);
            if (!mesh) return mesh.error();
            heat.mesh = *mesh;
        }
        heat.lastSubfaces = uint32_t(heat.grid.subfaces.size());
    } else {  // rewrite the touched ranges in place (the caller waited for the device)
        auto* mappedVertices = static_cast<MeshVertex*>(heat.mesh.vertices.data);
        auto* mappedColors = static_cast<glm::vec3*>(heat.mesh.colors.data);
        size_t k = 0;
        for (uint32_t i : touched)
            for (uint32_t j = heat.grid.firstSample[i]; j < heat.grid.firstSample[i + 1]; ++j, ++k) {
                heat.relError[j] = error.relError[k];
                if (mappedVertices) mappedVertices[j] = vertices[k];
                if (mappedColors) mappedColors[j] = colors[k];
            }
        heat.lastSubfaces = uint32_t(touched.size());
    }
    double sumSquares = 0.0, maximum = 0.0;
    for (float e : heat.relError) {
        sumSquares += double(e) * double(e);
        maximum = std::max(maximum, double(e));
    }
    heat.maxRelError = maximum;
    heat.rmsRelError = heat.relError.empty() ? 0.0 : std::sqrt(sumSquares / double(heat.relError.size()));
    heat.valid = true;
    heat.lastMs = msSince(start);
    return success();
}


glm::vec3 sharpnessRampColor(float sharpness) {
    const float t = std::min(sharpness / kInfiniteSharpness, 1.0f);
    return glm::mix(glm::vec3(1.0f, 0.85f, 0.1f), glm::vec3(0.9f, 0.05f, 0.02f), t);
}

Result<SceneRenderer> createSceneRenderer(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat) {
    SceneRenderer r;
    r.gpu = GpuContext{&ctx, cache, colorFormat, VK_FORMAT_D32_SFLOAT};
    Result<LinePass> lines = createLinePass(ctx, cache, colorFormat);
    if (!lines) return lines.error();
    r.lines = *lines;
    Result<MeshPass> heat = createMeshPass(ctx, cache, colorFormat);
    if (!heat) {
        destroySceneRenderer(ctx, r);
        return heat.error();
    }
    r.heatPass = *heat;
    if (ctx.features.pipelineStatisticsQuery) {
        for (VkQueryPool& pool : r.statistics) {
            VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
            info.queryCount = kMaxViewports;
            info.pipelineStatistics = kStatistics;
            if (VkResult result = vkCreateQueryPool(ctx.device, &info, nullptr, &pool); result != VK_SUCCESS) {
                destroySceneRenderer(ctx, r);
                return vkError("vkCreateQueryPool", result);
            }
        }
    }
    return r;
}

void releaseSchemes(const VulkanContext& ctx, SceneRenderer& r) {
    releaseOtherObjects(ctx, r);
    if (r.views.empty() && r.parked.empty()) return;
    vkQueueWaitIdle(ctx.queue);
    for (SchemeView& view : r.views) destroyView(ctx, view);
    for (ParkedInstance& p : r.parked) destroyView(ctx, p.view);
    r.views.clear();
    r.parked.clear();
    r.generation = r.planRevision = r.positionRevision = r.displacementRevision = r.sampleRevision = ~0ull;
}

void destroySceneRenderer(const VulkanContext& ctx, SceneRenderer& r) {
    releaseSchemes(ctx, r);
    destroyBuffer(ctx, r.cageLines);
    destroyBuffer(ctx, r.creaseLines);
    destroyBuffer(ctx, r.gridLines);
    destroyBuffer(ctx, r.overlayLines);
    for (VkQueryPool pool : r.statistics)
        if (pool) vkDestroyQueryPool(ctx.device, pool, nullptr);
    if (r.lines.pipeline) destroyLinePass(ctx, r.lines);
    if (r.heatPass.layout) destroyMeshPass(ctx, r.heatPass);
    r = SceneRenderer{};
}

Status syncScene(const VulkanContext& ctx, SceneRenderer& r, const PluginCatalog& catalog, const Document& doc,
                 uint64_t generation, std::span<const SchemeRequest> requests, std::span<const uint32_t> changedSamples,
                 const EditReport& planChange, const DisplayOptions& display) {
    r.lastDeviceWaitMs = 0.0;
    if (!doc.planned) return success();
    const Cage& cage = doc.planned->cage();
    const bool newDocument = r.generation != generation;
    const bool newPlans = newDocument || r.planRevision != doc.planRevision;
    // Rebuilt instances get the displacement as they are made; the others keep theirs.
    const bool newDisplacement = newDocument || r.displacementRevision != doc.displacementRevision;
    const bool newSamples = !newDisplacement && r.sampleRevision != doc.sampleRevision;
    const bool newPositions = newPlans || r.positionRevision != doc.positionRevision;
    const bool newHidden = newPlans || r.hiddenRevision != doc.hiddenRevision;
    std::vector<uint32_t> moved;
    // One drag step behind: its vertices; further behind, those whose positions differ.
    const bool oneStep = !newDocument && doc.lastMove.leads(r.positionRevision, doc.positionRevision) &&
                         r.positions.size() == cage.positions.size();
    if (oneStep) moved = doc.lastMove.vertices;
    else if (newPositions && !newDocument && !planChange.topologyChanged && r.positions.size() == cage.positions.size())
        moved = movedVertices(r.positions, cage.positions);
    const std::string overlay = selectionKey(doc);

    // Decide first, so the device is drained once and only when something changes.
    std::vector<SchemeView> closed;  // views of viewports that went away: parked below
    for (size_t i = requests.size(); i < r.views.size(); ++i) closed.push_back(std::move(r.views[i]));
    r.views.resize(requests.size());
    std::vector<char> rebuild(requests.size()), replan(requests.size()), heatWhole(requests.size()), heatOff(requests.size());
    // The grid follows the scene's bounds in the world, which tag edits and most topology edits
    // leave alone.
    const std::optional<Bounds> bounds = newPlans ? std::optional<Bounds>(documentBounds(doc)) : std::nullopt;
    const bool newGrid = r.gridUp != display.up || (bounds && (bounds->min != r.gridBounds.min || bounds->max != r.gridBounds.max));
    bool work = newPositions || newDisplacement || newSamples || newGrid || newHidden || overlay != r.overlayKey ||
                !closed.empty();
    for (size_t i = 0; i < requests.size(); ++i) {
        const SchemeView& view = r.views[i];
        const SchemeRequest& want = requests[i];
        rebuild[i] = newDocument || view.generation != generation || want.name != view.built.name ||
                     !sameSettings(want.settings, view.built.settings) || (newPlans && !view.instance);
        replan[i] = !rebuild[i] && newPlans;
        heatWhole[i] = want.heatMap && (rebuild[i] || !view.heat.valid || want.heatFactor != view.built.heatFactor);
        heatOff[i] = !want.heatMap && view.heat.valid;
        work |= rebuild[i] || replan[i] || heatWhole[i] || heatOff[i];
    }
    if (!work) {  // the edited cage's views are as they were; objects may have moved or come and gone
        syncOtherObjects(ctx, r, catalog, doc, generation, requests);
        return success();
    }

    const auto waitStart = Clock::now();
    VK_CHECK(vkQueueWaitIdle(ctx.queue));
    r.lastDeviceWaitMs = msSince(waitStart);
    const auto start = Clock::now();
    // The cage's lines drawn anew (a topology edit renumbers every edge) on another core while
    // the viewports update: they share nothing but the document, which neither changes.
    const Topology& topology = doc.planned->topology();
    CageLines& lines = r.cageLineCache;
    const bool newLines = (newPositions || newHidden) &&
                          (newDocument || planChange.topologyChanged || r.hiddenRevision != doc.hiddenRevision ||
                           lines.lineOf.size() != topology.edgeCount() || r.positions.size() != cage.positions.size());
    tbb::task_group lineWork;
    if (newLines) lineWork.run([&] { rebuildCageLines(lines, cage, topology, shownEdges(doc)); });
    if (newPlans) r.featuresStale = true;
    for (SchemeView& view : closed) park(ctx, r, doc, view);
    if (newPlans && !newDocument)  // parked instances that can take the edit in place stay usable
        for (ParkedInstance& p : r.parked)
            if (p.view.generation == generation && p.view.planRevision == r.planRevision &&
                updatePlansInPlace(p.view, doc, planChange))
                p.view.planRevision = doc.planRevision;
    dropStaleParked(ctx, r, doc, generation);
    for (size_t i = 0; i < requests.size(); ++i) {
        SchemeView& view = r.views[i];
        if (replan[i] && !updatePlansInPlace(view, doc, planChange)) rebuild[i] = true;
        if (rebuild[i] && !newDocument && !replan[i] && view.instance) park(ctx, r, doc, view);  // another scheme or settings
        if (rebuild[i] && !replan[i] && unpark(r, doc, generation, requests[i], view)) {
            rebuild[i] = false;
        } else if (rebuild[i]) {
            const auto buildStart = Clock::now();
            buildView(r, catalog, doc, view, requests[i]);
            view.generation = generation;
            view.planRevision = doc.planRevision;
            if (replan[i]) view.planUpdateMs = msSince(buildStart);
        } else if (replan[i]) {
            view.planRevision = doc.planRevision;
        }
        if (!rebuild[i] && !moved.empty() && view.instance) {
            const auto updateStart = Clock::now();
            if (Status s = view.instance->updateMoved(moved); !s) {
                view.problem = s.error().message;
                destroyView(ctx, view);
            }
            view.updateMs = msSince(updateStart);
            view.updatedVertices = uint32_t(moved.size());
            ++view.drawRevision;
        }
        if (!rebuild[i] && view.instance && (newDisplacement || newSamples)) {
            const auto updateStart = Clock::now();
            if (Status s = syncDisplacement(view, doc, newDisplacement, changedSamples); !s) {
                view.problem = s.error().message;
                destroyView(ctx, view);
            }
            view.displacementMs = msSince(updateStart);
            view.updatedSamples = newDisplacement ? uint32_t(displacementOf(doc).samples.size()) : uint32_t(changedSamples.size());
            ++view.drawRevision;
        }
        view.built.heatMap = requests[i].heatMap;
        view.built.heatFactor = requests[i].heatFactor;
        if (heatOff[i] || !view.instance) {
            if (view.heat.valid) ++view.drawRevision;
            destroyHeat(ctx, view.heat);
        } else if (requests[i].heatMap && (heatWhole[i] || replan[i] || !moved.empty())) {
            // After new plans the error may change wherever the surface did: measured again whole.
            const bool whole = heatWhole[i] || replan[i];
            if (Status s = updateHeat(ctx, doc, view, whole ? nullptr : &moved); !s) {
                view.problem = "heat map: " + s.error().message;
                destroyHeat(ctx, view.heat);
            }
        }
    }
    lineWork.wait();
    if (newPositions || newHidden) {
        // Moves and tag edits rewrite the lines they touched; anything else draws them anew (above).
        if (!newLines) {
            if (newPlans) retagCageLines(lines, cage, topology, planChange.replannedFaceList);
            moveCageLines(lines, cage, topology, moved);
        }
        if (Status s = syncLineSet(ctx, r.cageLines, r.cageLineCount, lines.plain, lines.changedPlain, lines.wholePlain); !s)
            return s;
        if (Status s = syncLineSet(ctx, r.creaseLines, r.creaseLineCount, lines.creased, lines.changedCreased, lines.wholeCreased);
            !s)
            return s;
        if (oneStep)
            for (uint32_t v : moved) r.positions[v] = cage.positions[v];
        else
            r.positions = cage.positions;
        r.cageBounds = cageExtent(doc).bounds;
    }
    if (newHidden) {
        r.hiddenSubfaces = hiddenSubfacesOf(doc);
        for (SchemeView& view : r.views) ++view.drawRevision;
    }
    if (newGrid) {
        r.gridBounds = bounds ? *bounds : documentBounds(doc);
        const GroundGrid grid = groundGrid(r.gridBounds, display.up, display.background);
        if (Status s = fillLineBuffer(ctx, r.gridLines, r.gridLineCount, grid.lines); !s) return s;
        r.gridUp = display.up;
    }
    if (Status s = fillLineBuffer(ctx, r.overlayLines, r.overlayLineCount, overlayLines(doc)); !s) return s;
    r.overlayKey = overlay;
    r.generation = generation;
    r.planRevision = doc.planRevision;
    r.positionRevision = doc.positionRevision;
    r.displacementRevision = doc.displacementRevision;
    r.sampleRevision = doc.sampleRevision;
    r.hiddenRevision = doc.hiddenRevision;
    syncOtherObjects(ctx, r, catalog, doc, generation, requests);
    r.lastSyncMs = msSince(start);
    return success();
}

void recordScene(VkCommandBuffer cmd, SceneRenderer& r, uint32_t slot, const RenderTarget& target,
                 std::span<const ViewportDraw> viewports, const DisplayOptions& options) {
    const VkQueryPool pool = r.statistics[slot];
    const uint32_t count = std::min<uint32_t>(uint32_t(std::min(viewports.size(), r.views.size())), kMaxViewports);
    if (pool) vkCmdResetQueryPool(cmd, pool, 0, kMaxViewports);
    r.recordedViewports[slot] = count;
    r.recordedWire[slot] = options.wireframe;
    for (uint32_t i = 0; i < count; ++i) {
        const ViewportDraw& v = viewports[i];
        SchemeView& view = r.views[i];
        const RenderTarget area = subArea(target, v.rect);
        r.recordedSurface[slot][i] = false;
        r.recordedPatches[slot][i] = 0;
        r.recordedCull[slot][i] = ViewportCounts{};
        if (!view.instance) {
            beginRendering(cmd, area, true, options.background);
            vkCmdEndRendering(cmd);
            continue;
        }
        if (pool) vkCmdBeginQuery(cmd, pool, i, 0);
        if (view.heat.valid) {
            const MeshDraw draw{&view.heat.mesh, glm::vec3(0.8f), true, options.wireframe};
            recordMeshPass(cmd, r.heatPass, area, MeshView{v.viewProjection, v.eye, options.background, options.shading},
                           view.heat.mesh.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
            recordOtherHeatMaps(cmd, r, i, area, v, options);
        } else {
            DrawView drawView;
            drawView.viewProjection = v.viewProjection;
            drawView.eye = v.eye;
            drawView.background = options.background;
            drawView.pixelsPerUnit = v.pixelsPerUnit;
            drawView.navigating = v.navigating;
            drawView.wireframe = options.wireframe;
            drawView.shading = options.shading;
            drawView.hiddenSubfaces = r.hiddenSubfaces;
            drawView.cull = v.cull;
            drawView.colorBy = std::find(view.colorModes.begin(), view.colorModes.end(), v.colorBy) != view.colorModes.end()
                                   ? v.colorBy
                                   : view.colorModes.front();
            barrierBeforeEvaluation(cmd);
            Result<DrawStats> drawn = view.instance->record(cmd, area, drawView);
            view.drawProblem = drawn ? std::string() : drawn.error().message;
            if (drawn) {
                r.recordedPatches[slot][i] = drawn->patches;
                addCullStats(r.recordedCull[slot][i], *drawn);
            }
            recordOtherObjects(cmd, r, i, area, v, drawView, r.recordedCull[slot][i]);
        }
        if (pool) vkCmdEndQuery(cmd, pool, i);
        r.recordedSurface[slot][i] = pool != VK_NULL_HANDLE;
        if (options.grid && r.gridLineCount > 0)
            recordLines(cmd, r.lines, area, v.worldViewProjection, r.gridLines, r.gridLineCount, kGridLineWidth);
        const glm::mat4 cageView = withDepthBias(v.viewProjection, kCageDepthBias);
        const bool plainLines =
            options.denseCage || plainLinesReadable(r.cageLineCache, r.cageBounds, v.viewProjection, v.eye, v.pixelsPerUnit);
        r.plainLinesHidden[i] = options.cage && r.cageLineCount > 0 && !plainLines;
        if (options.cage && plainLines && r.cageLineCount > 0)
            recordLines(cmd, r.lines, area, cageView, r.cageLines, r.cageLineCount, kCageLineWidth);
        if (options.cage && r.creaseLineCount > 0)
            recordLines(cmd, r.lines, area, cageView, r.creaseLines, r.creaseLineCount, kCreaseLineWidth);
        if (options.selection && r.overlayLineCount > 0)
            recordLines(cmd, r.lines, area, withDepthBias(v.viewProjection, kOverlayDepthBias), r.overlayLines,
                        r.overlayLineCount, kOverlayLineWidth);
    }
}

void addCullStats(ViewportCounts& counts, const DrawStats& drawn) {
    counts.cull += drawn.cull;
    counts.cullMilliseconds += drawn.cullMilliseconds;
    counts.sampleCulled += drawn.sampleCulledTriangles;
    counts.facingAway += drawn.facingAwayTriangles;
}

std::vector<ViewportCounts> readViewportCounts(const VulkanContext& ctx, const SceneRenderer& r, uint32_t slot) {
    std::vector<ViewportCounts> counts;
    if (!r.statistics[slot]) return counts;
    const uint64_t passes = r.recordedWire[slot] ? 2 : 1;
    for (uint32_t i = 0; i < r.recordedViewports[slot]; ++i) {
        ViewportCounts c;
        uint64_t values[2] = {0, 0};
        if (r.recordedSurface[slot][i] &&
            vkGetQueryPoolResults(ctx.device, r.statistics[slot], i, 1, sizeof values, values, sizeof values,
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            // The device counts what reached it: the surface without the triangles sample culling
            // left out, the wireframe (drawn from every triangle) with them.
            const uint64_t left = r.recordedCull[slot][i].sampleCulled + r.recordedCull[slot][i].facingAway;
            c.triangles = (values[1] - std::min(values[1], (passes - 1) * left)) / passes + left;
            c.patches = r.recordedPatches[slot][i];
            c.cull = r.recordedCull[slot][i].cull;
            c.cullMilliseconds = r.recordedCull[slot][i].cullMilliseconds;
            c.sampleCulled = r.recordedCull[slot][i].sampleCulled;
            c.facingAway = r.recordedCull[slot][i].facingAway;
        }
        counts.push_back(c);
    }
    return counts;
}

}  // namespace qp::editor
