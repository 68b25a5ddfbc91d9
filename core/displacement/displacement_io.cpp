#include "displacement/displacement_io.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <set>

#include "mesh/topology.h"
#include "plans/face_config.h"

namespace qp {

namespace {

using json = nlohmann::json;

constexpr const char* kEncoding = "base64-float32-le";
constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

struct FieldError {
    std::string field, message;
};

[[noreturn]] void fail(const std::string& field, std::string message) { throw FieldError{field, std::move(message)}; }

std::string describe(const json& value) {
    return std::string(value.is_array() || value.is_object() ? "an " : "a ") + value.type_name();
}

int64_t readInteger(const json& value, const std::string& field) {
    if (!value.is_number_integer()) fail(field, "expected an integer, got " + describe(value));
    if (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(INT64_MAX))
        fail(field, "integer " + value.dump() + " is too large");
    return value.get<int64_t>();
}

// Decodes a base64 field into exactly `expected` finite floats; `name(i)` says what value i is.
template <class Name>
std::vector<float> readFloats(const json& value, const std::string& field, size_t expected, Name name) {
    if (!value.is_string()) fail(field, "expected a base64 string of float32 values, got " + describe(value));
    Result<std::vector<float>> floats = decodeFloats(value.get<std::string>());
    if (!floats) fail(field, floats.error().message);
    if (floats->size() != expected)
        fail(field, "has " + std::to_string(floats->size()) + " values but " + std::to_string(expected) +
                        " are needed" + (expected ? "" : " (none)"));
    for (size_t i = 0; i < floats->size(); ++i)
        if (!std::isfinite((*floats)[i]))
            fail(field, "value " + std::to_string(i) + " (" + name(i) + ") is " +
                            (std::isnan((*floats)[i]) ? "NaN" : "infinite") + "; displacements must be finite numbers");
    return std::move(floats).value();
}

void warnUnknown(const json& object, const std::set<std::string>& known, const std::string& path,
                 const std::string& source, std::vector<std::string>* warnings) {
    if (!warnings) return;
    for (const auto& [key, value] : object.items())
        if (!known.count(key)) warnings->push_back(source + ": " + path + "." + key + ": unknown field, ignored");
}

std::string pointName(const SampleGridLayout& layout, size_t id) {
    if (id < layout.vertexCount) return "cage vertex " + std::to_string(id);
    if (id < layout.vertexCount + layout.edgeCount) return "midpoint of cage edge " + std::to_string(id - layout.vertexCount);
    return "centre of face " + std::to_string(id - layout.vertexCount - layout.edgeCount);
}

// The optional mask: one value in [0, 1] per sample, in sample order.
std::vector<float> readMask(const json& value, size_t sampleCount) {
    std::vector<float> mask = readFloats(value, "displacement.mask", sampleCount,
                                         [](size_t i) { return "the mask of sample " + std::to_string(i); });
    for (size_t i = 0; i < mask.size(); ++i)
        if (!(mask[i] >= 0.0f && mask[i] <= 1.0f))
            fail("displacement.mask", "value " + std::to_string(i) + " is " + json(double(mask[i])).dump() +
                                          "; mask values must lie between 0 (not masked) and 1 (fully masked)");
    return mask;
}

// `at` prefixes the field paths of warnings (errors get it where they are caught).
SampleGrids readVersion1(const json& value, const Cage& cage, const std::string& source,
                          std::vector<std::string>* warnings, const std::string& at) {
    warnUnknown(value, {"version", "encoding", "subfaces", "points", "segments", "mask"}, at + "displacement", source,
                warnings);
    if (auto it = value.find("encoding"); it != value.end() && (!it->is_string() || it->get<std::string>() != kEncoding))
        fail("displacement.encoding", "expected \"" + std::string(kEncoding) + "\", got " + it->dump());
    auto subfacesIt = value.find("subfaces");
    if (subfacesIt == value.end()) fail("displacement.subfaces", "required field is missing");
    const json& subfaces = *subfacesIt;
    if (!subfaces.is_array()) fail("displacement.subfaces", "expected an array, got " + describe(subfaces));
    if (subfaces.empty()) {
        for (const char* key : {"points", "segments", "mask"})
            if (value.contains(key))
                fail(std::string("displacement.") + key, "not allowed when \"subfaces\" is empty (no displacement)");
        return SampleGrids{};
    }

    uint32_t subfaceTotal = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) subfaceTotal += subfaceCount(cage.faceSize(f));
    if (subfaces.size() != subfaceTotal)
        fail("displacement.subfaces", "has " + std::to_string(subfaces.size()) + " entries but the cage has " +
                                          std::to_string(subfaceTotal) + " sub-faces (" + std::to_string(cage.faceCount()) +
                                          " faces; a quad is one sub-face, an n-gon n): the displacement belongs to "
                                          "another cage");
    std::vector<uint32_t> resolutions(subfaceTotal);
    for (uint32_t s = 0; s < subfaceTotal; ++s) {
        const std::string field = "displacement.subfaces[" + std::to_string(s) + "]";
        if (!subfaces[s].is_object()) fail(field, "expected an object, got " + describe(subfaces[s]));
        warnUnknown(subfaces[s], {"resolution", "interior"}, at + field, source, warnings);
        auto r = subfaces[s].find("resolution");
        if (r == subfaces[s].end()) fail(field + ".resolution", "required field is missing");
        int64_t resolution = readInteger(*r, field + ".resolution");
        if (resolution < 1 || resolution > kMaxDisplacementResolution || !isPowerOfTwo(uint32_t(resolution)))
            fail(field + ".resolution", "resolution " + std::to_string(resolution) + " is not a power of two between 1 and " +
                                            std::to_string(kMaxDisplacementResolution));
        resolutions[s] = uint32_t(resolution);
    }

