// PLY, OFF and STL cages through OpenMesh's readers (core/mesh/mesh_import.h), and written back
// (core/mesh/mesh_cage_write.h): every face read, in order and winding, non-manifold ones too; what
// the file declares checked; bad files refused with a message naming the file, nothing half read.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "mesh/mesh_cage_write.h"
#include "mesh/mesh_file_check.h"
#include "mesh/mesh_import.h"
#include "mesh/topology.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
namespace fs = std::filesystem;

namespace {

class MeshImport : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("quadplan_mesh_import_" + std::to_string(getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }

    std::string write(const std::string& name, const std::string& bytes) {
        const fs::path path = dir / name;
        std::ofstream(path, std::ios::binary) << bytes;
        return path.string();
    }
};

std::string offOf(const Cage& cage) {
    std::string text = "OFF\n" + std::to_string(cage.vertexCount()) + " " + std::to_string(cage.faceCount()) + " 0\n";
    for (const glm::vec3& p : cage.positions)
        text += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        text += std::to_string(cage.faceSize(f));
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) text += " " + std::to_string(cage.faceBegin(f)[k]);
        text += "\n";
    }
    return text;
}

template <class T>
void append(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

TEST_F(MeshImport, ReadsEveryFaceOfOffAndPlyInOrderAndWinding) {
    const Cage mixed = test::makeMixedGrid();  // quads, a triangle, a pentagon
    for (const std::string& name : {std::string("mixed.off")}) {
        Result<Cage> cage = loadMeshCage(write(name, offOf(mixed)));
        ASSERT_TRUE(cage) << cage.error().message;
        EXPECT_EQ(cage->faceOffsets, mixed.faceOffsets);
        EXPECT_EQ(cage->faceVertices, mixed.faceVertices);
        ASSERT_EQ(cage->positions.size(), mixed.positions.size());
        for (size_t v = 0; v < mixed.positions.size(); ++v) EXPECT_LT(glm::length(cage->positions[v] - mixed.positions[v]), 1e-5f);
    }
    // Binary little-endian PLY with quads (int indices, float positions) and an ASCII one.
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(mixed.vertexCount()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(mixed.faceCount()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const glm::vec3& p : mixed.positions) append(ply, p);
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) {
        append(ply, uint8_t(mixed.faceSize(f)));
        for (uint32_t k = 0; k < mixed.faceSize(f); ++k) append(ply, int32_t(mixed.faceBegin(f)[k]));
    }
    Result<Cage> binary = loadMeshCage(write("mixed.ply", ply));
    ASSERT_TRUE(binary) << binary.error().message;
    EXPECT_EQ(binary->faceVertices, mixed.faceVertices);
    EXPECT_EQ(binary->positions, mixed.positions);
    // The same file declared big-endian is read as such: its numbers are garbage (counts of corners
    // past 1024, indices past the vertices, or non-finite positions) and it is refused; written
    // big-endian for real, it reads the same cage.
    std::string mislabelled = ply;
    mislabelled.replace(mislabelled.find("binary_little_endian"), 20, "binary_big_endian");
    Result<Cage> wrongEndian = loadMeshCage(write("wrong_endian.ply", mislabelled));
    ASSERT_FALSE(wrongEndian) << "a little-endian body read as big-endian was accepted";
    EXPECT_NE(wrongEndian.error().message.find("wrong_endian.ply"), std::string::npos) << wrongEndian.error().message;
    auto bigEndian = [](auto value) {
        std::string bytes(reinterpret_cast<const char*>(&value), sizeof value);
        std::reverse(bytes.begin(), bytes.end());
        return bytes;
    };
    std::string big = "ply\nformat binary_big_endian 1.0\nelement vertex " + std::to_string(mixed.vertexCount()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(mixed.faceCount()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const glm::vec3& p : mixed.positions) big += bigEndian(p.x) + bigEndian(p.y) + bigEndian(p.z);
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) {
        big += char(mixed.faceSize(f));
        for (uint32_t k = 0; k < mixed.faceSize(f); ++k) big += bigEndian(int32_t(mixed.faceBegin(f)[k]));
    }
    Result<Cage> bigCage = loadMeshCage(write("big_endian.ply", big));
    ASSERT_TRUE(bigCage) << bigCage.error().message;
    EXPECT_EQ(bigCage->faceVertices, mixed.faceVertices);
    EXPECT_EQ(bigCage->positions, mixed.positions);
    // Everywhere a cage opens: loadSceneOrCage (info, render, edit, File > Open, Python's load).
    Result<Scene> scene = loadSceneOrCage((dir / "mixed.ply").string());
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->objects.at(0).name, "mixed");
    EXPECT_EQ(scene->objects[0].cage.faceCount(), mixed.faceCount());
}

