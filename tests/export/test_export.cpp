// Exporting the limit surface (export/, `quadplan export`): the welded mesh's counts and
// closure, its points on the exact limit surface, holes and n-gons, the optimised order, and
// every file format read back by a second reader (tinygltf for glTF, OpenMesh for OBJ, PLY,
// OFF and STL).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "camera.h"
#include "cli_run.h"
#include "limit_mesh.h"
#include "mesh/mesh_cage_write.h"
#include "mesh_files.h"
#include "mesh_order.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"
#include "scene_export.h"
#include "test_cages.h"

using namespace qp;
namespace fs = std::filesystem;

namespace {

using OpenTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

fs::path scratch() {
    const fs::path dir = fs::temp_directory_path() / ("quadplan_export_" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir;
}

PlannedCage planned(const Cage& cage, PlanDatabase& database) {
    Result<PlannedCage> p = PlannedCage::create(cage, database, PlanOptions{}, "test cage");
    EXPECT_TRUE(p) << p.error().message;
    return std::move(p).value();
}

ExportScene sceneOf(LimitMesh mesh) {
    ExportScene scene;
    scene.meshes.push_back(std::move(mesh));
    scene.meshNames.push_back("cage");
    scene.objects.push_back({"cage", ObjectTransform{}, 0});
    return scene;
}

}  // namespace

TEST(LimitMeshExport, AClosedQuadCageGivesTheWeldedCountAndIsWatertight) {
    PlanDatabase database;
    const PlannedCage cube = planned(test::makeSubdividedCube(2), database);  // V 26, E 48, N 24
    const uint32_t V = cube.cage().vertexCount(), E = cube.topology().edgeCount(), N = cube.cage().faceCount();
    for (uint32_t f : {1u, 2u, 5u, 8u}) {
        Result<LimitMesh> mesh = exactLimitMesh(cube, f);
        ASSERT_TRUE(mesh) << mesh.error().message;
        EXPECT_EQ(mesh->vertexCount(), V + (f - 1) * E + (f - 1) * (f - 1) * N) << "factor " << f;
        EXPECT_EQ(mesh->triangleCount(), 2 * f * f * N);
        EXPECT_TRUE(meshClosure(mesh->indices).watertight()) << "factor " << f;
        // Euler characteristic of a sphere: V - E + F = 2 for the triangle mesh.
        const int64_t edges = 3 * int64_t(mesh->triangleCount()) / 2;
        EXPECT_EQ(int64_t(mesh->vertexCount()) - edges + int64_t(mesh->triangleCount()), 2);
    }
}

TEST(LimitMeshExport, VerticesLieOnTheExactLimitSurfaceWithItsNormals) {
    PlanDatabase database;
    Cage cage = test::makeSubdividedCube(2);
    cage.setEdgeSharpness(cage.faceBegin(0)[0], cage.faceBegin(0)[1], 2.5f);
    const PlannedCage cube = planned(cage, database);
    Result<LimitMesh> mesh = exactLimitMesh(cube, 6);
    ASSERT_TRUE(mesh);
    const float diagonal = computeBounds(cube.cage()).diagonal();
    for (uint32_t v = 0; v < mesh->vertexCount(); ++v) {
        const LimitSample exact = cube.evaluate(mesh->subfaces[v], mesh->parameters[v].x, mesh->parameters[v].y);
        EXPECT_LT(glm::length(exact.position - mesh->positions[v]), 1e-5f * diagonal) << "vertex " << v;
        EXPECT_NEAR(glm::length(mesh->normals[v]), 1.0f, 1e-4f) << "vertex " << v;
    }
}

TEST(LimitMeshExport, HolesAndNgonsStayManifold) {
    PlanDatabase database;
    Cage cage = test::makeSubdividedCube(2);
    cage.setHole(3, true);
    const PlannedCage holed = planned(cage, database);
    Result<LimitMesh> mesh = exactLimitMesh(holed, 4);
    ASSERT_TRUE(mesh);
    const MeshClosure closure = meshClosure(mesh->indices);
    EXPECT_EQ(closure.borderEdges, 4u * 4u) << "the hole's rim: its four cage edges, four segments each";
    EXPECT_EQ(closure.nonManifoldEdges, 0u);
    for (uint32_t v = 0; v < mesh->vertexCount(); ++v) {
        const glm::vec2 uv = mesh->parameters[v];
        const bool inside = uv.x > 0.0f && uv.x < 1.0f && uv.y > 0.0f && uv.y < 1.0f;
        EXPECT_FALSE(mesh->subfaces[v] == holed.firstSubface(3) && inside) << "the hole's inside was exported";
    }

    const PlannedCage mixed = planned(test::makeMixedGrid(), database);  // quads, a triangle and a pentagon
    for (uint32_t f : {2u, 3u, 8u}) {
        Result<LimitMesh> m = exactLimitMesh(mixed, f);
        ASSERT_TRUE(m) << m.error().message;
        EXPECT_EQ(meshClosure(m->indices).nonManifoldEdges, 0u) << "factor " << f;
        for (size_t i = 0; i < m->indices.size(); i += 3)
            EXPECT_TRUE(m->indices[i] != m->indices[i + 1] && m->indices[i + 1] != m->indices[i + 2] &&
                        m->indices[i] != m->indices[i + 2]);
    }
    EXPECT_FALSE(exactLimitMesh(mixed, 0)) << "factor 0 was accepted";
    EXPECT_FALSE(exactLimitMesh(mixed, 65)) << "factor 65 was accepted";
}

TEST(LimitMeshExport, OptimisedOrderKeepsTheSurfaceAndLowersTheMissRatio) {
    PlanDatabase database;
    const PlannedCage cube = planned(test::makeSubdividedCube(3), database);
    Result<LimitMesh> mesh = exactLimitMesh(cube, 16);
    ASSERT_TRUE(mesh);
    auto triangles = [](const LimitMesh& m) {
        std::vector<std::array<float, 9>> out;
        for (size_t i = 0; i < m.indices.size(); i += 3) {
            std::array<glm::vec3, 3> t{m.positions[m.indices[i]], m.positions[m.indices[i + 1]], m.positions[m.indices[i + 2]]};
            std::rotate(t.begin(), std::min_element(t.begin(), t.end(), [](auto& a, auto& b) {
                            return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
                        }), t.end());  // the same triangle in either order starts at its least corner
            out.push_back({t[0].x, t[0].y, t[0].z, t[1].x, t[1].y, t[1].z, t[2].x, t[2].y, t[2].z});
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    const auto before = triangles(*mesh);
    LimitMesh ordered = *mesh;
    const OrderReport report = optimizeMeshOrder(ordered);
    EXPECT_EQ(triangles(ordered), before) << "the surface changed";
    EXPECT_EQ(ordered.vertexCount(), mesh->vertexCount());
    EXPECT_GT(report.acmrBefore, 0.9f);  // sub-face rows: about the course's scanline 1.06
    EXPECT_LT(report.acmrAfter, 0.75f);  // Forsyth-like: the course's 0.67
    EXPECT_LT(report.acmrAfter, report.acmrBefore);
}

TEST(LimitMeshExport, EveryFormatReadsBackThroughASecondReader) {
    const fs::path dir = scratch();
    PlanDatabase database;
    const PlannedCage cube = planned(test::makeSubdividedCube(2), database);
    Result<LimitMesh> mesh = exactLimitMesh(cube, 4);
    ASSERT_TRUE(mesh);
    const ExportScene scene = sceneOf(*mesh);
    for (const char* ext : {".obj", ".ply", ".off", ".stl"}) {
        const std::string path = (dir / (std::string("cube") + ext)).string();
        Result<MeshFormat> format = meshFormatOf(path);
        ASSERT_TRUE(format);
        ASSERT_TRUE(writeMeshFile(scene, path, *format)) << ext;
        OpenTriMesh read;
        OpenMesh::IO::Options options;
        ASSERT_TRUE(OpenMesh::IO::read_mesh(read, path, options)) << "OpenMesh could not read " << ext;
        EXPECT_EQ(read.n_faces(), mesh->triangleCount()) << ext;
        EXPECT_EQ(read.n_vertices(), mesh->vertexCount()) << ext << " (STL: OpenMesh welds equal positions)";
    }
    // PLY's per-vertex sub-face and (u, v), which OpenMesh skipped above: the last vertex's, read by hand.
    std::ifstream ply(dir / "cube.ply", std::ios::binary);
    const std::string plyBytes((std::istreambuf_iterator<char>(ply)), std::istreambuf_iterator<char>());
    EXPECT_NE(plyBytes.find("property uint subface\nproperty float subface_u\nproperty float subface_v\n"), std::string::npos);
    const size_t vertexEnd = plyBytes.find("end_header\n") + 11 + size_t(mesh->vertexCount()) * 36;
    uint32_t subface = 0;
    glm::vec2 uv(0.0f);
    std::memcpy(&subface, plyBytes.data() + vertexEnd - 12, 4);
    std::memcpy(&uv, plyBytes.data() + vertexEnd - 8, 8);
    EXPECT_EQ(subface, mesh->subfaces.back());
    EXPECT_EQ(uv, mesh->parameters.back());
    // glTF, binary and text: the counts, the node, the attributes.
    for (const char* ext : {".glb", ".gltf"}) {
        const std::string path = (dir / (std::string("cube") + ext)).string();
        ASSERT_TRUE(writeMeshFile(scene, path, *meshFormatOf(path)));
        tinygltf::Model model;
        tinygltf::TinyGLTF reader;
        std::string error, warning;
        const bool loaded = std::string(ext) == ".glb" ? reader.LoadBinaryFromFile(&model, &error, &warning, path)
                                                       : reader.LoadASCIIFromFile(&model, &error, &warning, path);
        ASSERT_TRUE(loaded) << error;
        ASSERT_EQ(model.meshes.size(), 1u);
        const tinygltf::Primitive& p = model.meshes[0].primitives.at(0);
        EXPECT_EQ(model.accessors[p.attributes.at("POSITION")].count, mesh->vertexCount());
        EXPECT_EQ(model.accessors[p.attributes.at("NORMAL")].count, mesh->vertexCount());
        EXPECT_EQ(model.accessors[p.indices].count, mesh->indices.size());
        EXPECT_TRUE(p.attributes.count("_SUBFACE") && p.attributes.count("_SUBFACE_UV"));
    }
    // Unknown names and unwritable places: an error, no file.
    EXPECT_FALSE(meshFormatOf((dir / "cube.fbx").string()));
    EXPECT_FALSE(writeMeshFile(scene, (dir / "missing" / "cube.ply").string(), MeshFormat::Ply));
    EXPECT_FALSE(fs::exists(dir / "missing"));
    fs::remove_all(dir);
}

TEST(LimitMeshExport, ScenesKeepObjectsAsNodesOrMergeThemInTheWorld) {
    PlanDatabase database;
    const PlannedCage cube = planned(test::makeCube(), database);
    Result<LimitMesh> mesh = exactLimitMesh(cube, 2);
    ASSERT_TRUE(mesh);
    ExportScene scene = sceneOf(*mesh);
    ObjectTransform moved;
    moved.translation = {5, 0, 0};
    moved.rotationDegrees = {0, 0, 90};
    moved.scale = {-1, 1, 1};  // a mirror: the merged copy must stay outward-facing
    scene.objects.push_back({"cage.001", moved, 0});  // an instance of the same mesh
    const LimitMesh merged = mergedInWorld(scene);
    EXPECT_EQ(merged.vertexCount(), 2 * mesh->vertexCount());
    EXPECT_TRUE(meshClosure(merged.indices).watertight());
    // Outward: each copy's normals point away from its centre.
    const glm::vec3 centres[2] = {glm::vec3(0.0f), moved.translation};
    for (uint32_t v = 0; v < merged.vertexCount(); ++v)
        EXPECT_GT(glm::dot(merged.normals[v], merged.positions[v] - centres[v / mesh->vertexCount()]), 0.0f) << v;
    // The triangles' winding agrees with the normals in the mirrored copy too.
    for (size_t i = 0; i < merged.indices.size(); i += 3) {
        const glm::vec3 &a = merged.positions[merged.indices[i]], &b = merged.positions[merged.indices[i + 1]],
                        &c = merged.positions[merged.indices[i + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), merged.normals[merged.indices[i]]), 0.0f) << "triangle " << i / 3;
    }

    const fs::path dir = scratch();
    const std::string path = (dir / "two.glb").string();
    ASSERT_TRUE(writeMeshFile(scene, path, MeshFormat::Glb));
    tinygltf::Model model;
    tinygltf::TinyGLTF reader;
    std::string error, warning;
    ASSERT_TRUE(reader.LoadBinaryFromFile(&model, &error, &warning, path)) << error;
    ASSERT_EQ(model.nodes.size(), 2u);
    EXPECT_EQ(model.meshes.size(), 1u) << "the instance did not share the mesh";
    EXPECT_EQ(model.nodes[0].mesh, model.nodes[1].mesh);
    ASSERT_EQ(model.nodes[1].translation.size(), 3u);
    EXPECT_DOUBLE_EQ(model.nodes[1].translation[0], 5.0);
    ASSERT_EQ(model.nodes[1].rotation.size(), 4u);
    EXPECT_NEAR(model.nodes[1].rotation[2], std::sqrt(0.5), 1e-6);  // 90 degrees about z
    EXPECT_EQ(model.nodes[1].scale, (std::vector<double>{-1, 1, 1}));
    fs::remove_all(dir);
}

TEST(ExportCommand, WritesAndReportsAsJson) {
    const fs::path dir = scratch();
    const std::string out = (dir / "objects.glb").string();
    test::CommandRun run = test::runQuadplan("export " + std::string(QUADPLAN_SCENES_DIR) + "/objects.json --out " + out +
                                             " --tess 4 --json");
    ASSERT_EQ(run.status, 0) << run.out;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["file"], out);
    EXPECT_EQ(report["objects"], 3);
    EXPECT_EQ(report["meshes"], 2) << "the instance exported its own mesh";
    EXPECT_GT(report["vertices"].get<int>(), 0);
    EXPECT_LT(report["acmr_after"].get<double>(), report["acmr_before"].get<double>());
    EXPECT_TRUE(fs::exists(out));
    // --split: one file per object, merged formats.
    run = test::runQuadplan("export " + std::string(QUADPLAN_SCENES_DIR) + "/objects.json --out " + (dir / "part.ply").string() +
                            " --split --tess 2");
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_TRUE(fs::exists(dir / "part_default.ply") && fs::exists(dir / "part_default.001.ply") &&
                fs::exists(dir / "part_creased_box.ply"));
    // --cage: the cages' polygons, merged in the world; the lost creases named.
    run = test::runQuadplan("export " + std::string(QUADPLAN_SCENES_DIR) + "/objects.json --cage --out " + (dir / "cages.off").string(),
                            true);
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_NE(run.out.find("off cannot hold the cage's"), std::string::npos) << run.out;
    Result<Scene> cages = loadSceneOrCage((dir / "cages.off").string());
    ASSERT_TRUE(cages) << cages.error().message;
    EXPECT_GT(cages->objects[0].cage.faceCount(), 300u) << "not every object's cage was written";
    // Bad requests: a clear error, nothing written.
    run = test::runQuadplan("export " + std::string(QUADPLAN_SCENES_DIR) + "/objects.json --out " + (dir / "x.fbx").string(), true);
    EXPECT_EQ(run.status, 1);
    EXPECT_NE(run.out.find(".glb, .gltf, .obj, .ply, .off or .stl"), std::string::npos) << run.out;
    run = test::runQuadplan("export " + (dir / "nowhere.obj").string() + " --out " + (dir / "y.obj").string(), true);
    EXPECT_EQ(run.status, 1);
    EXPECT_FALSE(fs::exists(dir / "y.obj"));
    fs::remove_all(dir);
}

TEST(LimitMeshExport, LinearUvsFollowTheCageAndSplitOnlyAtSeams) {
    PlanDatabase database;
    // Continuous UVs (one per vertex: its x, y): no seam, so no vertex is split.
    Cage grid = test::makeGrid(3);
    for (const glm::vec3& p : grid.positions) grid.uvs.push_back({p.x, p.y});
    grid.faceUVIndices = grid.faceVertices;
    const PlannedCage smooth = planned(grid, database);
    Result<LimitMesh> plain = exactLimitMesh(smooth, 4);
    Result<LimitMesh> mapped = exactLimitMesh(smooth, 4, nullptr, UvMode::Linear);
    ASSERT_TRUE(plain && mapped);
    EXPECT_EQ(mapped->vertexCount(), plain->vertexCount());
    ASSERT_EQ(mapped->uvs.size(), mapped->vertexCount());
    for (uint32_t v = 0; v < mapped->vertexCount(); ++v) {  // bilinear over each quad's corner UVs
        const uint32_t f = mapped->subfaces[v];  // quads: sub-face = face
        const glm::vec2 uv = mapped->parameters[v];
        auto corner = [&](uint32_t k) { return grid.uvs[grid.faceUVIndices[grid.faceOffsets[f] + k]]; };
        const glm::vec2 expected = (1 - uv.x) * (1 - uv.y) * corner(0) + uv.x * (1 - uv.y) * corner(1) +
                                   uv.x * uv.y * corner(2) + (1 - uv.x) * uv.y * corner(3);
        EXPECT_LT(glm::length(mapped->uvs[v] - expected), 1e-5f) << "vertex " << v;
    }
    // Each face its own UV island: every face border is a seam, the surface stays closed.
    Cage cube = test::makeSubdividedCube(2);
    const glm::vec2 square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t f = 0; f < cube.faceCount(); ++f)  // islands side by side, so no two faces share a UV
        for (uint32_t k = 0; k < cube.faceSize(f); ++k) {
            cube.faceUVIndices.push_back(uint32_t(cube.uvs.size()));
            cube.uvs.push_back(square[k] + glm::vec2(2.0f * float(f), 0.0f));
        }
    const PlannedCage islands = planned(cube, database);
    const uint32_t f = 3;
    Result<LimitMesh> split = exactLimitMesh(islands, f, nullptr, UvMode::Linear);
    ASSERT_TRUE(split);
    EXPECT_EQ(split->vertexCount(), cube.faceCount() * (f + 1) * (f + 1)) << "every face border is a seam";
    EXPECT_TRUE(split->closure.watertight()) << "the seams opened the surface's closure";
    EXPECT_FALSE(meshClosure(split->indices).watertight()) << "the index buffer should open at the seams";
    // Formats: glTF's TEXCOORD_0, OBJ's vt; a cage without UVs is refused.
    const fs::path dir = scratch();
    ExportScene scene = sceneOf(*split);
    ASSERT_TRUE(writeMeshFile(scene, (dir / "uv.glb").string(), MeshFormat::Glb));
    tinygltf::Model model;
    tinygltf::TinyGLTF reader;
    std::string error, warning;
    ASSERT_TRUE(reader.LoadBinaryFromFile(&model, &error, &warning, (dir / "uv.glb").string())) << error;
    ASSERT_TRUE(model.meshes[0].primitives[0].attributes.count("TEXCOORD_0"));
    const tinygltf::Accessor& texcoords = model.accessors[model.meshes[0].primitives[0].attributes.at("TEXCOORD_0")];
    ASSERT_EQ(texcoords.count, split->vertexCount());
    const tinygltf::BufferView& texcoordView = model.bufferViews[texcoords.bufferView];
    const auto* written = reinterpret_cast<const glm::vec2*>(model.buffers[texcoordView.buffer].data.data() +
                                                             texcoordView.byteOffset + texcoords.byteOffset);
    for (uint32_t v = 0; v < split->vertexCount(); ++v)  // glTF's v runs down the image, OBJ's up
        ASSERT_EQ(written[v], glm::vec2(split->uvs[v].x, 1.0f - split->uvs[v].y)) << "vertex " << v;
    ASSERT_TRUE(writeMeshFile(scene, (dir / "uv.obj").string(), MeshFormat::Obj));
    std::ifstream obj(dir / "uv.obj");
    std::stringstream text;
    text << obj.rdbuf();
    EXPECT_NE(text.str().find("\nvt "), std::string::npos);
    EXPECT_NE(text.str().find("1/1/1"), std::string::npos);
    Result<LimitMesh> none = exactLimitMesh(planned(test::makeCube(), database), 2, nullptr, UvMode::Linear);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("no texture coordinates"), std::string::npos);
    fs::remove_all(dir);
}