    SampleGrids d;
    d.layout = withResolutions(buildSampleGridLayout(cage, buildTopology(cage), 1), resolutions);
    d.samples.assign(d.layout.sampleCount, 0.0f);
    const SampleGridLayout& layout = d.layout;

    auto points = value.find("points");
    if (points == value.end()) fail("displacement.points", "required field is missing");
    std::vector<float> pointValues =
        readFloats(*points, "displacement.points", layout.pointCount, [&](size_t i) { return pointName(layout, i); });
    std::copy(pointValues.begin(), pointValues.end(), d.samples.begin());

    auto segments = value.find("segments");
    if (segments == value.end()) fail("displacement.segments", "required field is missing");
    const size_t segmentSamples = layout.tileSampleBegin() - layout.segmentSampleBegin();
    std::vector<float> segmentValues = readFloats(*segments, "displacement.segments", segmentSamples, [&](size_t i) {
        uint32_t sample = layout.segmentSampleBegin() + uint32_t(i);
        for (uint32_t k = 0; k < layout.segments.size(); ++k) {
            const DisplacementSegment& seg = layout.segments[k];
            if (sample >= seg.offset && sample < seg.offset + seg.resolution - 1)
                return "segment " + std::to_string(k) + " from " + pointName(layout, seg.pointA) + " to " +
                       pointName(layout, seg.pointB) + ", sample " + std::to_string(sample - seg.offset + 1) + " of " +
                       std::to_string(seg.resolution);
        }
        return std::string("a segment");
    });
    std::copy(segmentValues.begin(), segmentValues.end(), d.samples.begin() + layout.segmentSampleBegin());

