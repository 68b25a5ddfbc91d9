// What every binding file shares: the exception a failed Result becomes, NumPy conversions of
// the core's flat arrays, and the names enums have in scene files and on the command line.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp::py {

namespace py = pybind11;

// Raised as quadplan.Error with the Result's message (what the command line prints after
// "error: ").
struct ScriptError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

template <class T>
T unwrap(Result<T> result) {
    if (!result) throw ScriptError(result.error().message);
    return std::move(result).value();
}
inline void check(const Status& status) {
    if (!status) throw ScriptError(status.error().message);
}

// Passes each loader warning to Python's warnings module (the command line prints them to
// stderr as "warning: ...").
void warnAll(const std::vector<std::string>& warnings);

// (N, 3) float32 array, copied.
py::array_t<float> toArray(const std::vector<glm::vec3>& points);
py::array_t<uint32_t> toArray(const std::vector<uint32_t>& values);
// Any (N, 3) array-like of numbers; `what` names it in the error.
std::vector<glm::vec3> pointsFrom(const py::object& object, const std::string& what);
glm::vec3 vec3From(const py::object& object, const std::string& what);
// Any sequence of non-negative integers.
std::vector<uint32_t> indicesFrom(const py::object& object, const std::string& what);

// Enum names as scene files spell them (docs/scene-format.md).
template <class E>
using NameTable = std::vector<std::pair<std::string_view, E>>;
extern const NameTable<BoundaryInterpolation> kBoundaryNames;
extern const NameTable<CreaseMethod> kCreaseMethodNames;
extern const NameTable<TriangleSubdivision> kTriangleNames;
extern const NameTable<SelectionMode> kSelectionModeNames;
extern const NameTable<TransformSpace> kSpaceNames;

template <class E>
E enumFrom(const NameTable<E>& table, const std::string& name, const std::string& what) {
    std::string known;
    for (const auto& [n, value] : table) {
        if (n == name) return value;
        known += (known.empty() ? "" : ", ") + std::string(n);
    }
    throw ScriptError("unknown " + what + " '" + name + "'; use " + known);
}
template <class E>
std::string enumName(const NameTable<E>& table, E value) {
    for (const auto& [n, v] : table)
        if (v == value) return std::string(n);
    return "?";
}

void bindCage(py::module_& m);
void bindScene(py::module_& m);
void bindRender(py::module_& m);

}  // namespace qp::py