TEST(LimitMeshExport, AdaptiveDensityFollowsTheViewAndStaysWatertight) {
    PlanDatabase database;
    const PlannedCage mixed = planned(test::makeMixedGrid(), database);
    const PlannedCage cube = planned(test::makeSubdividedCube(2), database);
    auto viewFrom = [](float distance) {
        RenderCamera camera;
        camera.eye = {0.3f * distance, 0.4f * distance, distance};
        camera.target = glm::vec3(0.0f);
        camera.aspect = 4.0f / 3.0f;
        camera.farZ = 100.0f + distance;
        return AdaptiveView{viewProjection(camera), pixelsPerUnit(projectionMatrix(camera), 600), 6.0f};
    };
    Result<LimitMesh> nearCube = exactLimitMesh(cube, MeshDensity(viewFrom(4.0f)));
    Result<LimitMesh> farCube = exactLimitMesh(cube, MeshDensity(viewFrom(40.0f)));
    ASSERT_TRUE(nearCube && farCube);
    EXPECT_TRUE(nearCube->closure.watertight()) << nearCube->closure.borderEdges << " border, "
                                                << nearCube->closure.nonManifoldEdges << " non-manifold edges";
    EXPECT_TRUE(farCube->closure.watertight());
    EXPECT_GT(nearCube->triangleCount(), 4 * farCube->triangleCount()) << "a closer view should cut the surface finer";
    // N-gons and a boundary: no edge used more than twice, the border only along the cage's.
    Result<LimitMesh> nearMixed = exactLimitMesh(mixed, MeshDensity(viewFrom(5.0f)));
    ASSERT_TRUE(nearMixed);
    EXPECT_EQ(nearMixed->closure.nonManifoldEdges, 0u);
    Result<LimitMesh> uniform = exactLimitMesh(mixed, 2);
    ASSERT_TRUE(uniform);
    EXPECT_GT(nearMixed->closure.borderEdges, uniform->closure.borderEdges) << "the boundary was not cut finer";
    AdaptiveView nothing = viewFrom(4.0f);
    nothing.pixelsPerSegment = 0.0f;
    EXPECT_FALSE(exactLimitMesh(cube, MeshDensity(nothing)));
}

