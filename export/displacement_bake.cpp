#include "displacement_bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <tbb/parallel_for.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>

#include "mesh/file_io.h"
#include "offscreen_target.h"
#include "scene_export.h"

namespace qp {

namespace {

// A piece of a sub-face's UV image: corners in texel coordinates (x right, y down) and the
// sub-face parameters there.
struct BakeTriangle {
    glm::vec2 texel[3];
    glm::vec2 param[3];
    uint32_t subface;
};

constexpr uint32_t kBandRows = 16;

glm::vec2 toTexel(glm::vec2 uv, uint32_t size) { return {uv.x * float(size), (1.0f - uv.y) * float(size)}; }

// Cuts each sub-face's UV image into cells of about two texels.
std::vector<BakeTriangle> uvTriangles(const PlannedCage& planned, const CageUvs& uvs, uint32_t size, uint32_t& outside) {
    std::vector<std::vector<BakeTriangle>> perSubface(planned.subfaceCount());
    std::vector<uint8_t> leaves(planned.subfaceCount(), 0);
    tbb::parallel_for(uint32_t(0), planned.subfaceCount(), [&](uint32_t s) {
        if (!planned.hasSurface(s)) return;
        float extent = 0.0f;
        const glm::vec2 corners[4] = {uvs.at(s, 0, 0), uvs.at(s, 1, 0), uvs.at(s, 1, 1), uvs.at(s, 0, 1)};
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) extent = std::max(extent, glm::length(corners[a] - corners[b]) * float(size));
        const uint32_t m = std::clamp(uint32_t(std::ceil(extent / 2.0f)), 1u, 64u);
        std::vector<glm::vec2> grid((m + 1) * (m + 1));
        for (uint32_t j = 0; j <= m; ++j)
            for (uint32_t i = 0; i <= m; ++i) {
                const glm::vec2 uv = uvs.at(s, float(i) / float(m), float(j) / float(m));
                if (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f) leaves[s] = 1;
                grid[j * (m + 1) + i] = toTexel(uv, size);
            }
        auto corner = [&](uint32_t i, uint32_t j) {
            return std::pair(grid[j * (m + 1) + i], glm::vec2(float(i) / float(m), float(j) / float(m)));
        };
        for (uint32_t j = 0; j < m; ++j)
            for (uint32_t i = 0; i < m; ++i) {
                const auto c00 = corner(i, j), c10 = corner(i + 1, j), c11 = corner(i + 1, j + 1), c01 = corner(i, j + 1);
                perSubface[s].push_back({{c00.first, c10.first, c11.first}, {c00.second, c10.second, c11.second}, s});
                perSubface[s].push_back({{c00.first, c11.first, c01.first}, {c00.second, c11.second, c01.second}, s});
            }
    });
    outside = uint32_t(std::count(leaves.begin(), leaves.end(), 1));
    std::vector<BakeTriangle> all;
    for (std::vector<BakeTriangle>& t : perSubface) all.insert(all.end(), t.begin(), t.end());
    return all;
}

// The tangent-space normal at (u, v): the displaced normal in the frame of the limit surface's
// derivatives along the texture's U and V. `uvJacobian` maps sub-face parameter steps to UV steps.
glm::vec3 tangentSpaceNormal(const PlannedCage& planned, const Displacement& displacement, uint32_t subface, glm::vec2 p,
                             const glm::mat2& uvJacobian) {
    const LimitSample limit = planned.evaluate(subface, p.x, p.y);
    const glm::vec3 cross = glm::cross(limit.du, limit.dv);
    const float length = glm::length(cross);
    if (!(length > 0.0f)) return {0.0f, 0.0f, 1.0f};
    const glm::vec3 normal = cross / length;
    const DisplacedPoint displaced =
        displacePoint(limit.position, limit.du, limit.dv, normal, evaluateDisplacement(displacement, subface, p.x, p.y));
    // [P_U P_V] = [P_u P_v] J^-1, J = d(U, V) / d(u, v).
    const glm::mat2 inverse = glm::inverse(uvJacobian);
    const glm::vec3 alongU = limit.du * inverse[0][0] + limit.dv * inverse[0][1];
    const glm::vec3 alongV = limit.du * inverse[1][0] + limit.dv * inverse[1][1];
    glm::vec3 tangent = alongU - normal * glm::dot(normal, alongU);
    if (!(glm::length(tangent) > 0.0f)) return {0.0f, 0.0f, 1.0f};
    tangent = glm::normalize(tangent);
    glm::vec3 bitangent = glm::cross(normal, tangent);
    if (glm::dot(bitangent, alongV) < 0.0f) bitangent = -bitangent;
    const glm::vec3 n = displaced.normal;
    return glm::normalize(glm::vec3(glm::dot(n, tangent), glm::dot(n, bitangent), glm::dot(n, normal)));
}

void rasterise(const PlannedCage& planned, const Displacement& displacement, const BakeTriangle& t, uint32_t size,
               uint32_t rowBegin, uint32_t rowEnd, BakedMaps& maps) {
    const glm::vec2 a = t.texel[0], b = t.texel[1], c = t.texel[2];
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::abs(area) > 0.0f)) return;
    const float lo = -1e-5f * std::abs(area);  // texel centres on a shared edge go to both sides
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}) - 0.5f)));
    const int x1 = std::min(int(size) - 1, int(std::ceil(std::max({a.x, b.x, c.x}) - 0.5f)));
    const int y0 = std::max(int(rowBegin), int(std::floor(std::min({a.y, b.y, c.y}) - 0.5f)));
    const int y1 = std::min(int(rowEnd) - 1, int(std::ceil(std::max({a.y, b.y, c.y}) - 0.5f)));
    glm::mat2 uvJacobian(1.0f);
    if (!maps.normals.empty()) {
        // Texel steps back to UV (y runs down), then d(U, V) / d(u, v) = dUV * dParam^-1.
        const glm::mat2 dUv(glm::vec2(b.x - a.x, a.y - b.y) / float(size), glm::vec2(c.x - a.x, a.y - c.y) / float(size));
        const glm::mat2 dParam(t.param[1] - t.param[0], t.param[2] - t.param[0]);
        uvJacobian = dUv * glm::inverse(dParam);
    }
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const glm::vec2 p(float(x) + 0.5f, float(y) + 0.5f);
            float w0 = (b.x - p.x) * (c.y - p.y) - (b.y - p.y) * (c.x - p.x);
            float w1 = (c.x - p.x) * (a.y - p.y) - (c.y - p.y) * (a.x - p.x);
            float w2 = (a.x - p.x) * (b.y - p.y) - (a.y - p.y) * (b.x - p.x);
            if (area < 0.0f) w0 = -w0, w1 = -w1, w2 = -w2;
            if (w0 < lo || w1 < lo || w2 < lo) continue;
            const float sum = w0 + w1 + w2;
            const glm::vec2 param = glm::clamp((w0 * t.param[0] + w1 * t.param[1] + w2 * t.param[2]) / sum, 0.0f, 1.0f);
            const size_t texel = size_t(y) * size + size_t(x);
            maps.displacement[texel] = evaluateDisplacement(displacement, t.subface, param.x, param.y).value;
            maps.coverage[texel] = TexelCoverage::Island;
            if (!maps.normals.empty())
                maps.normals[texel] = tangentSpaceNormal(planned, displacement, t.subface, param, uvJacobian);
        }
}

