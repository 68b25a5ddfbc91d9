// libFuzzer target: the OBJ reader (parseObj) on arbitrary text. Whatever parses must also
// survive what the product does next with a cage: validation, topology, and a save/load round
// trip that gives back the same topology and tags.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mesh/obj_io.h"
#include "mesh/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "fuzz.obj", &warnings);
    if (!cage) return 0;
    const qp::Topology topology = qp::buildTopology(*cage);
    (void)qp::computeStats(*cage, topology);
    qp::Result<qp::Cage> again = qp::parseObj(qp::formatObj(*cage), "again.obj");
    if (!again || !qp::sameTopologyAndTags(*cage, *again)) std::abort();  // lossless round trip
    return 0;
}