TEST(LimitMeshExport, OpenMeshReadsTheTagsOfAnOmCage) {
    // The second reader: OpenMesh's own .om reader into its own mesh, tags as named properties.
    Cage cage = test::makeSubdividedCube(2);
    cage.setEdgeSharpness(cage.faceBegin(0)[0], cage.faceBegin(0)[1], 4.0f);
    cage.setVertexSharpness(5, 2.0f);
    cage.setHole(3, true);
    const fs::path dir = scratch();
    const std::string path = (dir / "tags.om").string();
    ASSERT_TRUE(saveMeshCage(cage, path));
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    OpenMesh::EPropHandleT<float> crease;
    OpenMesh::VPropHandleT<float> corner;
    OpenMesh::FPropHandleT<int> hole;
    mesh.add_property(crease, "quadplan:crease");
    mesh.add_property(corner, "quadplan:corner");
    mesh.add_property(hole, "quadplan:hole");
    ASSERT_TRUE(OpenMesh::IO::read_mesh(mesh, path));
    ASSERT_EQ(mesh.n_vertices(), cage.vertexCount());
    ASSERT_EQ(mesh.n_faces(), cage.faceCount());
    uint32_t creased = 0;
    for (auto e : mesh.edges())
        if (const float s = mesh.property(crease, e); s != 0.0f) {
            ++creased;
            EXPECT_EQ(s, 4.0f);
            const int a = mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx(), b = mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx();
            EXPECT_EQ(cage.edgeSharpness(uint32_t(a), uint32_t(b)), 4.0f);
        }
    EXPECT_EQ(creased, 1u);
    EXPECT_EQ(mesh.property(corner, OpenMesh::VertexHandle(5)), 2.0f);
    for (auto f : mesh.faces()) EXPECT_EQ(mesh.property(hole, f), f.idx() == 3 ? 1 : 0);
    fs::remove_all(dir);
}

