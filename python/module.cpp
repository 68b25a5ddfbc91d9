// The compiled part of the Python package `quadplan` (python/quadplan/__init__.py re-exports
// it): docs/python.md is the guide, every function and class carries its docstring.
#include "conversions.h"

PYBIND11_MODULE(_quadplan, m) {
    using namespace qp::py;
    m.doc() = "Quadplan's scripting interface: scenes, cages, edits with undo, limit evaluation, rendering "
              "through the scheme plugins and scheme comparison. See docs/python.md.";
    static py::exception<ScriptError> error(m, "Error", PyExc_RuntimeError);
    error.attr("__doc__") = "A Quadplan operation failed; the message is the one the command line prints.";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const ScriptError& e) {
            error(e.what());
        }
    });
    bindCage(m);
    bindScene(m);
    bindRender(m);
}
