#include "mesh/mesh_file_check.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>
#include <vector>

namespace qp {

namespace {

// Whitespace-separated words of a text, with the line each starts on.
class Words {
public:
    explicit Words(std::string_view text) : text_(text) {}
    bool next(std::string_view& word) {
        while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) {
            if (text_[at_] == '\n') ++line_;
            ++at_;
        }
        if (at_ >= text_.size()) return false;
        const size_t start = at_;
        while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
        word = text_.substr(start, at_ - start);
        return true;
    }
    // The rest of the current line, dropped (OFF faces may carry colours after their corners).
    void skipLine() {
        while (at_ < text_.size() && text_[at_] != '\n') ++at_;
    }
    int line() const { return line_; }

private:
    std::string_view text_;
    size_t at_ = 0;
    int line_ = 1;
};

bool parseNumber(std::string_view word, double& value) {
    const char* end = word.data() + word.size();
    const auto [ptr, ec] = std::from_chars(word.data(), end, value);
    return ec == std::errc() && ptr == end && std::isfinite(value);
}

bool parseIndex(std::string_view word, long long& value) {
    const char* end = word.data() + word.size();
    const auto [ptr, ec] = std::from_chars(word.data(), end, value);
    return ec == std::errc() && ptr == end;
}

// A number read from a file for a message: whole when it is one, else as it came.
std::string numberText(double value) {
    if (std::abs(value) < 1e15 && value == std::floor(value)) return std::to_string((long long)value);
    return std::to_string(value);
}

Error at(const std::string& source, const std::string& where, const std::string& what) {
    return Error{source + ": " + where + ": " + what};
}

// ---- PLY ------------------------------------------------------------------------------------

enum class PlyType : uint8_t { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64, None };

PlyType plyType(std::string_view name) {
    if (name == "char" || name == "int8") return PlyType::Int8;
    if (name == "uchar" || name == "uint8") return PlyType::Uint8;
    if (name == "short" || name == "int16") return PlyType::Int16;
    if (name == "ushort" || name == "uint16") return PlyType::Uint16;
    if (name == "int" || name == "int32") return PlyType::Int32;
    if (name == "uint" || name == "uint32") return PlyType::Uint32;
    if (name == "float" || name == "float32") return PlyType::Float32;
    if (name == "double" || name == "float64") return PlyType::Float64;
    return PlyType::None;
}

size_t plySize(PlyType t) {
    switch (t) {
    case PlyType::Int8:
    case PlyType::Uint8: return 1;
    case PlyType::Int16:
    case PlyType::Uint16: return 2;
    case PlyType::Int32:
    case PlyType::Uint32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
    case PlyType::None: break;
    }
    return 0;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::None, countType = PlyType::None;  // countType: lists only
    bool list = false;
};
struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> properties;
};

// A binary value of type `t` at `p` as a double (the caller checked the bytes are there).
double binaryValue(const unsigned char* p, PlyType t, bool bigEndian) {
    unsigned char b[8];
    const size_t n = plySize(t);
    std::memcpy(b, p, n);
    if (bigEndian != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
    switch (t) {
    case PlyType::Int8: return double(int8_t(b[0]));
    case PlyType::Uint8: return double(b[0]);
    case PlyType::Int16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::Uint16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::Int32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Uint32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    case PlyType::None: break;
    }
    return 0.0;
}

bool isCornerList(const PlyElement& e, const PlyProperty& p) {
    return e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
}
bool isPosition(const PlyElement& e, const PlyProperty& p) {
    return e.name == "vertex" && !p.list && (p.name == "x" || p.name == "y" || p.name == "z");
}

// Checks one value read for property `p` of element `e` (record `r`), `i` its place in a list.
Status checkPlyValue(const PlyElement& e, const PlyProperty& p, long long r, double value, long long vertices,
                     const std::string& source) {
    const std::string where = e.name + " " + std::to_string(r + 1) + ", " + p.name;
    if (!std::isfinite(value)) return at(source, where, "not a finite number");
    if (isCornerList(e, p) && (value < 0 || value >= double(vertices) || value != std::floor(value)))
        return at(source, where, "names vertex " + numberText(value) + ", but there are " + std::to_string(vertices));
    return success();
}

Status checkListCount(const PlyElement& e, const PlyProperty& p, long long r, double count, size_t left,
                      const std::string& source) {
    const std::string where = e.name + " " + std::to_string(r + 1) + ", " + p.name;
    if (!(count >= 0) || count != std::floor(count)) return at(source, where, "the list length is not a count");
    if (isCornerList(e, p) && (count < 3 || count > kMaxFaceCorners))
        return at(source, where, "a face of " + numberText(count) + " corners (3 to " +
                                     std::to_string(kMaxFaceCorners) + " are read)");
    if (count > double(left)) return at(source, where, "the list is longer than the rest of the file");
    return success();
}

}  // namespace

