// The Python module woven._woven (imported by the package woven, python/woven/__init__.py).
#include "bindings.hpp"
#include "woven/common/error.hpp"

PYBIND11_MODULE(_woven, m)
{
    namespace py = pybind11;
    using namespace woven::python;
    m.doc() = "woven: drape of woven cloth from Kawabata (KES) measurements (Breen, House & Wozny 1994).";
    m.attr("__version__") = WOVEN_VERSION;
    // Bad input: woven's one-line message ("<source>: <field>: <what is expected>"), as the
    // command prints it after "woven: error: ". A ValueError.
    // A value the request names by its command-line option ("command line: --grid: ...") is
    // named by the Python keyword that gave it ("grid: ...").
    static py::exception<woven::InputError> input_error(m, "InputError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const woven::InputError& e) {
            PyErr_SetString(input_error.ptr(), python_message(e).c_str());
        }
    });
    // A failure on valid input (an I/O error, a non-finite state): a RuntimeError.
    py::register_exception<woven::RuntimeError>(m, "Error", PyExc_RuntimeError);
    input_warning = PyErr_NewExceptionWithDoc("woven.InputWarning",
                                              "A warning about an input that is read anyway: an unknown key, a value outside "
                                              "the usual range, more threads than cores.",
                                              PyExc_UserWarning, nullptr);
    m.attr("InputWarning") = py::handle(input_warning);
    bind_obstacle(m);
    bind_fabric_scene(m);
    bind_drape(m);
    bind_testers(m);
    bind_garment(m);
    // A woven call on a daemon thread is stopped before the interpreter finalizes (issue 53).
    py::module_::import("atexit").attr("register")(py::cpp_function(&stop_calls_at_exit));
}