TEST_F(MeshImport, NonManifoldFacesAreReadNotDropped) {
    // Three quads around one edge: OpenMesh's kernel would refuse the third.
    const std::string off = "OFF\n7 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 0 1\n0 0 1\n0 0 -1\n4 0 1 2 3\n4 0 1 4 5\n4 1 0 5 6\n";
    Result<Cage> cage = loadMeshCage(write("fan.off", off));
    ASSERT_TRUE(cage) << cage.error().message;
    EXPECT_EQ(cage->faceCount(), 3u);
    EXPECT_EQ(computeStats(*cage, buildTopology(*cage)).nonManifoldEdges, 1u);
}

TEST_F(MeshImport, StlTrianglesAreWelded) {
    // A binary STL of a tetrahedron: 4 triangles, 12 corners, 4 distinct positions.
    const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int tris[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string stl(80, ' ');
    append(stl, uint32_t(4));
    for (const auto& t : tris) {
        append(stl, glm::vec3(0.0f));
        for (int k = 0; k < 3; ++k) append(stl, p[t[k]]);
        append(stl, uint16_t(0));
    }
    std::vector<std::string> warnings;
    Result<Cage> cage = loadMeshCage(write("tet.stl", stl), &warnings);
    ASSERT_TRUE(cage) << cage.error().message;
    EXPECT_EQ(cage->vertexCount(), 4u);
    EXPECT_EQ(cage->faceCount(), 4u);
    const CageStats stats = computeStats(*cage, buildTopology(*cage));
    EXPECT_EQ(stats.boundaryEdges, 0u) << "the welded tetrahedron is closed";
    EXPECT_EQ(stats.nonManifoldEdges, 0u);
    EXPECT_FALSE(warnings.empty());
}

TEST_F(MeshImport, BadFilesAreRefusedNamingTheFile) {
    struct Case {
        const char* name;
        std::string bytes;
        const char* says;
    };
    std::string truncated = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    append(truncated, glm::vec3(0.0f));  // one vertex of four, no face
    std::string shortStl(80, ' ');
    append(shortStl, uint32_t(1000000));
    const Case cases[] = {
        {"huge.off", "OFF\n999999999 1 0\n0 0 0\n", "more than its"},
        {"index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 7\n", "names vertex 7, but there are 3"},
        {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n1 1 0\n3 0 1 2\n", "line 4 (vertex 2): a vertex is three finite numbers on one line"},
        {"truncated.ply", truncated, "truncated"},
        {"short.stl", shortStl, "not an STL file"},
        {"bigface.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n999999999 0 1 2\n", "a face of 999999999 corners"},
        {"biglist.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                        "element face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n",
         "a face of 2000000000 corners"},
        {"noheader.ply", "ply\nformat ascii 1.0\n", "end_header"},
        {"repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 1\n", "repeat.off"},
        {"notoff.off", "hello\n", "not an OFF file"},
        {"shortoff.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n", "lines after the header"},  // a fuzzer find
        // The fuzzer's first find: OpenMesh's header parser crashed on a property before any element.
        {"noelement.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "a property before any element"},
        {"badtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n", "known type"},
    };
    for (const Case& c : cases) {
        const std::string path = write(c.name, c.bytes);
        Result<Cage> cage = loadMeshCage(path);
        ASSERT_FALSE(cage) << c.name << " was read";
        EXPECT_NE(cage.error().message.find(path), std::string::npos) << cage.error().message;
        EXPECT_NE(cage.error().message.find(c.says), std::string::npos) << c.name << ": " << cage.error().message;
    }
    EXPECT_FALSE(loadMeshCage((dir / "missing.ply").string()));
}

TEST_F(MeshImport, CagesWrittenAsPlyOffAndStlReadBack) {
    Cage mixed = test::makeMixedGrid();
    mixed.setEdgeSharpness(mixed.faceBegin(0)[0], mixed.faceBegin(0)[1], 2.0f);
    for (const char* ext : {".ply", ".off"}) {
        const std::string path = (dir / (std::string("cage") + ext)).string();
        std::vector<std::string> lost;
        ASSERT_TRUE(saveMeshCage(mixed, path, &lost)) << ext;
        ASSERT_EQ(lost.size(), 1u) << ext;
        EXPECT_NE(lost[0].find("1 creases"), std::string::npos) << lost[0];
        Result<Cage> back = loadMeshCage(path);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_EQ(back->faceVertices, mixed.faceVertices) << ext;
        EXPECT_EQ(back->faceOffsets, mixed.faceOffsets) << ext;
        EXPECT_EQ(back->positions, mixed.positions) << ext << ": shortest round-trip floats";
        EXPECT_TRUE(back->creases.empty());
    }
    // STL: triangles (polygons fanned), welded back to the cage's vertices.
    const std::string stl = (dir / "cage.stl").string();
    std::vector<std::string> lost;
    ASSERT_TRUE(saveMeshCage(mixed, stl, &lost));
    EXPECT_EQ(lost.size(), 2u) << "creases and the fanned polygons";
    Result<Cage> back = loadMeshCage(stl);
    ASSERT_TRUE(back) << back.error().message;
    uint32_t triangles = 0;
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) triangles += mixed.faceSize(f) - 2;
    EXPECT_EQ(back->faceCount(), triangles);
    EXPECT_EQ(back->vertexCount(), mixed.vertexCount());
    EXPECT_FALSE(saveMeshCage(mixed, (dir / "cage.fbx").string()));
    EXPECT_FALSE(fs::exists(dir / "cage.fbx"));
}

namespace {

// A cage with every tag and option .om carries: creases (one infinite), a corner, a hole, UVs
// with a seam, n-gons, options other than the defaults.
Cage taggedMixedGrid() {
    Cage cage = test::makeMixedGrid();
    cage.setEdgeSharpness(0, 1, 2.5f);
    cage.setEdgeSharpness(6, 7, kInfiniteSharpness);
    cage.setVertexSharpness(12, 3.0f);
    cage.setHole(2, true);
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) {
            const glm::vec3 p = cage.positions[cage.faceBegin(f)[k]];
            cage.faceUVIndices.push_back(uint32_t(cage.uvs.size()));  // every corner its own UV: seams everywhere
            cage.uvs.push_back({p.x * 0.25f + float(f) * 1e-3f, p.y * 0.25f});
        }
    cage.options.boundary = BoundaryInterpolation::EdgesOnly;
    cage.options.creaseMethod = CreaseMethod::Chaikin;
    cage.options.fvarInterpolation = FVarInterpolation::CornersPlus1;
    cage.options.fvarPropagateCorners = true;
    EXPECT_TRUE(validateCage(cage, "tagged"));
    return cage;
}

void expectSameCage(const Cage& a, const Cage& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.faceOffsets, b.faceOffsets);
    EXPECT_EQ(a.faceVertices, b.faceVertices);
    ASSERT_EQ(a.creases.size(), b.creases.size());
    for (size_t i = 0; i < a.creases.size(); ++i)
        EXPECT_TRUE(a.creases[i].v0 == b.creases[i].v0 && a.creases[i].v1 == b.creases[i].v1 &&
                    a.creases[i].sharpness == b.creases[i].sharpness) << "crease " << i;
    ASSERT_EQ(a.corners.size(), b.corners.size());
    for (size_t i = 0; i < a.corners.size(); ++i)
        EXPECT_TRUE(a.corners[i].vertex == b.corners[i].vertex && a.corners[i].sharpness == b.corners[i].sharpness);
    EXPECT_EQ(a.holes, b.holes);
    EXPECT_TRUE(a.options == b.options);
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(a.faceUVIndices, b.faceUVIndices);
}

}  // namespace

