// How the commands that draw (render, compare) report a frame's culling (DrawView::cull,
// DrawStats::cull) in their JSON.
#pragma once

#include <nlohmann/json.hpp>

#include "scheme_api.h"

namespace qp::cli {

// {"method", "tested", "frustum", "back_facing", "frustum_only", "cull_ms"}: the patches the
// frame tested, those culled outside the frustum and facing away, those only the frustum could
// test, and the CPU time the tests took.
inline nlohmann::json cullJson(CullMethod method, const DrawStats& draw) {
    return {{"method", cullMethodName(method)},       {"tested", draw.cull.tested},
            {"frustum", draw.cull.frustum},           {"back_facing", draw.cull.backFacing},
            {"frustum_only", draw.cull.frustumOnly},  {"cull_ms", draw.cullMilliseconds}};
}

}  // namespace qp::cli
