// libFuzzer target: the scene reader (parseScene) on arbitrary text, then a format/parse round
// trip of whatever it accepted. Referenced cage paths resolve against an empty directory, so
// only inline cages load.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    qp::Result<qp::Scene> scene = qp::parseScene(text, "fuzz.json", "/nonexistent-quadplan-fuzz-dir");
    if (!scene) return 0;
    qp::Result<qp::Scene> again = qp::parseScene(qp::formatScene(*scene, qp::CageStorage::Inline), "again.json", "/");
    if (!again || again->objects.size() != scene->objects.size()) std::abort();
    for (size_t i = 0; i < scene->objects.size(); ++i) {
        const qp::SceneObject &a = scene->objects[i], &b = again->objects[i];
        if (a.name != b.name || a.instanceOf != b.instanceOf || !(a.transform == b.transform) || a.visible != b.visible ||
            !qp::sameTopologyAndTags(a.cage, b.cage))
            std::abort();
    }
    return 0;
}