    for (uint32_t s = 0; s < subfaceTotal; ++s) {
        const std::string field = "displacement.subfaces[" + std::to_string(s) + "].interior";
        const uint32_t R = resolutions[s];
        auto interior = subfaces[s].find("interior");
        if (interior == subfaces[s].end()) fail(field, "required field is missing");
        std::vector<float> values = readFloats(*interior, field, size_t(R - 1) * (R - 1), [&](size_t i) {
            return "grid point (" + std::to_string(i % (R - 1) + 1) + ", " + std::to_string(i / (R - 1) + 1) + ") of resolution " +
                   std::to_string(R);
        });
        std::copy(values.begin(), values.end(), d.samples.begin() + layout.subfaces[s].interiorOffset);
    }
    if (auto mask = value.find("mask"); mask != value.end()) d.mask = readMask(*mask, layout.sampleCount);
    return d;
}


// The tiles' R that keeps a version 1 displacement's detail: its finest sub-face's resolution in
// quad cells (an n-gon sub-face spans half a quad side: resolution r there needs R = 2r), at most
// kMaxDisplacementResolution.
uint32_t resolutionForGrids(const SampleGrids& grids, const Cage& cage) {
    uint32_t resolution = minimumDisplacementResolution(cage);
    const uint32_t centres = grids.layout.vertexCount + grids.layout.edgeCount;
    for (const DisplacementSubface& sf : grids.layout.subfaces)
        resolution = std::max(resolution, sf.corners[2] >= centres ? 2 * sf.resolution : sf.resolution);
    return std::min(resolution, kMaxDisplacementResolution);
}

Displacement readVersion2(const json& value, const Cage& cage, const std::string& source,
                          std::vector<std::string>* warnings, const std::string& at) {
    warnUnknown(value, {"version", "encoding", "resolution", "samples", "mask"}, at + "displacement", source, warnings);
    if (auto it = value.find("encoding"); it != value.end() && (!it->is_string() || it->get<std::string>() != kEncoding))
        fail("displacement.encoding", "expected \"" + std::string(kEncoding) + "\", got " + it->dump());
    auto r = value.find("resolution");
    if (r == value.end()) fail("displacement.resolution", "required field is missing");
    const int64_t resolution = readInteger(*r, "displacement.resolution");
    if (resolution == 0) {
        for (const char* key : {"samples", "mask"})
            if (value.contains(key))
                fail(std::string("displacement.") + key, "not allowed when \"resolution\" is 0 (no displacement)");
        return Displacement{};
    }
    const uint32_t minimum = minimumDisplacementResolution(cage);
    if (resolution < 1 || resolution > kMaxDisplacementResolution || !isPowerOfTwo(uint32_t(resolution)))
        fail("displacement.resolution", "resolution " + std::to_string(resolution) + " is not a power of two between 1 and " +
                                            std::to_string(kMaxDisplacementResolution) + " (or 0 for none)");
    if (uint32_t(resolution) < minimum)
        fail("displacement.resolution", "resolution " + std::to_string(resolution) + " is below " + std::to_string(minimum) +
                                            std::string(minimum == 4 ? ", the least a cage with non-quad faces allows (their sub-faces get half, and tiles need "
                                                                        "2 cells per side)"
                                                                      : ", the least a displacement allows (tiles need 2 cells per side)"));
    Displacement d;
    d.layout = buildDisplacementLayout(cage, buildTopology(cage), uint32_t(resolution));
    auto samples = value.find("samples");
    if (samples == value.end()) fail("displacement.samples", "required field is missing");
    const DisplacementLayout& layout = d.layout;
    d.samples = readFloats(*samples, "displacement.samples", layout.sampleCount, [&](size_t i) {
        const SampleHome& home = layout.homes[i];
        return "sample " + std::to_string(i) + ", cell (" + std::to_string(home.i) + ", " + std::to_string(home.j) +
               ") of sub-face " + std::to_string(home.tile);
    });
    if (auto mask = value.find("mask"); mask != value.end()) d.mask = readMask(*mask, layout.sampleCount);
    return d;
}

}  // namespace

std::string encodeFloats(const float* values, size_t count) {
    std::vector<uint8_t> bytes(count * 4);
    for (size_t i = 0; i < count; ++i) {
        uint32_t word = std::bit_cast<uint32_t>(values[i]);
        for (int b = 0; b < 4; ++b) bytes[4 * i + b] = uint8_t(word >> (8 * b));
    }
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t chunk = uint32_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) chunk |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) chunk |= bytes[i + 2];
        out += kAlphabet[chunk >> 18 & 63];
        out += kAlphabet[chunk >> 12 & 63];
        out += i + 1 < bytes.size() ? kAlphabet[chunk >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
    }
    return out;
}

