#include "mesh/obj_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <unordered_set>

#include "mesh/file_io.h"

namespace qp {

namespace {

// Indices must fit in uint32_t; the largest value marks "no texture coordinate".
constexpr uint32_t kNoUV = std::numeric_limits<uint32_t>::max();
constexpr int64_t kIndexLimit = kNoUV;
constexpr uint32_t kDroppedFace = std::numeric_limits<uint32_t>::max();

// --- Tokens and numbers -----------------------------------------------------------------------

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
    tokens.clear();
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        size_t start = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        if (i > start) tokens.push_back(line.substr(start, i - start));
    }
}

// Text files hold no control characters besides whitespace; anything else means binary data.
bool hasControlCharacter(std::string_view line) {
    for (char c : line) {
        auto u = static_cast<unsigned char>(c);
        if ((u < 0x20 && !isBlank(c)) || u == 0x7f) return true;
    }
    return false;
}

// The whole token must be a number; from_chars does not accept the '+' some writers emit.
template <class T>
std::optional<T> parseNumber(std::string_view token) {
    if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
    T value{};
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
    return value;
}

// Quotes a token for a message; bytes that are not printable ASCII are escaped so that a
// message about a binary file is still valid text.
std::string quoted(std::string_view token) {
    constexpr size_t kMax = 40;  // keep messages readable when the "token" is a line of garbage
    static const char kHex[] = "0123456789abcdef";
    std::string s = "'";
    for (char c : token.substr(0, kMax)) {
        auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7f) {
            s += c;
        } else {
            s += "\\x";
            s += kHex[u >> 4];
            s += kHex[u & 15];
        }
    }
    return s + (token.size() > kMax ? "...'" : "'");
}

// --- Tag value encodings ----------------------------------------------------------------------

// OpenSubdiv's tag numbering (regression/common/far_utils.h, from RenderMan):
// 0 none, 1 edges and corners, 2 edges only. It is not the order of the enum.
std::optional<BoundaryInterpolation> boundaryFromTag(int64_t value) {
    switch (value) {
    case 0: return BoundaryInterpolation::None;
    case 1: return BoundaryInterpolation::EdgesAndCorners;
    case 2: return BoundaryInterpolation::EdgesOnly;
    default: return std::nullopt;
    }
}

int boundaryTagValue(BoundaryInterpolation boundary) {
    switch (boundary) {
    case BoundaryInterpolation::None: return 0;
    case BoundaryInterpolation::EdgesAndCorners: return 1;
    case BoundaryInterpolation::EdgesOnly: return 2;
    }
    return 1;
}

// A file without `interpolateboundary` means what it means to OpenSubdiv, whose shapes these
// are: edges only.
constexpr BoundaryInterpolation kUntaggedBoundary = BoundaryInterpolation::EdgesOnly;

struct TagArgs {
    std::string_view name;
    std::vector<std::string_view> ints, floats, strings;  // raw tokens, parsed per tag
};

// --- Parser -----------------------------------------------------------------------------------

class ObjParser {
public:
    ObjParser(const std::string& source, std::vector<std::string>* warnings)
        : source_(source), warnings_(warnings) {
        cage_.options.boundary = kUntaggedBoundary;
    }

    Result<Cage> parse(std::string_view text);

private:
    Status parseLine(std::string_view line);
    Status parseVertex();
    Status parseTexCoord();
    Status parseFace();
    Status parseFaceCorner(std::string_view token, uint32_t& vertex, uint32_t& uv);
    Status parseTag();
    Status applyTag(const TagArgs& tag);
    Status addCreases(const TagArgs& tag);
    Status addCorners(const TagArgs& tag);
    Status addHoles(const TagArgs& tag);
    Status setOption(const TagArgs& tag);