TEST_F(MeshImport, OmRoundTripsEveryTagExactly) {
    const Cage tagged = taggedMixedGrid();
    const std::string path = (dir / "tagged.om").string();
    std::vector<std::string> lost;
    ASSERT_TRUE(saveMeshCage(tagged, path, &lost));
    EXPECT_TRUE(lost.empty()) << lost.front();
    Result<Cage> back = loadMeshCage(path);
    ASSERT_TRUE(back) << back.error().message;
    expectSameCage(tagged, *back);
    // Without UVs and with default options too.
    const Cage plain = test::makeSubdividedCube(2);
    ASSERT_TRUE(saveMeshCage(plain, path));
    back = loadMeshCage(path);
    ASSERT_TRUE(back) << back.error().message;
    expectSameCage(plain, *back);
}

TEST_F(MeshImport, OmRefusesNonManifoldCagesNamingTheFaces) {
    Cage fan = test::makeGrid(1);  // one quad, then three more faces on its first edge
    for (int k = 0; k < 3; ++k) {
        const uint32_t v = fan.vertexCount();
        fan.positions.push_back({0.5f, float(k) * 0.1f - 0.5f, 1.0f + float(k)});
        const uint32_t tri[3] = {1, 0, v};
        fan.addFace(tri, 3);
    }
    const std::string path = (dir / "fan.om").string();
    Status saved = saveMeshCage(fan, path);
    ASSERT_FALSE(saved);
    EXPECT_NE(saved.error().message.find("non-manifold faces 2, 3"), std::string::npos) << saved.error().message;
    EXPECT_FALSE(fs::exists(path)) << "a refused save left a file";
}