Result<DeclaredCounts> checkPlyFile(const std::string& bytes, const std::string& source) {
    if (bytes.rfind("ply\n", 0) != 0 && bytes.rfind("ply\r\n", 0) != 0)
        return Error{source + ": not a PLY file (it must start with a 'ply' line)"};
    // The line that is exactly "end_header" (OpenMesh's reader looks for that word and nothing else).
    size_t headerEnd = bytes.find("\nend_header");
    while (headerEnd != std::string::npos) {
        const size_t after = headerEnd + 11;
        if (after == bytes.size() || bytes[after] == '\n' || (bytes[after] == '\r' && after + 1 < bytes.size() && bytes[after + 1] == '\n'))
            break;
        headerEnd = bytes.find("\nend_header", after);
    }
    if (headerEnd == std::string::npos) return Error{source + ": the PLY header has no 'end_header' line"};
    const size_t bodyStart = bytes.find('\n', headerEnd + 1);
    std::vector<PlyElement> elements;
    std::string format;
    {
        Words header(std::string_view(bytes).substr(0, headerEnd + 1));
        std::string_view word;
        header.next(word);  // "ply"
        int lastLine = 0;
        std::vector<std::string_view> line;
        auto flush = [&](int number) -> Status {
            if (line.empty()) return success();
            const std::string where = "PLY header line " + std::to_string(number);
            const std::string_view keyword = line[0];
            if (keyword == "comment" || keyword == "obj_info") {
            } else if (keyword == "format") {
                if (line.size() != 3 || (line[1] != "ascii" && line[1] != "binary_little_endian" && line[1] != "binary_big_endian") ||
                    line[2] != "1.0")
                    return at(source, where, "the format must be ascii, binary_little_endian or binary_big_endian, version 1.0");
                if (!format.empty()) return at(source, where, "a second format line");
                format = std::string(line[1]);
            } else if (keyword == "element") {
                long long count = -1;
                if (format.empty()) return at(source, where, "an element before the format line");
                if (line.size() != 3 || !parseIndex(line[2], count) || count < 0)
                    return at(source, where, "an element needs a name and a count");
                if (line[1] != "vertex" && line[1] != "face")
                    return at(source, where, "only vertex and face elements are read, not '" + std::string(line[1].substr(0, 40)) + "'");
                elements.push_back({std::string(line[1]), count, {}});
            } else if (keyword == "property") {
                if (elements.empty()) return at(source, where, "a property before any element");
                PlyProperty p;
                p.list = line.size() == 5 && line[1] == "list";
                if (p.list) p.countType = plyType(line[2]), p.type = plyType(line[3]), p.name = std::string(line[4]);
                else if (line.size() == 3) p.type = plyType(line[1]), p.name = std::string(line[2]);
                if (p.type == PlyType::None || (p.list && p.countType == PlyType::None))
                    return at(source, where, "a property needs a known type and a name ('property float x', "
                                             "'property list uchar int vertex_indices')");
                elements.back().properties.push_back(p);
            } else {
                return at(source, where, "'" + std::string(keyword.substr(0, 40)) + "' is not a PLY header keyword");
            }
            line.clear();
            return success();
        };
        while (header.next(word)) {
            if (header.line() != lastLine) {
                if (Status s = flush(lastLine); !s) return s.error();
                lastLine = header.line();
            }
            line.push_back(word);
        }
        if (Status s = flush(lastLine); !s) return s.error();
    }
    if (format.empty()) return Error{source + ": the PLY header has no format line"};
    DeclaredCounts counts;
    for (const PlyElement& e : elements) {
        if (e.name == "vertex") counts.vertices = e.count;
        if (e.name == "face") counts.faces = e.count;
    }
    if (counts.vertices < 0) return Error{source + ": the PLY header declares no vertex element"};
    const long long vertices = counts.vertices;
    if (bodyStart == std::string::npos) return counts.vertices == 0 && counts.faces <= 0 ? Result<DeclaredCounts>(counts)
                                                                                        : Error{source + ": the PLY file ends after its header"};
    const std::string_view body = std::string_view(bytes).substr(bodyStart + 1);
    for (const PlyElement& e : elements)  // every record takes at least a byte
        if (e.count > 0 && (e.properties.empty() || e.count > (long long)body.size()))
            return Error{source + ": the PLY header declares " + std::to_string(e.count) + " " + e.name +
                         " records, more than its " + std::to_string(body.size()) + " bytes of data can hold"};

    if (format == "ascii") {  // one record per line, as the reader takes them
        size_t next = 0;
        int lineNumber = 0;
        for (const PlyElement& e : elements)
            for (long long r = 0; r < e.count; ++r) {
                const size_t end = std::min(body.find('\n', next), body.size());
                if (next >= body.size()) return at(source, e.name + " " + std::to_string(r + 1), "the file ends early (a truncated file?)");
                Words words(body.substr(next, end - next));
                next = end + 1;
                ++lineNumber;
                const std::string where = "data line " + std::to_string(lineNumber) + " (" + e.name + " " + std::to_string(r + 1) + ")";
                std::string_view word;
                for (const PlyProperty& p : e.properties) {
                    double value = 0.0;
                    if (!words.next(word) || !parseNumber(word, value)) return at(source, where, "a number is missing or not finite");
                    if (!p.list) {
                        if (Status s = checkPlyValue(e, p, r, value, vertices, source); !s) return s.error();
                        continue;
                    }
                    if (Status s = checkListCount(e, p, r, value, body.size(), source); !s) return s.error();
                    for (long long i = 0; i < (long long)value; ++i) {
                        double item = 0.0;
                        if (!words.next(word) || !parseNumber(word, item)) return at(source, where, "a list item is missing or not finite");
                        if (Status s = checkPlyValue(e, p, r, item, vertices, source); !s) return s.error();
                    }
                }
                if (words.next(word)) return at(source, where, "more values than the header's properties");
            }
        return counts;
    }
    const bool bigEndian = format == "binary_big_endian";
    const auto* data = reinterpret_cast<const unsigned char*>(body.data());
    size_t offset = 0;
    for (const PlyElement& e : elements)
        for (long long r = 0; r < e.count; ++r)
            for (const PlyProperty& p : e.properties) {
                const PlyType countOrValue = p.list ? p.countType : p.type;
                if (offset + plySize(countOrValue) > body.size())
                    return at(source, e.name + " " + std::to_string(r + 1), "the binary data ends early (a truncated file?)");
                const double value = binaryValue(data + offset, countOrValue, bigEndian);
                offset += plySize(countOrValue);
                if (!p.list) {
                    if (isPosition(e, p) || isCornerList(e, p))
                        if (Status s = checkPlyValue(e, p, r, value, vertices, source); !s) return s.error();
                    continue;
                }
                if (Status s = checkListCount(e, p, r, value, (body.size() - offset) / plySize(p.type), source); !s) return s.error();
                for (long long i = 0; i < (long long)value; ++i, offset += plySize(p.type))
                    if (isCornerList(e, p))
                        if (Status s = checkPlyValue(e, p, r, binaryValue(data + offset, p.type, bigEndian), vertices, source); !s)
                            return s.error();
            }
    return counts;
}

