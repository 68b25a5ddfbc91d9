// The SPIR-V a scheme module carries: its stage files, compiled and embedded at build time by
// quadplan_scheme_shaders (plugins/CMakeLists.txt), plus tess_patch.vert. Every module has its
// own definition of this function, hidden inside the module (modules export only their entry
// point), so two modules never see each other's shaders.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace qp {

// The code of the module's shader whose source file is named `name` ("acc2.tese"), or an empty
// span.
std::span<const uint32_t> moduleShaderCode(std::string_view name);

}  // namespace qp
