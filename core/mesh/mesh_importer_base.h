// What Quadplan's OpenMesh importers (mesh_import.cpp, mesh_om.cpp) share: a BaseImporter that
// drops every attribute OpenMesh's readers hand over besides the mesh itself (normals, colours,
// texture coordinates, status bits), and a guard that silences OpenMesh's own error stream while
// a reader runs (our messages say what matters). Include only from those two files: OpenMesh's
// headers are slow to compile.
#pragma once

#include <string>
#include <vector>

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

namespace qp {

class AttributeFreeImporter : public OpenMesh::IO::BaseImporter {
public:
    using VH = OpenMesh::VertexHandle;
    using HH = OpenMesh::HalfedgeHandle;
    using EH = OpenMesh::EdgeHandle;
    using FH = OpenMesh::FaceHandle;
    using Status = OpenMesh::Attributes::StatusInfo;

    void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f>&) override {}
    void set_face_texindex(FH, int) override {}
    void set_halfedge(VH, HH) override {}
    void set_normal(VH, const OpenMesh::Vec3f&) override {}
    void set_normal(VH, const OpenMesh::Vec3d&) override {}
    void set_color(VH, const OpenMesh::Vec3uc&) override {}
    void set_color(VH, const OpenMesh::Vec4uc&) override {}
    void set_color(VH, const OpenMesh::Vec3f&) override {}
    void set_color(VH, const OpenMesh::Vec4f&) override {}
    void set_texcoord(VH, const OpenMesh::Vec2f&) override {}
    void set_texcoord(VH, const OpenMesh::Vec3f&) override {}
    void set_status(VH, const Status&) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HH, const OpenMesh::Vec2f&) override {}
    void set_texcoord(HH, const OpenMesh::Vec3f&) override {}
    void set_status(HH, const Status&) override {}
    void set_color(EH, const OpenMesh::Vec3uc&) override {}
    void set_color(EH, const OpenMesh::Vec4uc&) override {}
    void set_color(EH, const OpenMesh::Vec3f&) override {}
    void set_color(EH, const OpenMesh::Vec4f&) override {}
    void set_status(EH, const Status&) override {}
    void set_normal(FH, const OpenMesh::Vec3f&) override {}
    void set_normal(FH, const OpenMesh::Vec3d&) override {}
    void set_color(FH, const OpenMesh::Vec3uc&) override {}
    void set_color(FH, const OpenMesh::Vec4uc&) override {}
    void set_color(FH, const OpenMesh::Vec3f&) override {}
    void set_color(FH, const OpenMesh::Vec4f&) override {}
    void set_status(FH, const Status&) override {}
    void add_texture_information(int, std::string) override {}
};

struct QuietOpenMesh {
    QuietOpenMesh() { omerr().disable(), omlog().disable(); }
    ~QuietOpenMesh() { omerr().enable(), omlog().enable(); }
};

}  // namespace qp
