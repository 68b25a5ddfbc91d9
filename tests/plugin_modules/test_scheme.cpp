// Scheme modules for the loader tests (tests/plugins/test_schemes.cpp), one source built in several
// variants (tests/plugin_modules/CMakeLists.txt). QP_TEST_GOOD is also the smallest complete scheme:
// the cage itself, bilinear over each sub-face, drawn through the CPU grid path.
#include <stdexcept>

#include "mesh_pass.h"
#include "scheme_api.h"
#include "scheme_support.h"

namespace qp {
namespace {

class FlatScheme : public Scheme {
public:
    SupportReport support(const CageFeatures&, const SchemeSettings&) const override { return {}; }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
#ifdef QP_TEST_THROWS_AT_BUILD
        throw std::runtime_error("deliberate failure in build");
#endif
        planned_ = &planned;
        grid_ = buildSubfaceGrid(planned, settings.tessFactor);
        return success();
    }
    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        return createSchemeMeshPass(pass_, gpu);
    }
    Status update() override {
        if (!ctx_ || grid_.samples.empty()) return success();
        std::vector<SurfacePoint> points(grid_.samples.size());
        evaluateParallel(*this, grid_.samples, points);
        return replaceMesh(*ctx_, mesh_, meshVertices(points), grid_.indices);
    }
    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        MeshDraw draw{&mesh_};
        recordMeshPass(cmd, pass_, target, MeshView{view.viewProjection, view.eye, view.background},
                       mesh_.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
        return DrawStats{0, grid_.indices.size() / 3};
    }
    // Bilinear over the sub-face's corners: a quad's vertices, or an n-gon sub-face's (vertex k,
    // midpoint of edge k, centre, midpoint of edge k-1).
    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        const Cage& cage = planned_->cage();
        for (size_t i = 0; i < requests.size(); ++i) {
            const uint32_t face = faceOfSubface(*planned_, requests[i].subface);
            const uint32_t n = cage.faceSize(face), k = requests[i].subface - planned_->firstSubface(face);
            const uint32_t* v = cage.faceBegin(face);
            glm::vec3 c[4];
            if (n == 4) {
                for (int j = 0; j < 4; ++j) c[j] = cage.positions[v[j]];
            } else {
                glm::vec3 centre(0.0f);
                for (uint32_t j = 0; j < n; ++j) centre += cage.positions[v[j]] / float(n);
                c[0] = cage.positions[v[k]];
                c[1] = 0.5f * (c[0] + cage.positions[v[(k + 1) % n]]);
                c[2] = centre;
                c[3] = 0.5f * (c[0] + cage.positions[v[(k + n - 1) % n]]);
            }
            const float u = requests[i].u, w = requests[i].v;
            const glm::vec3 p = (1 - u) * (1 - w) * c[0] + u * (1 - w) * c[1] + u * w * c[2] + (1 - u) * w * c[3];
            const glm::vec3 du = (1 - w) * (c[1] - c[0]) + w * (c[2] - c[3]);
            const glm::vec3 dv = (1 - u) * (c[3] - c[0]) + u * (c[2] - c[1]);
            out[i] = surfacePoint(p, du, dv);
        }
    }
#ifdef QP_TEST_FAILING_UPDATE
    // Claims updates in place and fails every one: the host must rebuild and say so.
    Result<PlanUpdate> updatePlans(const PlanChange&) override { return Error{"deliberate failure in updatePlans"}; }
    bool updatesPlansInPlace() const override { return true; }
#endif
    SchemeStats stats() const override { return {}; }
    void destroyGpu() override {
        if (!ctx_) return;
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        destroyMeshPass(*ctx_, pass_);
        ctx_ = nullptr;
    }

private:
    const PlannedCage* planned_ = nullptr;
    SubfaceGrid grid_;
    const VulkanContext* ctx_ = nullptr;
    MeshPass pass_;
    GpuMesh mesh_;
};

}  // namespace
}  // namespace qp

#if defined(QP_TEST_GOOD) || defined(QP_TEST_DUPLICATE)
QUADPLAN_EXPORT_SCHEME("test-flat", "the cage, bilinear (a test scheme)", qp::FlatScheme)
#elif defined(QP_TEST_FAILING_UPDATE)
QUADPLAN_EXPORT_SCHEME("test-update-fails", "fails its updates in place (a test scheme)", qp::FlatScheme)
#elif defined(QP_TEST_THROWS_AT_BUILD)
QUADPLAN_EXPORT_SCHEME("test-throws", "throws in build (a test scheme)", qp::FlatScheme)
#elif defined(QP_TEST_NULL_CREATE)
extern "C" __attribute__((visibility("default"))) const qp::SchemeModule* quadplan_scheme_module() {
    static const qp::SchemeModule module{qp::kSchemeApiVersion, QUADPLAN_SCHEME_ABI_TAG, qp::kSchemeLayoutFingerprint,
                                         "test-null", "creates nothing", []() -> qp::Scheme* { return nullptr; }};
    return &module;
}
#elif defined(QP_TEST_WRONG_VERSION)
extern "C" __attribute__((visibility("default"))) const qp::SchemeModule* quadplan_scheme_module() {
    static const qp::SchemeModule module{qp::kSchemeApiVersion + 100, QUADPLAN_SCHEME_ABI_TAG, qp::kSchemeLayoutFingerprint,
                                         "test-version", "from the future", []() -> qp::Scheme* { return new qp::FlatScheme(); }};
    return &module;
}
#elif defined(QP_TEST_WRONG_ABI)
extern "C" __attribute__((visibility("default"))) const qp::SchemeModule* quadplan_scheme_module() {
    static const qp::SchemeModule module{qp::kSchemeApiVersion, "another compiler", qp::kSchemeLayoutFingerprint,
                                         "test-abi", "another build", []() -> qp::Scheme* { return new qp::FlatScheme(); }};
    return &module;
}
#elif defined(QP_TEST_UNDEFINED_SYMBOL)
// Not defined anywhere: dlopen with RTLD_NOW must fail and say so.
extern "C" int quadplan_test_symbol_nobody_defines();
extern "C" __attribute__((visibility("default"))) const qp::SchemeModule* quadplan_scheme_module() {
    static const qp::SchemeModule module{qp::kSchemeApiVersion, QUADPLAN_SCHEME_ABI_TAG, qp::kSchemeLayoutFingerprint,
                                         "test-undefined", "unresolved", []() -> qp::Scheme* {
                                             return quadplan_test_symbol_nobody_defines() ? new qp::FlatScheme() : nullptr;
                                         }};
    return &module;
}
#elif defined(QP_TEST_NO_ENTRY)
// A shared module without quadplan_scheme_module.
extern "C" __attribute__((visibility("default"))) int quadplan_not_a_scheme() { return 42; }
#endif