Result<DeclaredCounts> checkOffFile(const std::string& bytes, const std::string& source) {
    // The first line is "OFF" and nothing else (the reader takes what follows the keyword on its
    // line for the variants' dimensions, and the counts from the next line).
    const size_t firstEnd = std::min(bytes.find('\n'), bytes.size());
    std::string_view first = std::string_view(bytes).substr(0, firstEnd);
    while (!first.empty() && std::isspace(static_cast<unsigned char>(first.back()))) first.remove_suffix(1);
    if (first != "OFF") {
        if (first.find("OFF") != std::string_view::npos)
            return Error{source + ": the first line is '" + std::string(first.substr(0, 24)) + "'; only plain OFF is read ('OFF' "
                                  "alone on the first line, the counts below it)"};
        return Error{source + ": not an OFF file (it must start with 'OFF')"};
    }
    // Line by line and token by token alike (the reader takes vertices by lines and faces by
    // tokens): comments only before the counts, then one vertex per line (three numbers) and one
    // face per line (its corner count and the corners, nothing more), no blank lines between.
    std::vector<std::string_view> lines;
    for (size_t at = firstEnd + 1; at < bytes.size();) {
        const size_t end = std::min(bytes.find('\n', at), bytes.size());
        lines.push_back(std::string_view(bytes).substr(at, end - at));
        at = end + 1;
    }
    auto tokens = [](std::string_view line) {
        std::vector<std::string_view> out;
        Words words(line);
        for (std::string_view w; words.next(w);) out.push_back(w);
        return out;
    };
    DeclaredCounts counts;
    size_t l = 0;
    while (l < lines.size() && (tokens(lines[l]).empty() || tokens(lines[l])[0][0] == '#')) ++l;
    const std::vector<std::string_view> header = l < lines.size() ? tokens(lines[l]) : std::vector<std::string_view>{};
    long long edges = 0;
    if (header.size() != 3 || !parseIndex(header[0], counts.vertices) || !parseIndex(header[1], counts.faces) ||
        !parseIndex(header[2], edges) || counts.vertices < 0 || counts.faces < 0)
        return Error{source + ": the OFF header needs its vertex, face and edge counts on one line"};
    ++l;
    const long long available = (long long)(lines.size() - l);
    if (counts.vertices > available || counts.faces > available - counts.vertices)
        return Error{source + ": the header declares " + std::to_string(counts.vertices) + " vertices and " +
                     std::to_string(counts.faces) + " faces, more than its " + std::to_string(lines.size() - l) +
                     " lines after the header can hold"};
    for (long long v = 0; v < counts.vertices; ++v, ++l) {
        const std::vector<std::string_view> t = tokens(lines[l]);
        double value = 0.0;
        if (t.size() != 3 || !parseNumber(t[0], value) || !parseNumber(t[1], value) || !parseNumber(t[2], value))
            return at(source, "line " + std::to_string(l + 2) + " (vertex " + std::to_string(v + 1) + ")",
                      "a vertex is three finite numbers on one line");
    }
    for (long long f = 0; f < counts.faces; ++f, ++l) {
        const std::vector<std::string_view> t = tokens(lines[l]);
        const std::string where = "line " + std::to_string(l + 2) + " (face " + std::to_string(f + 1) + ")";
        long long corners = 0;
        if (t.empty() || !parseIndex(t[0], corners)) return at(source, where, "the face's corner count is missing");
        if (corners < 3 || corners > kMaxFaceCorners)
            return at(source, where, "a face of " + std::to_string(corners) + " corners (3 to " + std::to_string(kMaxFaceCorners) + " are read)");
        if ((long long)t.size() != corners + 1)
            return at(source, where, "a face is its corner count and that many corners on one line (face colours are not read)");
        for (long long k = 1; k <= corners; ++k) {
            long long index = -1;
            if (!parseIndex(t[size_t(k)], index)) return at(source, where, "a corner is not a vertex number");
            if (index < 0 || index >= counts.vertices)
                return at(source, where, "names vertex " + std::to_string(index) + ", but there are " + std::to_string(counts.vertices));
        }
    }
    return counts;
}