Result<std::vector<float>> decodeFloats(const std::string& text) {
    if (text.size() % 4)
        return Error{"is not base64: its length " + std::to_string(text.size()) + " is not a multiple of 4"};
    int8_t decode[256];
    std::memset(decode, -1, sizeof decode);
    for (int i = 0; i < 64; ++i) decode[uint8_t(kAlphabet[i])] = int8_t(i);
    std::vector<uint8_t> bytes;
    bytes.reserve(text.size() / 4 * 3);
    for (size_t i = 0; i < text.size(); i += 4) {
        const bool last = i + 4 == text.size();
        const int padding = last ? (text[i + 3] == '=') + (text[i + 2] == '=') : 0;
        uint32_t chunk = 0;
        for (int k = 0; k < 4; ++k) {
            char c = text[i + k];
            int digit = k >= 4 - padding ? 0 : decode[uint8_t(c)];
            if (digit < 0)
                return Error{"is not base64: character " + std::to_string(i + k) + " ('" + std::string(1, c) + "') is not allowed"};
            chunk = chunk << 6 | uint32_t(digit);
        }
        bytes.push_back(uint8_t(chunk >> 16));
        if (padding < 2) bytes.push_back(uint8_t(chunk >> 8));
        if (padding < 1) bytes.push_back(uint8_t(chunk));
    }
    if (bytes.size() % 4)
        return Error{"holds " + std::to_string(bytes.size()) + " bytes, not a whole number of float32 values (4 bytes each)"};
    std::vector<float> values(bytes.size() / 4);
    for (size_t i = 0; i < values.size(); ++i) {
        uint32_t word = 0;
        for (int b = 0; b < 4; ++b) word |= uint32_t(bytes[4 * i + b]) << (8 * b);
        values[i] = std::bit_cast<float>(word);
    }
    return values;
}

Result<Displacement> readDisplacementJson(const json& value, const Cage& cage, const std::string& source,
                                          std::vector<std::string>* warnings, const std::string& at) {
    try {
        if (!value.is_object()) fail("displacement", "expected an object, got " + describe(value));
        auto version = value.find("version");
        if (version == value.end()) fail("displacement.version", "required field is missing");
        int64_t v = readInteger(*version, "displacement.version");
        if (v > kDisplacementVersion)
            fail("displacement.version", "displacement version " + std::to_string(v) + " is not supported (this build reads "
                                         "versions up to " + std::to_string(kDisplacementVersion) +
                                         "); the scene was written by a newer Quadplan");
        if (v < 0) fail("displacement.version", "displacement version " + std::to_string(v) + " is not valid");
        if (v == 0) {
            // The placeholder of scenes written before displacement existed: it never held data.
            warnUnknown(value, {"version", "faces"}, at + "displacement", source, warnings);
            if (auto faces = value.find("faces"); faces != value.end() && !(faces->is_array() && faces->empty()))
                fail("displacement.faces", "a version 0 displacement is an empty placeholder; expected [], got " +
                                               faces->dump().substr(0, 60));
            return Displacement{};
        }
        if (v == 2) return readVersion2(value, cage, source, warnings, at);
        const SampleGrids grids = readVersion1(value, cage, source, warnings, at);
        if (grids.empty()) return Displacement{};
        const uint32_t resolution = resolutionForGrids(grids, cage);
        if (warnings)
            warnings->push_back(source + ": " + at + "displacement: version 1 (bilinear sample grids) converted to smooth "
                                "tiles of resolution " + std::to_string(resolution) + " fitted to it; saving writes version " +
                                std::to_string(kDisplacementVersion));
        return fitSampleGrids(buildDisplacementLayout(cage, buildTopology(cage), resolution), grids);
    } catch (const FieldError& e) {
        return Error{at + e.field + ": " + e.message};
    }
}

bool displacementFitsCage(const Displacement& d, const Cage& cage) {
    if (d.empty()) return true;
    uint32_t subfaces = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) subfaces += subfaceCount(cage.faceSize(f));
    if (d.layout.tiles.size() != subfaces || d.samples.size() != d.layout.sampleCount) return false;
    if (d.layout.resolution < minimumDisplacementResolution(cage)) return false;
    return d.layout == buildDisplacementLayout(cage, buildTopology(cage), d.layout.resolution);
}

nlohmann::ordered_json displacementJson(const Displacement& d) {
    nlohmann::ordered_json out;
    out["version"] = kDisplacementVersion;
    out["encoding"] = kEncoding;
    out["resolution"] = d.empty() ? 0u : d.layout.resolution;
    if (d.empty()) return out;
    out["samples"] = encodeFloats(d.samples.data(), d.samples.size());
    // A mask of zeros masks nothing: it is left out, as an empty one is.
    if (d.mask.size() == d.samples.size() && std::any_of(d.mask.begin(), d.mask.end(), [](float m) { return m != 0.0f; }))
        out["mask"] = encodeFloats(d.mask.data(), d.mask.size());
    return out;
}

}  // namespace qp
