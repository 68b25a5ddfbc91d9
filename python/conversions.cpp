#include "conversions.h"

#include <cmath>

namespace qp::py {

const NameTable<BoundaryInterpolation> kBoundaryNames = {{"edges-and-corners", BoundaryInterpolation::EdgesAndCorners},
                                                         {"edges-only", BoundaryInterpolation::EdgesOnly},
                                                         {"none", BoundaryInterpolation::None}};
const NameTable<CreaseMethod> kCreaseMethodNames = {{"normal", CreaseMethod::Normal}, {"chaikin", CreaseMethod::Chaikin}};
const NameTable<TriangleSubdivision> kTriangleNames = {{"catmark", TriangleSubdivision::Catmark},
                                                       {"smooth", TriangleSubdivision::Smooth}};
const NameTable<SelectionMode> kSelectionModeNames = {
    {"vertex", SelectionMode::Vertex}, {"edge", SelectionMode::Edge}, {"face", SelectionMode::Face}};
const NameTable<TransformSpace> kSpaceNames = {{"world", TransformSpace::World}, {"local", TransformSpace::Local}};

void warnAll(const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings) PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 2);
    if (PyErr_Occurred()) throw py::error_already_set();  // warnings turned into errors
}

py::array_t<float> toArray(const std::vector<glm::vec3>& points) {
    py::array_t<float> out({py::ssize_t(points.size()), py::ssize_t(3)});
    auto view = out.mutable_unchecked<2>();
    for (size_t i = 0; i < points.size(); ++i)
        for (int c = 0; c < 3; ++c) view(py::ssize_t(i), c) = points[i][c];
    return out;
}

py::array_t<uint32_t> toArray(const std::vector<uint32_t>& values) {
    py::array_t<uint32_t> out(py::ssize_t(values.size()));
    std::copy(values.begin(), values.end(), out.mutable_data());
    return out;
}

std::vector<glm::vec3> pointsFrom(const py::object& object, const std::string& what) {
    py::array_t<double, py::array::c_style | py::array::forcecast> array;
    try {
        array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
    } catch (const py::error_already_set&) {
        array = {};
    }
    if (!array || (!(array.ndim() == 2 && array.shape(1) == 3) && !(array.ndim() == 1 && array.shape(0) == 3)))
        throw ScriptError(what + " must be an (N, 3) array of numbers (or one point [x, y, z])");
    const size_t n = array.ndim() == 2 ? size_t(array.shape(0)) : 1;
    std::vector<glm::vec3> points(n);
    const double* data = array.data();
    for (size_t i = 0; i < n; ++i) {
        points[i] = glm::vec3(float(data[3 * i]), float(data[3 * i + 1]), float(data[3 * i + 2]));
        if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z))
            throw ScriptError(what + ": point " + std::to_string(i) + " is not finite");
    }
    return points;
}

glm::vec3 vec3From(const py::object& object, const std::string& what) {
    if (py::isinstance<py::float_>(object) || py::isinstance<py::int_>(object)) {
        const float value = object.cast<float>();
        return glm::vec3(value);
    }
    std::vector<glm::vec3> points = pointsFrom(object, what);
    if (points.size() != 1) throw ScriptError(what + " must be one vector [x, y, z]");
    return points[0];
}

std::vector<uint32_t> indicesFrom(const py::object& object, const std::string& what) {
    if (py::isinstance<py::int_>(object)) {
        const long long value = object.cast<long long>();
        if (value < 0 || value > (long long)(UINT32_MAX - 1)) throw ScriptError(what + ": index " + std::to_string(value) + " is out of range");
        return {uint32_t(value)};
    }
    const py::object numpyInteger = py::module_::import("numpy").attr("integer");
    std::vector<uint32_t> out;
    if (py::isinstance<py::str>(object)) throw ScriptError(what + " must be a sequence of integer indices");
    for (const py::handle item : py::iter(object)) {
        if (!py::isinstance<py::int_>(item) && !py::isinstance(item, numpyInteger))
            throw ScriptError(what + " must be a sequence of integer indices");
        const long long value = item.cast<long long>();
        if (value < 0 || value > (long long)(UINT32_MAX - 1))
            throw ScriptError(what + ": index " + std::to_string(value) + " is out of range");
        out.push_back(uint32_t(value));
    }
    return out;
}

}  // namespace qp::py