Result<DeclaredCounts> checkStlFile(const std::string& bytes, const std::string& source) {
    DeclaredCounts counts;
    if (bytes.size() >= 84) {
        uint32_t triangles = 0;
        std::memcpy(&triangles, bytes.data() + 80, 4);
        if (84 + 50ull * triangles == bytes.size()) {  // binary (its header may start with "solid" too)
            for (uint32_t t = 0; t < triangles; ++t)
                for (int k = 0; k < 12; ++k) {
                    float value = 0.0f;
                    std::memcpy(&value, bytes.data() + 84 + 50 * size_t(t) + 4 * size_t(k), 4);
                    if (!std::isfinite(value)) return at(source, "triangle " + std::to_string(t + 1), "a number is not finite");
                }
            counts.faces = triangles;
            return counts;
        }
    }
    if (bytes.rfind("solid", 0) != 0)
        return Error{source + ": not an STL file (binary STL is 84 bytes and 50 per triangle its header counts; ASCII STL "
                              "starts with 'solid')"};
    Words words(bytes);
    std::string_view word;
    words.next(word);  // solid
    words.skipLine();  // its name
    long long facets = 0;
    auto expect = [&](std::string_view keyword) {
        return words.next(word) && word == keyword;
    };
    auto numbers = [&](int n) {
        double value = 0.0;
        for (int k = 0; k < n; ++k)
            if (!words.next(word) || !parseNumber(word, value)) return false;
        return true;
    };
    while (words.next(word)) {
        if (word == "endsolid") return counts;
        const std::string where = "line " + std::to_string(words.line()) + " (facet " + std::to_string(facets + 1) + ")";
        if (word != "facet" || !expect("normal") || !numbers(3) || !expect("outer") || !expect("loop"))
            return at(source, where, "expected 'facet normal X Y Z' and 'outer loop'");
        for (int k = 0; k < 3; ++k)
            if (!expect("vertex") || !numbers(3)) return at(source, where, "expected three 'vertex X Y Z' lines of finite numbers");
        if (!expect("endloop") || !expect("endfacet")) return at(source, where, "expected 'endloop' and 'endfacet'");
        ++facets;
    }
    return Error{source + ": the ASCII STL has no 'endsolid' line (a truncated file?)"};
}

