// libFuzzer target: the plan-database file reader. The input is the file without its trailing
// checksum, which the target appends, so mutations reach the parser instead of stopping at the
// checksum. A database that loads is then used to plan a small cage with an extraordinary
// vertex, creases and a triangle: a plan that passed the reader's checks must be safe to apply.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "mesh/obj_io.h"
#include "plans/planned_cage.h"

namespace {

const char* const kCage = R"(v 0 0 0
v 1 0 0
v 2 0 0
v 0 1 0
v 1 1 1
v 2 1 0
v 0 2 0
v 1 2 0
f 1 2 5 4
f 2 3 6 5
f 4 5 8 7
f 5 6 8
t crease 2/1/0 2 5 2.5
)";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    const uint64_t sum = qp::planDatabaseChecksum(bytes.data(), bytes.size());
    bytes.append(reinterpret_cast<const char*>(&sum), sizeof(sum));
    qp::PlanDatabase database;
    if (!database.loadFromBytes(bytes, "fuzz.qpdb")) return 0;
    static const qp::Cage cage = qp::parseObj(kCage, "fuzz-cage.obj").value();
    qp::Result<qp::PlannedCage> planned = qp::PlannedCage::create(cage, database, qp::PlanOptions{}, "fuzz-cage");
    if (planned)
        for (uint32_t s = 0; s < planned->subfaceCount(); ++s)
            if (planned->hasSurface(s)) (void)planned->evaluate(s, 0.3f, 0.7f);
    return 0;
}
