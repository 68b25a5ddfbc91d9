// libFuzzer target: the scripted-stroke readers (core/displacement/sculpt_script.h) — the stroke-file JSON
// and the `--path "x,y,z;..."` text — on arbitrary input. Whatever they accept must be usable:
// a stroke has finite points, a positive radius, a finite strength and spacing, and no more
// dabs than kMaxDabsPerStroke (a stroke with billions of dabs ran for hours before that check);
// a whole-mask step has no path.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "displacement/sculpt_script.h"

namespace {

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (auto path = qp::parsePath(text))
        for (const glm::vec3& p : *path)
            if (!finite(p)) std::abort();
    if (auto strokes = qp::parseStrokeFile(text, "fuzz.json")) {
        for (const qp::ScriptedStroke& s : *strokes) {
            if (s.wholeMask != qp::WholeMaskStep::None) {
                if (!s.path.empty()) std::abort();
                continue;
            }
            const qp::Brush& b = s.options.brush;
            if (s.path.empty() || !(b.radius > 0) || !std::isfinite(b.radius) || !std::isfinite(b.strength) ||
                !std::isfinite(s.options.spacing) || s.options.spacing < 0 || !qp::checkStrokeLength(s))
                std::abort();
            for (const glm::vec3& p : s.path)
                if (!finite(p)) std::abort();
        }
    }
    return 0;
}