// Grows the islands by one texel per round: an empty texel next to filled ones takes their mean.
void dilate(BakedMaps& maps, uint32_t rounds) {
    const int size = int(maps.size);
    for (uint32_t round = 0; round < rounds; ++round) {
        std::vector<std::pair<size_t, std::pair<float, glm::vec3>>> filled;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const size_t texel = size_t(y) * size + x;
                if (maps.coverage[texel] != TexelCoverage::Empty) continue;
                float sum = 0.0f;
                glm::vec3 normal(0.0f);
                int count = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
                        const size_t n = size_t(ny) * size + nx;
                        if (maps.coverage[n] == TexelCoverage::Empty) continue;
                        sum += maps.displacement[n];
                        if (!maps.normals.empty()) normal += maps.normals[n];
                        ++count;
                    }
                if (count > 0)
                    filled.push_back({texel, {sum / float(count), glm::length(normal) > 0.0f ? glm::normalize(normal) : normal}});
            }
        if (filled.empty()) return;
        for (const auto& [texel, value] : filled) {
            maps.displacement[texel] = value.first;
            if (!maps.normals.empty()) maps.normals[texel] = value.second;
            maps.coverage[texel] = TexelCoverage::Padding;
        }
        maps.paddingTexels += filled.size();
    }
}

