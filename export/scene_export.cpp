#include "scene_export.h"

#include <chrono>
#include <filesystem>

#include "plan_pass.h"

namespace qp {

std::string splitExportPath(const std::string& out, const std::string& object) {
    const std::filesystem::path path(out);
    return (path.parent_path() / (path.stem().string() + "_" + object + path.extension().string())).string();
}

SceneCages sceneCages(const PlannedScene& planned) {
    SceneCages out{{}, planned.cageOfObject, planned.objectOfCage};
    for (const PlannedCage& cage : planned.cages) out.cages.push_back(&cage);
    return out;
}

AdaptiveExport adaptiveExport(const RenderCamera& camera, uint32_t viewportHeight, float pixelsPerSegment) {
    return {viewProjection(camera), pixelsPerUnit(projectionMatrix(camera), viewportHeight), pixelsPerSegment};
}

MeshDensity exportDensity(const Scene& scene, const SceneCages& planned, uint32_t c, const ExportOptions& options) {
    if (!options.adaptive) return MeshDensity(options.factor);
    // The cage is seen through its owner's transform (its instances share the owner's mesh).
    const glm::mat4 model = scene.objects[planned.objectOfCage[c]].transform.matrix();
    return MeshDensity(AdaptiveView{options.adaptive->viewProjection * model, options.adaptive->pixelsPerUnit,
                                    options.adaptive->pixelsPerSegment});
}

Result<ExportReport> exportScene(const Scene& scene, const SceneCages& planned, const std::string& path,
                                 const ExportOptions& options, const std::string& source, const CageMesher& mesher,
                                 const ExportProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    Result<MeshFormat> format = meshFormatOf(path);
    if (!format) return format.error();
    ExportReport report;
    ExportScene exported;
    double weightedBefore = 0.0, weightedAfter = 0.0, weight = 0.0;
    const float cages = float(planned.cages.size());
    auto step = [&](const std::string& stage, float fraction) { return !progress || progress(stage, fraction); };
    const Error cancelled{"cancelled: nothing was written"};
    for (uint32_t c = 0; c < planned.cages.size(); ++c) {
        const SceneObject& owner = scene.objects[planned.objectOfCage[c]];
        const std::string of = cages > 1 ? " (" + owner.name + ", " + std::to_string(c + 1) + " of " + std::to_string(planned.cages.size()) + ")" : "";
        if (!step("Evaluating the surface" + of, 0.9f * float(c) / cages)) return cancelled;
        const std::string where = planned.cages.size() == 1 ? source : source + ": object \"" + owner.name + "\"";
        const bool displace = options.displaced && !owner.displacement.empty();
        if (options.displaced && !displace) report.notes.push_back(where + " has no sculpted displacement: exported without");
        Result<LimitMesh> mesh = mesher ? mesher(*planned.cages[c], c, where)
                                        : exactLimitMesh(*planned.cages[c], exportDensity(scene, planned, c, options), displace ? &owner.displacement : nullptr,
                                                         options.uv);
        if (!mesh) return Error{where + ": " + mesh.error().message};
        const MeshClosure closure = mesh->closure;
        report.closure.borderEdges += closure.borderEdges;
        report.closure.nonManifoldEdges += closure.nonManifoldEdges;
        if (options.optimize) {
            if (!step("Optimising the vertex order" + of, 0.9f * (float(c) + 0.6f) / cages)) return cancelled;
            const OrderReport order = optimizeMeshOrder(*mesh);
            weightedBefore += double(order.acmrBefore) * mesh->triangleCount();
            weightedAfter += double(order.acmrAfter) * mesh->triangleCount();
            weight += mesh->triangleCount();
        }
        exported.meshes.push_back(std::move(mesh).value());
        exported.meshNames.push_back(owner.name);
    }
    if (weight > 0.0) report.order = {float(weightedBefore / weight), float(weightedAfter / weight)};
    for (uint32_t i = 0; i < scene.objects.size(); ++i)
        if (scene.objects[i].visible) exported.objects.push_back({scene.objects[i].name, scene.objects[i].transform, planned.cageOfObject[i]});
    report.objects = uint32_t(exported.objects.size());
    report.meshes = uint32_t(exported.meshes.size());

    if (!step("Writing " + path, 0.9f)) return cancelled;
    auto write = [&](const ExportScene& part, const std::string& file) -> Status {
        if (Status written = writeMeshFile(part, file, *format); !written) return written;
        report.files.push_back(file);
        if (hasNodes(*format)) {
            for (const LimitMesh& m : part.meshes) report.vertices += m.vertexCount(), report.triangles += m.triangleCount();
        } else {
            for (const ExportObject& o : part.objects)
                report.vertices += part.meshes[o.mesh].vertexCount(), report.triangles += part.meshes[o.mesh].triangleCount();
        }
        return success();
    };
    if (options.split && exported.objects.size() > 1) {
        for (const ExportObject& object : exported.objects) {
            ExportScene one{exported.meshes, exported.meshNames, {object}};
            if (Status s = write(one, splitExportPath(path, object.name)); !s) return s.error();
        }
    } else if (Status s = write(exported, path); !s) {
        return s.error();
    }
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    step("Done", 1.0f);
    return report;
}

}  // namespace qp
