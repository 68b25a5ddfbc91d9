#include "cage_uvs.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include "plans/osd_refiner.h"

namespace qp {

using namespace OpenSubdiv;

struct CageUvs::SmoothSurfaces {
    std::vector<Bfr::Surface<float>> surfaces;     // per face; invalid for holes
    std::vector<std::vector<float>> patchPoints;  // per face, two floats per point
};

Result<UvMode> parseUvMode(const std::string& name) {
    if (name == "none") return UvMode::None;
    if (name == "linear") return UvMode::Linear;
    if (name == "smooth") return UvMode::Smooth;
    return Error{"unknown UV mode '" + name + "': use none, linear or smooth"};
}

const char* uvModeName(UvMode mode) {
    switch (mode) {
        case UvMode::Linear: return "linear";
        case UvMode::Smooth: return "smooth";
        default: return "none";
    }
}

CageUvs::~CageUvs() = default;
CageUvs::CageUvs(CageUvs&&) noexcept = default;
CageUvs& CageUvs::operator=(CageUvs&&) noexcept = default;

Result<CageUvs> CageUvs::create(const PlannedCage& planned, UvMode mode, const std::string& source) {
    const Cage& cage = planned.cage();
    if (cage.uvs.empty() || cage.faceUVIndices.size() != cage.faceVertices.size())
        return Error{source + ": the cage has no texture coordinates (OBJ 'vt' with 'f v/vt') to carry onto the surface"};
    CageUvs out;
    out.planned_ = &planned;
    out.mode_ = mode;
    out.faceOfSubface_.resize(planned.subfaceCount());
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) out.faceOfSubface_[s] = f;
    glm::vec2 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec2& uv : cage.uvs) lo = glm::min(lo, uv), hi = glm::max(hi, uv);
    out.tolerance_ = 1e-5f * std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f});
    if (mode != UvMode::Smooth) return out;

    Result<std::unique_ptr<Far::TopologyRefiner>> refiner = createRefiner(cage, source);
    if (!refiner) return refiner.error();
    Bfr::RefinerSurfaceFactory<>::Options options;
    options.SetApproxLevelSmooth(int(planned.options().maxDepth)).SetApproxLevelSharp(int(planned.options().maxDepth));
    options.SetDefaultFVarID(0);
    const Bfr::RefinerSurfaceFactory<> factory(**refiner, options);
    out.smooth_ = std::make_unique<SmoothSurfaces>();
    out.smooth_->surfaces.resize(cage.faceCount());
    out.smooth_->patchPoints.resize(cage.faceCount());
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        Bfr::Surface<float>& surface = out.smooth_->surfaces[f];
        if (!factory.InitFaceVaryingSurface(int(f), &surface)) continue;
        out.smooth_->patchPoints[f].resize(size_t(surface.GetNumPatchPoints()) * 2);
        surface.PreparePatchPoints(&cage.uvs[0].x, 2, out.smooth_->patchPoints[f].data(), 2);
    }
    return out;
}

glm::vec2 CageUvs::linearAt(uint32_t subface, float u, float v) const {
    const Cage& cage = planned_->cage();
    const uint32_t f = faceOfSubface_[subface], n = cage.faceSize(f);
    auto uvOf = [&](uint32_t k) { return cage.uvs[cage.faceUVIndices[cage.faceOffsets[f] + (k % n)]]; };
    glm::vec2 c[4];
    if (n == 4) {
        for (uint32_t k = 0; k < 4; ++k) c[k] = uvOf(k);
    } else {
        const uint32_t k = subface - planned_->firstSubface(f);
        glm::vec2 centre(0.0f);
        for (uint32_t i = 0; i < n; ++i) centre += uvOf(i);
        c[0] = uvOf(k), c[1] = 0.5f * (uvOf(k) + uvOf(k + 1)), c[2] = centre / float(n), c[3] = 0.5f * (uvOf(k) + uvOf(k + n - 1));
    }
    return (1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] + (1 - u) * v * c[3];
}

glm::vec2 CageUvs::at(uint32_t subface, float u, float v) const {
    if (mode_ != UvMode::Smooth) return linearAt(subface, u, v);
    const uint32_t f = faceOfSubface_[subface];
    const Bfr::Surface<float>& surface = smooth_->surfaces[f];
    if (!surface.IsValid()) return linearAt(subface, u, v);  // a hole: nothing is drawn there
    // Ptex sub-face k of an n-gon is Bfr's normalised sub-face k (origin at corner k, u towards
    // corner k + 1, (1, 1) at the centre); a quad's (u, v) is Bfr's own.
    float st[2] = {u, v}, coord[2] = {u, v};
    const Bfr::Parameterization param = surface.GetParameterization();
    if (param.HasSubFaces()) param.ConvertNormalizedSubFaceToCoord(int(subface - planned_->firstSubface(f)), st, coord);
    float uv[2];
    surface.Evaluate(coord, smooth_->patchPoints[f].data(), 2, uv);
    return {uv[0], uv[1]};
}

bool CageUvs::sameUv(glm::vec2 a, glm::vec2 b) const {
    return std::abs(a.x - b.x) <= tolerance_ && std::abs(a.y - b.y) <= tolerance_;
}

}  // namespace qp
