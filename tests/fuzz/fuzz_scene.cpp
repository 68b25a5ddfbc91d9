// libFuzzer target: the scene reader (parseScene) on arbitrary text, then a format/parse round
// trip of whatever it accepted. Referenced cage paths resolve against an empty directory, so
// only inline cages load.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    qp::Result<qp::Scene> scene = qp::parseScene(text, "fuzz.json", "/nonexistent-quadplan-fuzz-dir");
    if (!scene) return 0;
    qp::Result<qp::Scene> again = qp::parseScene(qp::formatScene(*scene, qp::CageStorage::Inline), "again.json", "/");
    if (!again || !qp::sameTopologyAndTags(scene->cage, again->cage)) std::abort();
    return 0;
}