    Result<uint32_t> resolveIndex(std::string_view token, size_t defined, const char* what);
    Result<float> parseCoordinate(std::string_view token, const char* field);
    Result<int64_t> tagInt(const TagArgs& tag, size_t i);
    Result<uint32_t> tagIndex(const TagArgs& tag, size_t i);
    Result<float> tagSharpness(const TagArgs& tag, size_t i);
    Status expectCounts(const TagArgs& tag, size_t ints, size_t floats, size_t strings);

    Status checkFaceReferences() const;
    Status checkTagReferences() const;
    void remapHoles();
    void resolveUVs();
    void flushWarnings();

    Error errorAt(uint32_t line, const std::string& what) const {
        return Error{source_ + ":" + std::to_string(line) + ": " + what};
    }
    Error error(const std::string& what) const { return errorAt(line_, what); }
    // Repeated warnings are reported once, at their first line, with a count.
    void note(const std::string& what) {
        ++notes_.try_emplace(what, Note{line_, 0}).first->second.count;
    }

    struct Note {
        uint32_t firstLine;
        uint32_t count;
    };

    const std::string& source_;
    std::vector<std::string>* warnings_;
    Cage cage_;
    uint32_t line_ = 0;
    std::vector<std::string_view> tokens_;
    std::vector<std::pair<uint32_t, uint32_t>> faceCorners_;  // scratch: (vertex, uv) of one face

    std::vector<uint32_t> faceLines_;    // per face: the line of its `f`
    std::vector<uint32_t> cornerUVs_;    // per face-vertex: uv index or kNoUV
    std::vector<uint32_t> creaseLines_;  // parallel to cage_.creases before normalizeTags
    std::vector<uint32_t> cornerLines_;  // parallel to cage_.corners
    std::vector<uint32_t> holeLines_;    // parallel to cage_.holes
    // Hole tags count the file's `f` lines, dropped faces included.
    std::vector<uint32_t> fileFaceToCage_;
    uint32_t normalCount_ = 0;
    std::map<std::string, Note> notes_;      // warnings about lines
    std::vector<std::string> fileWarnings_;  // warnings about the whole file
};

Result<Cage> ObjParser::parse(std::string_view text) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        ++line_;
        if (Status s = parseLine(text.substr(pos, end - pos)); !s) return s.error();
        pos = end + 1;
    }

    if (cage_.faceCount() == 0)
        return Error{source_ + ": no faces (an OBJ cage needs at least one 'f' line with 3 distinct vertices)"};
    if (Status s = checkFaceReferences(); !s) return s.error();
    if (Status s = checkTagReferences(); !s) return s.error();
    remapHoles();
    resolveUVs();

    normalizeTags(cage_);
    if (Status s = validateCage(cage_, source_); !s) return s.error();
    flushWarnings();
    return std::move(cage_);
}

Status ObjParser::parseLine(std::string_view line) {
    if (hasControlCharacter(line)) return error("binary data; this is not an OBJ text file");
    splitTokens(line.substr(0, line.find('#')), tokens_);  // '#' starts a comment anywhere
    if (tokens_.empty()) return success();

    std::string_view keyword = tokens_[0];
    if (keyword == "v") return parseVertex();
    if (keyword == "vt") return parseTexCoord();
    if (keyword == "f") return parseFace();
    if (keyword == "t") return parseTag();
    if (keyword == "vn") {
        ++normalCount_;
        return success();
    }
    // Grouping and materials do not affect the cage.
    if (keyword == "o" || keyword == "g" || keyword == "s" || keyword == "usemtl" || keyword == "mtllib")
        return success();
    // Other OBJ statements (lines, points, free-form curves) have no place in a cage; a keyword
    // that is not even a word means the file is not OBJ.
    bool word = keyword.size() <= 16;
    for (char c : keyword) word = word && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_');
    if (!word) return error("unrecognized line starting with " + quoted(keyword) + "; this is not an OBJ file");
    note("unsupported OBJ statement '" + std::string(keyword) + "' ignored");
    return success();
}

