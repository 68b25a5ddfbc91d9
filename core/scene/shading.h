// How a renderer lights a surface: the scene's Display setting, passed to every scheme through
// DrawView (plugins/scheme_api.h) and to MeshPass (render/mesh_pass.h).
#pragma once

#include <cstdint>

namespace qp {

enum class Shading : uint8_t {
    Studio,  // world-fixed key and fill lights (plans) or a headlight with a fill (meshes)
    Matcap,  // a procedural clay material looked up by the view-space normal: follows the camera
};

}  // namespace qp