TEST_F(MeshImport, CorruptOmFilesAreRefusedNeverHalfRead) {
    const std::string path = (dir / "good.om").string();
    ASSERT_TRUE(saveMeshCage(taggedMixedGrid(), path));
    std::ifstream in(path, std::ios::binary);
    const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(good.size(), 200u);
    // Every truncation is refused (or, cut after the last chunk, reads the same cage).
    for (size_t length = 0; length < good.size(); length += 7) {
        Result<Cage> cage = loadMeshCage(write("cut.om", good.substr(0, length)));
        if (cage) EXPECT_EQ(cage->faceVertices, taggedMixedGrid().faceVertices) << "cut at " << length;
        else EXPECT_NE(cage.error().message.find("cut.om"), std::string::npos) << cage.error().message;
    }
    // Flipped bytes anywhere: an error naming the file, or a valid cage.
    for (size_t at = 0; at < good.size(); at += 3) {
        std::string bad = good;
        bad[at] = char(bad[at] ^ 0x5a);
        Result<Cage> cage = loadMeshCage(write("flipped.om", bad));
        if (cage) EXPECT_TRUE(validateCage(*cage, "flipped"));
        else EXPECT_NE(cage.error().message.find("flipped.om"), std::string::npos) << cage.error().message;
    }
    // Counts larger than the file, a newer version, another magic.
    std::string huge = good;
    huge[7] = char(0x7f);  // vertices ~ 2^31
    Result<Cage> refused = loadMeshCage(write("huge.om", huge));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("more vertices, faces or edges than the file has bytes"), std::string::npos);
    std::string newer = good;
    newer[3] = char((3 << 5) | 0);
    refused = loadMeshCage(write("newer.om", newer));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("newer OpenMesh"), std::string::npos) << refused.error().message;
    refused = loadMeshCage(write("other.om", "PLY not an OM file at all, just text"));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("not an OpenMesh .om file"), std::string::npos);
}