Result<float> ObjParser::parseCoordinate(std::string_view token, const char* field) {
    std::optional<float> value = parseNumber<float>(token);
    if (!value) return error(std::string(field) + " " + quoted(token) + " is not a number");
    if (!std::isfinite(*value))
        return error(std::string(field) + " is " + quoted(token) + "; coordinates must be finite numbers");
    return *value;
}

Status ObjParser::parseVertex() {
    if (tokens_.size() < 4)
        return error("truncated 'v' line: expected 3 coordinates x y z, found " + std::to_string(tokens_.size() - 1));
    static const char* const kFields[3] = {"coordinate x", "coordinate y", "coordinate z"};
    glm::vec3 p;
    for (int i = 0; i < 3; ++i) {
        Result<float> c = parseCoordinate(tokens_[i + 1], kFields[i]);
        if (!c) return c.error();
        p[i] = *c;
    }
    // A 4th value is the rational weight w, meaningless for a cage; more are vertex colors.
    if (tokens_.size() > 5) note("values after 'v x y z' (vertex colors?) ignored");
    cage_.positions.push_back(p);
    return success();
}

Status ObjParser::parseTexCoord() {
    if (tokens_.size() < 3)
        return error("truncated 'vt' line: expected 2 texture coordinates u v, found " +
                     std::to_string(tokens_.size() - 1));
    Result<float> u = parseCoordinate(tokens_[1], "texture coordinate u");
    if (!u) return u.error();
    Result<float> v = parseCoordinate(tokens_[2], "texture coordinate v");
    if (!v) return v.error();
    cage_.uvs.push_back({*u, *v});
    return success();
}

