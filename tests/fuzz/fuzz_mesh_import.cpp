// libFuzzer target: the PLY, OFF, STL and OM cage readers (core/mesh/mesh_import.h, OpenMesh's parsers
// into Quadplan's importers) on arbitrary bytes. The input is written to a scratch file whose
// extension follows its first bytes ("ply" -> .ply, "OFF" -> .off, "OM" -> .om, anything else ->
// .stl, where binary STL takes any bytes). Whatever loads must be a valid cage the product can build topology for.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

#include "mesh/mesh_import.h"
#include "mesh/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const char* ext = bytes.rfind("ply", 0) == 0 ? ".ply"
                      : bytes.rfind("OFF", 0) == 0 ? ".off"
                      : bytes.rfind("OM", 0) == 0  ? ".om"
                                                   : ".stl";
    static const std::string base = "/tmp/quadplan_fuzz_mesh_" + std::to_string(getpid());
    const std::string path = base + ext;
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    qp::Result<qp::Cage> cage = qp::loadMeshCage(path);
    if (cage) {
        if (!qp::validateCage(*cage, "fuzz")) std::abort();  // the reader let an invalid cage through
        const qp::Topology topology = qp::buildTopology(*cage);
        (void)qp::computeStats(*cage, topology);
    }
    std::remove(path.c_str());
    return 0;
}