// OpenEXR writes through a stream; this one keeps the bytes for writeFileAtomically.
class MemoryStream : public Imf::OStream {
public:
    explicit MemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}
    void write(const char c[], int n) override {
        if (position_ + size_t(n) > bytes_.size()) bytes_.resize(position_ + size_t(n));
        std::memcpy(bytes_.data() + position_, c, size_t(n));
        position_ += size_t(n);
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t position) override { position_ = size_t(position); }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
    size_t position_ = 0;
};

}  // namespace

Result<BakedMaps> bakeDisplacement(const PlannedCage& planned, const Displacement& displacement, const BakeOptions& options,
                                   const std::string& source) {
    if (options.size < 16 || options.size > 16384)
        return Error{"the map size must be 16 to 16384 texels, got " + std::to_string(options.size)};
    if (options.uv == UvMode::None) return Error{"baking needs UVs: linear or smooth"};
    if (displacement.empty()) return Error{source + ": there is no sculpted displacement to bake"};
    if (displacement.layout.tiles.size() != planned.subfaceCount() ||
        displacement.layout.adjacency.vertexCount != planned.cage().vertexCount())
        return Error{source + ": the displacement does not belong to this cage"};
    Result<CageUvs> uvs = CageUvs::create(planned, options.uv, source);
    if (!uvs) return Error{"cannot bake: " + uvs.error().message};

    BakedMaps maps;
    maps.size = options.size;
    const size_t texels = size_t(options.size) * options.size;
    maps.displacement.assign(texels, 0.0f);
    maps.coverage.assign(texels, TexelCoverage::Empty);
    if (options.normalMap) maps.normals.assign(texels, glm::vec3(0.0f, 0.0f, 1.0f));

    const std::vector<BakeTriangle> triangles = uvTriangles(planned, *uvs, options.size, maps.subfacesOutsideUnitSquare);
    const uint32_t bands = (options.size + kBandRows - 1) / kBandRows;
    std::vector<std::vector<uint32_t>> inBand(bands);
    for (uint32_t i = 0; i < triangles.size(); ++i) {
        const BakeTriangle& t = triangles[i];
        const float top = std::min({t.texel[0].y, t.texel[1].y, t.texel[2].y}) - 0.5f;
        const float bottom = std::max({t.texel[0].y, t.texel[1].y, t.texel[2].y}) - 0.5f;
        if (!(bottom >= 0.0f) || !(top < float(options.size))) continue;  // off the image (or NaN)
        const uint32_t first = uint32_t(std::max(0.0f, std::floor(top))) / kBandRows;
        const uint32_t last = std::min(uint32_t(std::ceil(bottom)), options.size - 1) / kBandRows;
        for (uint32_t b = first; b <= last; ++b) inBand[b].push_back(i);
    }
    tbb::parallel_for(uint32_t(0), bands, [&](uint32_t b) {
        const uint32_t rowBegin = b * kBandRows, rowEnd = std::min(options.size, rowBegin + kBandRows);
        for (uint32_t i : inBand[b]) rasterise(planned, displacement, triangles[i], options.size, rowBegin, rowEnd, maps);
    });

    bool first = true;
    for (size_t t = 0; t < texels; ++t) {
        if (maps.coverage[t] != TexelCoverage::Island) continue;
        ++maps.islandTexels;
        maps.minValue = first ? maps.displacement[t] : std::min(maps.minValue, maps.displacement[t]);
        maps.maxValue = first ? maps.displacement[t] : std::max(maps.maxValue, maps.displacement[t]);
        first = false;
    }
    if (maps.islandTexels == 0) return Error{source + ": no UV island covers a texel centre of the [0, 1] square"};
    dilate(maps, options.padding);
    return maps;
}

