// Writing exported limit-surface meshes (limit_mesh.h) in the formats other tools read.
//
//   .glb / .gltf  glTF 2.0 through tinygltf (binary by default): one mesh per cage, a node per
//                 object with its transform (translation, rotation as a quaternion, scale), so
//                 instances share their mesh; POSITION, NORMAL, 32-bit indices, and per vertex
//                 _SUBFACE (the Ptex face) and _SUBFACE_UV ((u, v) in it) for pipelines;
//                 TEXCOORD_0 when the mesh has UVs.
//   .obj          positions, normals and UVs when there are (v, vn, vt, f v/t/n), text
//   .ply          binary little-endian: positions, normals, UVs (s, t) when there are, triangles
//   .off          positions and triangles, text (OFF has no normals)
//   .stl          binary: facets with their flat normals (STL has no shared vertices)
// The formats without nodes get every object merged, each carried into the world by its
// transform (normals by its inverse transpose). Writes are atomic (core/mesh/file_io.h): a failed
// export leaves no file, or the old one. docs/formats.md lists what each format keeps and loses.
#pragma once

#include <string>
#include <vector>

#include "limit_mesh.h"
#include "mesh/result.h"
#include "scene/scene_objects.h"

namespace qp {

enum class MeshFormat { Glb, Gltf, Obj, Ply, Off, Stl };

// The format a path's extension names; an error listing the known ones otherwise.
Result<MeshFormat> meshFormatOf(const std::string& path);
const char* meshFormatName(MeshFormat format);
bool hasNodes(MeshFormat format);  // glTF: objects stay objects

struct ExportObject {
    std::string name;
    ObjectTransform transform;
    uint32_t mesh = 0;  // into ExportScene::meshes
};
struct ExportScene {
    std::vector<LimitMesh> meshes;        // one per cage
    std::vector<std::string> meshNames;   // parallel: the name of the object owning the cage
    std::vector<ExportObject> objects;    // the visible objects, each drawing one mesh
};

// Every object's mesh in world coordinates, concatenated (what formats without nodes hold).
LimitMesh mergedInWorld(const ExportScene& scene);

Status writeMeshFile(const ExportScene& scene, const std::string& path, MeshFormat format);

}  // namespace qp