// OBJ indices are 1-based; negative ones count back from the last element defined so far.
// Positive indices may name elements defined later; checkFaceReferences checks their range.
Result<uint32_t> ObjParser::resolveIndex(std::string_view token, size_t defined, const char* what) {
    std::optional<int64_t> raw = parseNumber<int64_t>(token);
    if (!raw) return error(std::string(what) + " index " + quoted(token) + " is not an integer");
    if (*raw == 0) return error(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
    int64_t index = *raw > 0 ? *raw - 1 : int64_t(defined) + *raw;
    if (index < 0)
        return error("relative " + std::string(what) + " index " + std::to_string(*raw) + " is out of range (" +
                     std::to_string(defined) + " defined before this line)");
    if (index >= kIndexLimit)
        return error(std::string(what) + " index " + std::to_string(*raw) + " is out of range");
    return uint32_t(index);
}

// One face corner: v, v/vt, v//vn or v/vt/vn.
Status ObjParser::parseFaceCorner(std::string_view token, uint32_t& vertex, uint32_t& uv) {
    std::string_view parts[3];
    size_t count = 0;
    for (size_t start = 0;;) {
        size_t slash = token.find('/', start);
        if (count == 3) return error("face corner " + quoted(token) + " has more than 3 '/'-separated indices");
        parts[count++] = token.substr(start, slash == std::string_view::npos ? slash : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
    }
    Result<uint32_t> v = resolveIndex(parts[0], cage_.positions.size(), "vertex");
    if (!v) return v.error();
    vertex = *v;
    uv = kNoUV;
    if (count > 1 && !parts[1].empty()) {
        Result<uint32_t> t = resolveIndex(parts[1], cage_.uvs.size(), "texture coordinate");
        if (!t) return t.error();
        uv = *t;
    }
    // Normals are not kept, but a malformed normal index still means a malformed line.
    if (count > 2 && !parseNumber<int64_t>(parts[2]))
        return error("normal index " + quoted(parts[2]) + " is not an integer");
    return success();
}

// Consecutive repeats (zero-length edges: OpenSubdiv's non-manifold shapes write a triangle as
// `f 4 3 5 5`) are collapsed; a face left with fewer than 3 vertices has no area and is
// dropped. A non-consecutive repeat (the face visits a vertex twice, as in OpenSubdiv's
// `catmark_nonman_edges`) is kept: it is non-manifold, not malformed.
Status ObjParser::parseFace() {
    size_t n = tokens_.size() - 1;
    if (n < 3) return error("face has " + std::to_string(n) + " vertices; a face needs at least 3");
    faceCorners_.clear();
    size_t withUV = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t vertex = 0, uv = kNoUV;
        if (Status s = parseFaceCorner(tokens_[i + 1], vertex, uv); !s) return s;
        withUV += uv != kNoUV;
        if (faceCorners_.empty() || faceCorners_.back().first != vertex) faceCorners_.push_back({vertex, uv});
    }
    if (withUV != 0 && withUV != n) return error("face gives texture coordinates for some corners but not all");
    while (faceCorners_.size() > 1 && faceCorners_.back().first == faceCorners_.front().first)
        faceCorners_.pop_back();
    if (faceCorners_.size() < 3) {
        note("face has fewer than 3 distinct vertices; dropped");
        fileFaceToCage_.push_back(kDroppedFace);
        return success();
    }
    if (faceCorners_.size() < n) note("face repeats a vertex consecutively (zero-length edge); repeat removed");

    fileFaceToCage_.push_back(cage_.faceCount());
    for (auto [vertex, uv] : faceCorners_) {
        cage_.faceVertices.push_back(vertex);
        cornerUVs_.push_back(uv);
    }
    cage_.faceOffsets.push_back(uint32_t(cage_.faceVertices.size()));
    faceLines_.push_back(line_);
    return success();
}

// --- Tags -------------------------------------------------------------------------------------

Status ObjParser::parseTag() {
    if (tokens_.size() < 2) return error("tag line 't' has no tag name");
    TagArgs tag;
    tag.name = tokens_[1];
    std::string prefix = "tag '" + std::string(tag.name) + "': ";
    if (tokens_.size() < 3) return error(prefix + "missing the nInts/nFloats/nStrings counts");

    std::string_view countsToken = tokens_[2];
    size_t counts[3];
    size_t field = 0;
    for (size_t start = 0; field < 3; ++field) {
        size_t slash = countsToken.find('/', start);
        std::string_view part = countsToken.substr(start, slash == std::string_view::npos ? slash : slash - start);
        std::optional<uint32_t> c = parseNumber<uint32_t>(part);
        if (!c || (field < 2 && slash == std::string_view::npos) || (field == 2 && slash != std::string_view::npos))
            return error(prefix + "counts " + quoted(countsToken) + " are not of the form nInts/nFloats/nStrings");
        counts[field] = *c;
        start = slash + 1;
    }
    size_t declared = counts[0] + counts[1] + counts[2];
    size_t given = tokens_.size() - 3;
    if (given != declared)
        return error(prefix + "counts " + std::string(countsToken) + " declare " + std::to_string(declared) +
                     " values but the line has " + std::to_string(given) + " (count mismatch)");

    auto args = tokens_.begin() + 3;
    tag.ints.assign(args, args + counts[0]);
    tag.floats.assign(args + counts[0], args + counts[0] + counts[1]);
    tag.strings.assign(args + counts[0] + counts[1], tokens_.end());
    return applyTag(tag);
}

Status ObjParser::applyTag(const TagArgs& tag) {
    if (tag.name == "crease") return addCreases(tag);
    if (tag.name == "corner") return addCorners(tag);
    if (tag.name == "hole") return addHoles(tag);
    if (tag.name == "interpolateboundary" || tag.name == "facevaryinginterpolateboundary" ||
        tag.name == "facevaryingpropagatecorners" || tag.name == "creasemethod" || tag.name == "smoothtriangles")
        return setOption(tag);
    // Hierarchical edits (vertexedit, edgeedit, faceedit) are not modelled by the cage.
    note("unknown tag '" + std::string(tag.name) + "' ignored");
    return success();
}

Result<int64_t> ObjParser::tagInt(const TagArgs& tag, size_t i) {
    std::optional<int64_t> value = parseNumber<int64_t>(tag.ints[i]);
    if (!value)
        return error("tag '" + std::string(tag.name) + "': integer " + std::to_string(i + 1) + " " +
                     quoted(tag.ints[i]) + " is not an integer");
    return *value;
}

// Tag indices are 0-based, unlike face indices.
Result<uint32_t> ObjParser::tagIndex(const TagArgs& tag, size_t i) {
    Result<int64_t> value = tagInt(tag, i);
    if (!value) return value.error();
    if (*value < 0 || *value >= kIndexLimit)
        return error("tag '" + std::string(tag.name) + "': index " + std::to_string(*value) + " is out of range");
    return uint32_t(*value);
}

Result<float> ObjParser::tagSharpness(const TagArgs& tag, size_t i) {
    std::string prefix = "tag '" + std::string(tag.name) + "': sharpness ";
    std::optional<float> s = parseNumber<float>(tag.floats[i]);
    if (!s) return error(prefix + quoted(tag.floats[i]) + " is not a number");
    if (std::isnan(*s) || std::isinf(*s))
        return error(prefix + quoted(tag.floats[i]) + " is not a finite number");
    if (*s < 0.0f) return error(prefix + quoted(tag.floats[i]) + " is negative; sharpness must be >= 0");
    // OpenSubdiv treats anything from 10 up as infinitely sharp; clamping keeps that meaning.
    if (*s > kInfiniteSharpness) {
        note("sharpness above 10 clamped to 10 (infinitely sharp)");
        return kInfiniteSharpness;
    }
    return *s;
}

Status ObjParser::expectCounts(const TagArgs& tag, size_t ints, size_t floats, size_t strings) {
    if (tag.ints.size() == ints && tag.floats.size() == floats && tag.strings.size() == strings)
        return success();
    return error("tag '" + std::string(tag.name) + "' expects " + std::to_string(ints) + "/" + std::to_string(floats) +
                 "/" + std::to_string(strings) + " values (nInts/nFloats/nStrings), not " +
                 std::to_string(tag.ints.size()) + "/" + std::to_string(tag.floats.size()) + "/" +
                 std::to_string(tag.strings.size()));
}

// `t crease 2n/1/0 v0 v1 ... s` or `t crease 2n/n/0 ...`: one sharpness for all edges or one each.
Status ObjParser::addCreases(const TagArgs& tag) {
    size_t edges = tag.ints.size() / 2;
    if (tag.ints.size() % 2 != 0 || edges == 0)
        return error("tag 'crease' needs pairs of vertex indices, got " + std::to_string(tag.ints.size()) + " integers");
    if (tag.floats.size() != 1 && tag.floats.size() != edges)
        return error("tag 'crease' needs 1 sharpness or one per edge (" + std::to_string(edges) + "), got " +
                     std::to_string(tag.floats.size()));
    if (!tag.strings.empty()) return error("tag 'crease' takes no strings");
    for (size_t e = 0; e < edges; ++e) {
        Result<uint32_t> a = tagIndex(tag, 2 * e), b = tagIndex(tag, 2 * e + 1);
        if (!a) return a.error();
        if (!b) return b.error();
        if (*a == *b) return error("tag 'crease': edge " + std::to_string(*a) + "-" + std::to_string(*b) + " joins a vertex to itself");
        Result<float> s = tagSharpness(tag, tag.floats.size() == 1 ? 0 : e);
        if (!s) return s.error();
        cage_.creases.push_back({*a, *b, *s});
        creaseLines_.push_back(line_);
    }
    return success();
}

// `t corner n/1/0 v ... s` or `t corner n/n/0 ...`.
Status ObjParser::addCorners(const TagArgs& tag) {
    size_t count = tag.ints.size();
    if (count == 0) return error("tag 'corner' names no vertex");
    if (tag.floats.size() != 1 && tag.floats.size() != count)
        return error("tag 'corner' needs 1 sharpness or one per vertex (" + std::to_string(count) + "), got " +
                     std::to_string(tag.floats.size()));
    if (!tag.strings.empty()) return error("tag 'corner' takes no strings");
    for (size_t i = 0; i < count; ++i) {
        Result<uint32_t> v = tagIndex(tag, i);
        if (!v) return v.error();
        Result<float> s = tagSharpness(tag, tag.floats.size() == 1 ? 0 : i);
        if (!s) return s.error();
        cage_.corners.push_back({*v, *s});
        cornerLines_.push_back(line_);
    }
    return success();
}

Status ObjParser::addHoles(const TagArgs& tag) {
    if (Status s = expectCounts(tag, tag.ints.size(), 0, 0); !s) return s;
    for (size_t i = 0; i < tag.ints.size(); ++i) {
        Result<uint32_t> face = tagIndex(tag, i);
        if (!face) return face.error();
        cage_.holes.push_back(*face);
        holeLines_.push_back(line_);
    }
    return success();
}

Status ObjParser::setOption(const TagArgs& tag) {
    SubdivisionOptions& options = cage_.options;
    std::string name(tag.name);
    bool isString = name == "creasemethod" || name == "smoothtriangles";
    if (Status s = expectCounts(tag, isString ? 0 : 1, 0, isString ? 1 : 0); !s) return s;

    if (isString) {
        std::string_view value = tag.strings[0];
        if (name == "creasemethod" && (value == "normal" || value == "chaikin"))
            options.creaseMethod = value == "chaikin" ? CreaseMethod::Chaikin : CreaseMethod::Normal;
        else if (name == "smoothtriangles" && (value == "catmark" || value == "smooth"))
            options.triangleSubdivision = value == "smooth" ? TriangleSubdivision::Smooth : TriangleSubdivision::Catmark;
        else
            return error("tag '" + name + "': unknown value " + quoted(value) +
                         (name == "creasemethod" ? " (expected normal or chaikin)" : " (expected catmark or smooth)"));
        return success();
    }

    Result<int64_t> value = tagInt(tag, 0);
    if (!value) return value.error();
    std::optional<BoundaryInterpolation> boundary = boundaryFromTag(*value);
    if (name == "interpolateboundary" && boundary)
        options.boundary = *boundary;
    else if (name == "facevaryinginterpolateboundary" && *value >= 0 && *value <= 5)
        options.fvarInterpolation = FVarInterpolation(*value);
    else if (name == "facevaryingpropagatecorners" && (*value == 0 || *value == 1))
        options.fvarPropagateCorners = *value == 1;
    else
        return error("tag '" + name + "': value " + std::to_string(*value) + " is out of range");
    return success();
}

// --- Whole-file checks ------------------------------------------------------------------------

Status ObjParser::checkFaceReferences() const {
    for (uint32_t f = 0; f < cage_.faceCount(); ++f)
        for (uint32_t i = cage_.faceOffsets[f]; i < cage_.faceOffsets[f + 1]; ++i) {
            if (cage_.faceVertices[i] >= cage_.vertexCount())
                return errorAt(faceLines_[f], "face refers to vertex " + std::to_string(cage_.faceVertices[i] + 1) +
                                                  " but the file has " + std::to_string(cage_.vertexCount()) +
                                                  " vertices (index out of range)");
            if (cornerUVs_[i] != kNoUV && cornerUVs_[i] >= cage_.uvs.size())
                return errorAt(faceLines_[f], "face refers to texture coordinate " + std::to_string(cornerUVs_[i] + 1) +
                                                  " but the file has " + std::to_string(cage_.uvs.size()) +
                                                  " (index out of range)");
        }
    return success();
}

// Tags are checked here, with their line, rather than by validateCage, which cannot name it.
Status ObjParser::checkTagReferences() const {
    std::unordered_set<uint64_t> edges;
    auto key = [](uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
    for (uint32_t f = 0; f < cage_.faceCount(); ++f) {
        const uint32_t* fv = cage_.faceBegin(f);
        for (uint32_t i = 0, n = cage_.faceSize(f); i < n; ++i) edges.insert(key(fv[i], fv[(i + 1) % n]));
    }
    for (size_t i = 0; i < cage_.creases.size(); ++i) {
        const EdgeCrease& c = cage_.creases[i];
        if (!edges.count(key(c.v0, c.v1)))
            return errorAt(creaseLines_[i], "tag 'crease': vertices " + std::to_string(c.v0) + " and " +
                                                std::to_string(c.v1) + " (0-based) are not joined by an edge of any face");
    }
    for (size_t i = 0; i < cage_.corners.size(); ++i)
        if (cage_.corners[i].vertex >= cage_.vertexCount())
            return errorAt(cornerLines_[i], "tag 'corner': vertex " + std::to_string(cage_.corners[i].vertex) +
                                                " (0-based) is out of range; the file has " +
                                                std::to_string(cage_.vertexCount()) + " vertices");
    for (size_t i = 0; i < cage_.holes.size(); ++i)
        if (cage_.holes[i] >= fileFaceToCage_.size())
            return errorAt(holeLines_[i], "tag 'hole': face " + std::to_string(cage_.holes[i]) +
                                              " (0-based) is out of range; the file has " +
                                              std::to_string(fileFaceToCage_.size()) + " faces");
    return success();
}

// From the file's face numbering to the cage's, which lacks the dropped faces.
void ObjParser::remapHoles() {
    std::vector<uint32_t> holes;
    for (uint32_t fileFace : cage_.holes)
        if (uint32_t face = fileFaceToCage_[fileFace]; face != kDroppedFace) holes.push_back(face);
    if (holes.size() < cage_.holes.size())
        fileWarnings_.push_back(source_ + ": " + std::to_string(cage_.holes.size() - holes.size()) +
                                " hole tags name dropped faces; ignored");
    cage_.holes = std::move(holes);
}

// UVs are kept only when every face has them: face-varying data must cover the whole cage.
void ObjParser::resolveUVs() {
    uint32_t firstWithout = 0;
    bool anyWith = false;
    for (uint32_t f = 0; f < cage_.faceCount(); ++f) {
        bool has = cornerUVs_[cage_.faceOffsets[f]] != kNoUV;
        anyWith = anyWith || has;
        if (!has && firstWithout == 0) firstWithout = faceLines_[f];
    }
    if (anyWith && firstWithout == 0) {
        cage_.faceUVIndices = std::move(cornerUVs_);
        return;
    }
    if (anyWith)
        notes_.try_emplace("face has no texture coordinates while others do; texture coordinates dropped",
                           Note{firstWithout, 1});
    else if (!cage_.uvs.empty())
        fileWarnings_.push_back(source_ + ": " + std::to_string(cage_.uvs.size()) +
                                " texture coordinates ('vt') ignored: no face refers to them");
    cage_.uvs.clear();
}

void ObjParser::flushWarnings() {
    if (!warnings_) return;
    if (normalCount_ > 0)
        warnings_->push_back(source_ + ": " + std::to_string(normalCount_) +
                             " normals ('vn') ignored: subdivision surface normals are derived from the surface");
    warnings_->insert(warnings_->end(), fileWarnings_.begin(), fileWarnings_.end());
    std::vector<std::pair<Note, const std::string*>> ordered;
    for (const auto& [what, n] : notes_) ordered.push_back({n, &what});
    std::sort(ordered.begin(), ordered.end(),
              [](const auto& a, const auto& b) { return a.first.firstLine < b.first.firstLine; });
    for (const auto& [n, what] : ordered)
        warnings_->push_back(source_ + ":" + std::to_string(n.firstLine) + ": " + *what +
                             (n.count > 1 ? " (" + std::to_string(n.count) + " lines)" : ""));
}

// --- Writing ----------------------------------------------------------------------------------

void appendFloat(std::string& out, float value) {
    char buffer[32];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest round-trip form
    out.append(buffer, end);
}

void appendUint(std::string& out, uint64_t value) {
    char buffer[24];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
    out.append(buffer, end);
}

void appendFaces(std::string& out, const Cage& cage) {
    bool withUVs = !cage.faceUVIndices.empty();
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        out += 'f';
        for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i) {
            out += ' ';
            appendUint(out, uint64_t(cage.faceVertices[i]) + 1);
            if (withUVs) {
                out += '/';
                appendUint(out, uint64_t(cage.faceUVIndices[i]) + 1);
            }
        }
        out += '\n';
    }
}