// ---- OpenMesh .om ---------------------------------------------------------------------------

Result<OmCounts> checkOmFile(const std::string& bytes, const std::string& source) {
    auto u32 = [&](size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);  // little-endian files on little-endian hosts
        return v;
    };
    if (bytes.size() < 16 || bytes[0] != 'O' || bytes[1] != 'M')
        return Error{source + ": not an OpenMesh .om file (it must start with 'OM' and a 16-byte header)"};
    OmCounts counts;
    counts.meshType = bytes[2];
    counts.version = uint8_t(bytes[3]);
    if (counts.meshType != 'T' && counts.meshType != 'Q' && counts.meshType != 'P')
        return Error{source + ": the .om header names an unknown mesh type (byte 2 must be T, Q or P)"};
    if (counts.version > kOmVersion)
        return Error{source + ": written by a newer OpenMesh (.om version " + std::to_string(counts.version >> 5) + "." +
                     std::to_string(counts.version & 31) + "; this build reads up to 2.2)"};
    counts.vertices = u32(4), counts.faces = u32(8), counts.edges = u32(12);
    const uint64_t V = counts.vertices, F = counts.faces, E = counts.edges;
    // What the counts need at the least (three floats a position; from 2.0 six indices of a byte or
    // more an edge, one a face): a header that claims more is corrupt, and is refused before
    // anything is sized from it.
    const uint64_t edgeBytes = counts.version >= (2 << 5) ? 6 : 1;
    if (V * 12 > bytes.size() || F > bytes.size() || E * edgeBytes > bytes.size())
        return Error{source + ": the .om header declares more vertices, faces or edges than the file has bytes for (a corrupt header)"};
    size_t at = 16;
    uint32_t customChunks = 0;
    std::string problem;
    auto take = [&](uint64_t n, const char* what) {
        if (n > bytes.size() - at) {
            problem = "byte " + std::to_string(at) + ": the " + std::string(what) + " runs past the end of the file (a truncated file?)";
            return false;
        }
        at += size_t(n);
        return true;
    };
    auto custom = [&](size_t chunkStart) {
        if (++customChunks > 64) {
            problem = "more than 64 custom property chunks (a corrupt file?)";
            return false;
        }
        bool variableSized = false;
        if (counts.version > ((2 << 5) | 1)) {  // 2.2 names the property's type
            if (at >= bytes.size()) return take(1, "property type");
            const std::string_view typeName = std::string_view(bytes).substr(at + 1, uint8_t(bytes[at]));
            variableSized = typeName.find("vector") != std::string_view::npos || typeName.find("string") != std::string_view::npos;
            if (!take(1 + uint8_t(bytes[at]), "property type")) return false;
        }
        if (bytes.size() - at < 4) return take(4, "property size");
        const uint32_t block = u32(at);
        if (!take(4, "property size") || !take(block, "property data")) return false;
        if (variableSized) counts.skippedChunks.push_back({chunkStart, at});
        return true;
    };
    while (at < bytes.size()) {
        const size_t chunkStart = at;
        if (bytes.size() - at < 2) return Error{source + ": byte " + std::to_string(at) + ": half a chunk header at the end"};
        const uint16_t header = uint16_t(uint8_t(bytes[at]) | uint8_t(bytes[at + 1]) << 8);
        at += 2;
        const bool named = (header >> 1) & 1, isFloat = (header >> 10) & 1;
        const uint32_t entity = (header >> 2) & 7, type = (header >> 5) & 15, dims = ((header >> 11) & 7) + 1, bits = (header >> 14) & 3;
        if (named && (at >= bytes.size() || !take(1 + uint8_t(bytes[at]), "property name")))
            return Error{source + ": " + (problem.empty() ? "a property name runs past the end of the file" : problem)};
        enum { Vertex = 0, Mesh = 1, Face = 2, Edge = 4, Halfedge = 6, Sentinel = 7 };
        enum { Pos = 0, Normal = 1, Texcoord = 2, Status = 3, Color = 4, Custom = 6, Topology = 7 };
        if (entity == Sentinel) return counts;
        const uint64_t elements = entity == Vertex ? V : entity == Face ? F : entity == Edge ? E : entity == Halfedge ? 2 * E : 1;
        if (entity != Vertex && entity != Mesh && entity != Face && entity != Edge && entity != Halfedge)
            return Error{source + ": byte " + std::to_string(at - 2) + ": a chunk of an unknown kind (entity " + std::to_string(entity) + ")"};
        const uint64_t index = uint64_t(1) << bits, scalar = isFloat ? (uint64_t(1) << bits) : (uint64_t(4) << bits);
        auto vectors = [&](const char* what) {  // positions and normals: floats or doubles, three each
            if (bits > 1) {
                problem = std::string(what) + " that are neither floats nor doubles";
                return false;
            }
            return take(elements * (bits == 0 ? 12 : 24), what);
        };
        // The reader asserts each standard chunk's dimension (and Debian builds it with asserts on).
        const uint32_t expected = type == Pos || type == Normal || type == Color ? 3 : type == Texcoord ? 2 : 1;
        if ((type == Pos || type == Normal || type == Texcoord || type == Color || type == Status) && entity != Mesh &&
            dims != expected)
            return Error{source + ": byte " + std::to_string(at - 2) + ": a chunk of " + std::to_string(dims) +
                         "-component values where OpenMesh expects " + std::to_string(expected)};
        bool ok = true;
        if (type == Custom) ok = custom(chunkStart);
        else if (entity == Vertex && type == Pos) ok = vectors("vertex positions");
        else if ((entity == Vertex || entity == Face) && type == Normal) ok = vectors("normals");
        else if (entity == Vertex && type == Texcoord) ok = take(V * 8, "texture coordinates");
        else if ((entity == Vertex || entity == Face) && type == Color) ok = take(elements * 3, "colours");
        else if (entity != Mesh && type == Status) ok = take(elements * 4, "status flags");
        else if (entity == Vertex && type == Topology) ok = take(V * index, "vertex topology");
        else if (entity == Halfedge && type == Topology) ok = take(E * 6 * index, "half-edge topology");
        else if (entity == Face && type == Topology && counts.version >= (2 << 5)) ok = take(F * index, "face topology");
        else if (entity == Face && type == Topology) {  // before 2.0: vertex lists
            for (uint64_t f = 0; ok && f < F; ++f) {
                uint64_t corners = counts.meshType == 'T' ? 3 : 4;
                if (counts.meshType == 'P') {
                    if (bytes.size() - at < 2) ok = take(2, "face list");
                    else corners = uint8_t(bytes[at]) | uint8_t(bytes[at + 1]) << 8, ok = take(2, "face list");
                }
                ok = ok && take(corners * index, "face list");
            }
        } else {
            ok = take(elements * dims * scalar, "chunk");  // what the reader skips
        }
        if (!ok) return Error{source + ": " + problem};
    }
    return counts;
}

}  // namespace qp