// A custom edge property of a variable-sized type (what the fuzzer found): OpenMesh sizes each
// element from a count inside the data, unchecked, and allocated 4 GB for a 4-byte block. The
// chunk is left out (no cage needs it) and the rest of the file reads as before.
TEST_F(MeshImport, OmVariableSizedCustomPropertiesAreLeftOut) {
    const std::string path = (dir / "good.om").string();
    ASSERT_TRUE(saveMeshCage(taggedMixedGrid(), path));
    std::ifstream in(path, std::ios::binary);
    const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(good[3], char((2 << 5) | 2)) << "the writer's .om 2.2 names property types";
    std::string chunk;
    chunk += char(0xd2), chunk += char(0x00);  // named custom chunk of the edges
    chunk += char(4), chunk += "evil";
    const std::string type = "std::vector<char>";
    chunk += char(type.size()), chunk += type;
    const uint32_t block = 4, count = 0xfdffffffu;  // the first edge's vector: 4 GB
    chunk.append(reinterpret_cast<const char*>(&block), 4);
    chunk.append(reinterpret_cast<const char*>(&count), 4);
    const std::string evil = good.substr(0, 16) + chunk + good.substr(16);
    Result<OmCounts> counts = checkOmFile(evil, "evil.om");
    ASSERT_TRUE(counts) << counts.error().message;
    ASSERT_EQ(counts->skippedChunks.size(), 1u);
    EXPECT_EQ(counts->skippedChunks[0], std::make_pair(size_t(16), size_t(16) + chunk.size()));
    Result<Cage> cage = loadMeshCage(write("evil.om", evil));
    ASSERT_TRUE(cage) << cage.error().message;
    expectSameCage(taggedMixedGrid(), *cage);
}

TEST_F(MeshImport, ScenesReferenceCagesInEveryFormatAndSaveWhatTheyCannotHoldAsObj) {
    const Cage grid = test::makeMixedGrid();
    ASSERT_TRUE(saveMeshCage(grid, (dir / "grid.ply").string()));
    ASSERT_TRUE(saveMeshCage(taggedMixedGrid(), (dir / "tagged.om").string()));
    const std::string scenePath = write("scene.json", R"({"format": "quadplan-scene", "version": 2, "objects": [
        {"name": "plain", "cage": {"path": "grid.ply"}},
        {"name": "tagged", "cage": {"path": "tagged.om"}}]})");
    Result<Scene> scene = loadScene(scenePath);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_EQ(scene->objects[0].cage.faceVertices, grid.faceVertices);
    expectSameCage(scene->objects[1].cage, taggedMixedGrid());
    // The PLY cage gains a crease: saving keeps grid.ply as it was and writes grid.obj beside it.
    std::ifstream before(dir / "grid.ply", std::ios::binary);
    const std::string plyBefore((std::istreambuf_iterator<char>(before)), std::istreambuf_iterator<char>());
    scene->objects[0].cage.setEdgeSharpness(0, 1, 3.0f);
    ASSERT_TRUE(saveScene(*scene, scenePath, CageStorage::AsLoaded));
    std::ifstream after(dir / "grid.ply", std::ios::binary);
    EXPECT_EQ(std::string((std::istreambuf_iterator<char>(after)), std::istreambuf_iterator<char>()), plyBefore);
    Result<Scene> again = loadScene(scenePath);
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ(again->objects[0].cagePath, "grid.obj");
    EXPECT_EQ(again->objects[0].cage.edgeSharpness(0, 1), 3.0f);
    EXPECT_EQ(again->objects[1].cagePath, "tagged.om") << "an .om cage keeps its tags in place";
    expectSameCage(again->objects[1].cage, taggedMixedGrid());
}