void appendTags(std::string& out, const Cage& cage) {
    for (const EdgeCrease& c : cage.creases) {
        out += "t crease 2/1/0 ";
        appendUint(out, c.v0);
        out += ' ';
        appendUint(out, c.v1);
        out += ' ';
        appendFloat(out, c.sharpness);
        out += '\n';
    }
    for (const VertexCorner& c : cage.corners) {
        out += "t corner 1/1/0 ";
        appendUint(out, c.vertex);
        out += ' ';
        appendFloat(out, c.sharpness);
        out += '\n';
    }
    if (!cage.holes.empty()) {
        out += "t hole ";
        appendUint(out, cage.holes.size());
        out += "/0/0";
        for (uint32_t h : cage.holes) {
            out += ' ';
            appendUint(out, h);
        }
        out += '\n';
    }
}

// interpolateboundary is always written: readers disagree on the default.
void appendOptions(std::string& out, const SubdivisionOptions& options) {
    const SubdivisionOptions defaults;
    out += "t interpolateboundary 1/0/0 ";
    appendUint(out, boundaryTagValue(options.boundary));
    out += '\n';
    if (options.fvarInterpolation != defaults.fvarInterpolation) {
        out += "t facevaryinginterpolateboundary 1/0/0 ";
        appendUint(out, uint64_t(options.fvarInterpolation));
        out += '\n';
    }
    if (options.fvarPropagateCorners != defaults.fvarPropagateCorners)
        out += options.fvarPropagateCorners ? "t facevaryingpropagatecorners 1/0/0 1\n"
                                            : "t facevaryingpropagatecorners 1/0/0 0\n";
    if (options.creaseMethod != defaults.creaseMethod)
        out += options.creaseMethod == CreaseMethod::Chaikin ? "t creasemethod 0/0/1 chaikin\n"
                                                             : "t creasemethod 0/0/1 normal\n";
    if (options.triangleSubdivision != defaults.triangleSubdivision)
        out += options.triangleSubdivision == TriangleSubdivision::Smooth ? "t smoothtriangles 0/0/1 smooth\n"
                                                                          : "t smoothtriangles 0/0/1 catmark\n";
}

}  // namespace