TEST(LimitMeshExport, ACancelledExportWritesNothing) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(std::string(QUADPLAN_SCENES_DIR) + "/objects.json", &warnings);
    ASSERT_TRUE(scene) << scene.error().message;
    PlanDatabase database;
    Result<PlannedScene> planned = PlannedScene::create(*scene, database, PlanOptions{}, "objects.json");
    ASSERT_TRUE(planned);
    const fs::path dir = scratch();
    const std::string path = (dir / "cancelled.glb").string();
    // Stopped at its first, second and third report (evaluating, ordering, the next cage).
    for (int stopAt = 0; stopAt < 3; ++stopAt) {
        int calls = 0;
        std::vector<std::string> stages;
        Result<ExportReport> report =
            exportScene(*scene, sceneCages(*planned), path, ExportOptions{}, "objects.json", nullptr,
                        [&](const std::string& stage, float fraction) {
                            stages.push_back(stage);
                            EXPECT_GE(fraction, 0.0f);
                            EXPECT_LE(fraction, 1.0f);
                            return calls++ < stopAt;
                        });
        ASSERT_FALSE(report) << "stage " << stopAt;
        EXPECT_NE(report.error().message.find("cancelled"), std::string::npos) << report.error().message;
        EXPECT_FALSE(fs::exists(path)) << "cancelled at '" << stages.back() << "' but a file was written";
    }
    // Never cancelled: the stages run to "Done".
    std::string last;
    ASSERT_TRUE(exportScene(*scene, sceneCages(*planned), path, ExportOptions{}, "objects.json", nullptr,
                            [&](const std::string& stage, float) { return last = stage, true; }));
    EXPECT_EQ(last, "Done");
    EXPECT_TRUE(fs::exists(path));
    fs::remove_all(dir);
}