Status writeDisplacementExr(const BakedMaps& maps, const std::string& path) {
    try {
        Imf::Header header(int(maps.size), int(maps.size));
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        header.compression() = Imf::ZIP_COMPRESSION;
        MemoryStream stream(path);
        {  // the line offset table is written when the file closes
            Imf::OutputFile file(stream, header);
            Imf::FrameBuffer frame;
            frame.insert("Y", Imf::Slice(Imf::FLOAT, (char*)maps.displacement.data(), sizeof(float),
                                         sizeof(float) * maps.size));
            file.setFrameBuffer(frame);
            file.writePixels(int(maps.size));
        }
        return writeFileAtomically(path, stream.bytes());
    } catch (const std::exception& e) {
        return Error{"cannot write '" + path + "' as OpenEXR: " + e.what()};
    }
}

Status writeNormalMapPng(const BakedMaps& maps, const std::string& path) {
    if (maps.normals.empty()) return Error{"no normal map was baked for '" + path + "'"};
    std::vector<uint8_t> rgba(maps.normals.size() * 4);
    for (size_t t = 0; t < maps.normals.size(); ++t) {
        const glm::vec3 n = maps.normals[t];
        for (int k = 0; k < 3; ++k) rgba[t * 4 + k] = uint8_t(std::lround(std::clamp(n[k] * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f));
        rgba[t * 4 + 3] = 255;
    }
    return writePng(path, maps.size, maps.size, rgba);
}

Result<BakeReport> bakeScene(const Scene& scene, const SceneCages& cages, const std::string& path,
                             const std::string& normalMapPath, const BakeOptions& options, const std::string& source,
                             const ExportProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    if (lowercaseExtension(path) != ".exr") return Error{"the displacement map must be an .exr file, got '" + path + "'"};
    if (!normalMapPath.empty() && lowercaseExtension(normalMapPath) != ".png")
        return Error{"the normal map must be a .png file, got '" + normalMapPath + "'"};
    if (options.normalMap != !normalMapPath.empty()) return Error{"a normal map needs both normalMap and its path"};
    BakeReport report;
    std::vector<std::pair<uint32_t, BakedMaps>> baked;  // (owner object, maps)
    for (uint32_t c = 0; c < cages.cages.size(); ++c) {
        const uint32_t owner = cages.objectOfCage[c];
        const SceneObject& object = scene.objects[owner];
        const std::string where = cages.cages.size() == 1 ? source : source + ": object \"" + object.name + "\"";
        if (object.displacement.empty()) {
            if (cages.cages.size() > 1) report.notes.push_back(where + " has no sculpted displacement: not baked");
            continue;
        }
        if (progress && !progress("Baking " + object.name, 0.9f * float(c) / float(cages.cages.size())))
            return Error{"cancelled: nothing was written"};
        Result<BakedMaps> maps = bakeDisplacement(*cages.cages[c], object.displacement, options, where);
        if (!maps) return maps.error();
        if (maps->subfacesOutsideUnitSquare > 0)
            report.notes.push_back(where + ": " + std::to_string(maps->subfacesOutsideUnitSquare) +
                                   " sub-faces have UVs outside [0, 1] (other UDIM tiles): only the [0, 1] square is baked");
        baked.emplace_back(owner, std::move(maps).value());
    }
    if (baked.empty()) return Error{source + ": there is no sculpted displacement to bake (sculpt first)"};
    for (size_t i = 0; i < baked.size(); ++i) {
        const BakedMaps& maps = baked[i].second;
        report.islandTexels += maps.islandTexels, report.paddingTexels += maps.paddingTexels;
        report.minValue = i == 0 ? maps.minValue : std::min(report.minValue, maps.minValue);
        report.maxValue = i == 0 ? maps.maxValue : std::max(report.maxValue, maps.maxValue);
    }
    auto fileFor = [&](const std::string& out, uint32_t owner) {
        return baked.size() == 1 ? out : splitExportPath(out, scene.objects[owner].name);
    };
    if (progress && !progress("Writing " + path, 0.9f)) return Error{"cancelled: nothing was written"};
    for (const auto& [owner, maps] : baked) {
        const std::string file = fileFor(path, owner);
        if (Status s = writeDisplacementExr(maps, file); !s) return s.error();
        report.files.push_back(file);
    }
    if (options.normalMap)
        for (const auto& [owner, maps] : baked) {
            const std::string file = fileFor(normalMapPath, owner);
            if (Status s = writeNormalMapPng(maps, file); !s) return s.error();
            report.files.push_back(file);
        }
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace qp
