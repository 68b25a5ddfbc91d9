#include "plans/osd_refiner.h"

#include <mutex>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>

namespace qp {

using namespace OpenSubdiv;

namespace {

// Far reports topology problems through a global callback; collect them per call.
std::mutex farErrorMutex;
std::string* farErrors = nullptr;

void collectFarError(Far::ErrorType, const char* message) {
    if (farErrors) {
        if (!farErrors->empty()) *farErrors += "; ";
        *farErrors += message;
    }
}

}  // namespace

OpenSubdiv::Far::PatchTableFactory::Options planPatchOptions(uint32_t depth, bool useCreaseNodes) {
    OpenSubdiv::Far::PatchTableFactory::Options options(depth);
    options.useInfSharpPatch = true;
    options.useSingleCreasePatch = useCreaseNodes;
    options.generateLegacySharpCornerPatches = false;
    options.generateVaryingTables = false;
    options.SetEndCapType(OpenSubdiv::Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    return options;
}

Sdc::Options toSdcOptions(const SubdivisionOptions& options) {
    Sdc::Options sdc;
    switch (options.boundary) {
    case BoundaryInterpolation::None: sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_NONE); break;
    case BoundaryInterpolation::EdgesOnly: sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY); break;
    case BoundaryInterpolation::EdgesAndCorners: sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER); break;
    }
    sdc.SetCreasingMethod(options.creaseMethod == CreaseMethod::Chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                        : Sdc::Options::CREASE_UNIFORM);
    sdc.SetTriangleSubdivision(options.triangleSubdivision == TriangleSubdivision::Smooth
                                   ? Sdc::Options::TRI_SUB_SMOOTH
                                   : Sdc::Options::TRI_SUB_CATMARK);
    sdc.SetFVarLinearInterpolation(Sdc::Options::FVarLinearInterpolation(int(options.fvarInterpolation)));
    return sdc;
}

Result<std::unique_ptr<Far::TopologyRefiner>> createRefiner(const Cage& cage, const std::string& source) {
    std::vector<int> vertsPerFace(cage.faceCount());
    for (uint32_t f = 0; f < cage.faceCount(); ++f) vertsPerFace[f] = int(cage.faceSize(f));

    std::vector<int> creaseVertices, cornerVertices, holeFaces(cage.holes.begin(), cage.holes.end());
    std::vector<float> creaseWeights, cornerWeights;
    for (const EdgeCrease& c : cage.creases) {
        creaseVertices.push_back(int(c.v0));
        creaseVertices.push_back(int(c.v1));
        creaseWeights.push_back(c.sharpness);
    }
    for (const VertexCorner& c : cage.corners) {
        cornerVertices.push_back(int(c.vertex));
        cornerWeights.push_back(c.sharpness);
    }

    Far::TopologyDescriptor desc;
    desc.numVertices = int(cage.vertexCount());
    desc.numFaces = int(cage.faceCount());
    desc.numVertsPerFace = vertsPerFace.data();
    desc.vertIndicesPerFace = reinterpret_cast<const Far::Index*>(cage.faceVertices.data());
    desc.numCreases = int(cage.creases.size());
    desc.creaseVertexIndexPairs = creaseVertices.data();
    desc.creaseWeights = creaseWeights.data();
    desc.numCorners = int(cage.corners.size());
    desc.cornerVertexIndices = cornerVertices.data();
    desc.cornerWeights = cornerWeights.data();
    desc.numHoles = int(holeFaces.size());
    desc.holeIndices = holeFaces.data();

    Far::TopologyDescriptor::FVarChannel uvChannel;
    if (!cage.faceUVIndices.empty()) {
        uvChannel.numValues = int(cage.uvs.size());
        uvChannel.valueIndices = reinterpret_cast<const Far::Index*>(cage.faceUVIndices.data());
        desc.numFVarChannels = 1;
        desc.fvarChannels = &uvChannel;
    }

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Factory::Options options(Sdc::SCHEME_CATMARK, toSdcOptions(cage.options));

    std::string errors;
    Far::TopologyRefiner* refiner = nullptr;
    {
        std::lock_guard<std::mutex> lock(farErrorMutex);
        farErrors = &errors;
        Far::SetErrorCallback(collectFarError);
        refiner = Factory::Create(desc, options);
        Far::SetErrorCallback(nullptr);
        farErrors = nullptr;
    }
    if (!refiner)
        return Error{source + ": OpenSubdiv rejected the topology" + (errors.empty() ? "" : ": " + errors)};
    return std::unique_ptr<Far::TopologyRefiner>(refiner);
}

}  // namespace qp
