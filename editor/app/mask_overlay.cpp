#include "mask_overlay.h"

#include "document.h"

namespace qp::editor {

namespace {

// Below this a sample is drawn as unmasked: brushes change it by 99% or more.
constexpr float kShownMask = 0.01f;

}  // namespace

void updateMaskDots(MaskDots& dots, Document& doc, uint64_t generation) {
    if (dots.generation == generation && dots.displacementRevision == doc.displacementRevision &&
        dots.sampleRevision == doc.sampleRevision && dots.maskRevision == doc.maskRevision &&
        dots.positionRevision == doc.positionRevision)
        return;
    dots = MaskDots{generation, doc.displacementRevision, doc.sampleRevision, doc.maskRevision, doc.positionRevision};
    if (!doc.planned) return;
    const Displacement& d = displacementOf(doc);
    if (d.empty() || d.mask.size() != d.samples.size()) return;
    for (float m : d.mask) dots.masked += m > kShownMask ? 1u : 0u;
    if (dots.masked == 0) return;
    const SculptSamples& sites = sculptSamplesOf(doc);
    const uint32_t stride = (dots.masked + kMaxMaskDots - 1) / kMaxMaskDots;
    uint32_t seen = 0;
    for (uint32_t k = 0; k < d.mask.size(); ++k) {
        if (!(d.mask[k] > kShownMask) || !sites.hasSite(k)) continue;
        if (seen++ % stride != 0) continue;
        // A sample's D at its own site is its value: the grid interpolates through it.
        dots.positions.push_back(sites.position(k) + d.samples[k] * sites.normal(k));
        dots.normals.push_back(sites.normal(k));
        dots.values.push_back(d.mask[k]);
    }
}

}  // namespace qp::editor