Result<Cage> parseObj(std::string_view text, const std::string& source, std::vector<std::string>* warnings) {
    return ObjParser(source, warnings).parse(text);
}

Result<Cage> loadObj(const std::string& path, std::vector<std::string>* warnings) {
    Result<std::string> text = readFile(path);
    if (!text) return text.error();
    return parseObj(*text, path, warnings);
}

std::string formatObj(const Cage& cage) {
    std::string out;
    out.reserve(cage.positions.size() * 32 + cage.faceVertices.size() * 12 + cage.creases.size() * 32 + 256);
    out += "# Catmull-Clark cage written by Quadplan; 't' lines are OpenSubdiv subdivision tags\n";
    for (const glm::vec3& p : cage.positions) {
        out += 'v';
        for (int i = 0; i < 3; ++i) {
            out += ' ';
            appendFloat(out, p[i]);
        }
        out += '\n';
    }
    if (!cage.faceUVIndices.empty())
        for (const glm::vec2& uv : cage.uvs) {
            out += "vt ";
            appendFloat(out, uv.x);
            out += ' ';
            appendFloat(out, uv.y);
            out += '\n';
        }
    appendFaces(out, cage);
    appendTags(out, cage);
    appendOptions(out, cage.options);
    return out;
}

Status saveObj(const Cage& cage, const std::string& path) {
    return writeFileAtomically(path, formatObj(cage));
}

}  // namespace qp
