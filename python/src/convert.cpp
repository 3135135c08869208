// Python values to woven's and back, warnings, and a command's code run from Python (bindings.hpp).
#include <atomic>
#include <chrono>
#include <limits>
#include <mutex>
#include <string_view>
#include <thread>

#include "bindings.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/error.hpp"
#include "woven/io/values.hpp"

namespace woven::python {

PyObject* input_warning = nullptr;

namespace {

/// Nesting allowed in values, as in a TOML file (io::kMaxTomlNesting); deeper, or a list that
/// holds itself, is refused rather than recursed into.
constexpr int kMaxDepth = 32;

std::string type_name(py::handle v) { return py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>(); }

nlohmann::json value(py::handle v, const std::string& source, const std::string& field, int depth)
{
    const auto fail = [&](const std::string& expected) -> InputError { return InputError(source, field, expected); };
    if (v.is_none()) return nullptr;  // io refuses it, naming the field
    if (PyBool_Check(v.ptr())) return v.ptr() == Py_True;
    if (PyLong_Check(v.ptr())) {
        int overflow = 0;
        const long long i = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
        if (overflow == 0) return i;
        if (overflow > 0) {
            const unsigned long long u = PyLong_AsUnsignedLongLong(v.ptr());
            if (!PyErr_Occurred()) return u;  // io refuses it above 2^63 - 1, naming the field
            PyErr_Clear();
        }
        throw fail("expected an integer within 64 bits (at most 9223372036854775807), got " + py::str(v).cast<std::string>().substr(0, 40));
    }
    if (PyFloat_Check(v.ptr())) return PyFloat_AsDouble(v.ptr());
    if (PyUnicode_Check(v.ptr())) return v.cast<std::string>();
    if (py::isinstance<Obstacle>(v)) return v.cast<const Obstacle&>().values;  // a scene's obstacle=[...]
    const bool container = PyDict_Check(v.ptr()) || PyList_Check(v.ptr()) || PyTuple_Check(v.ptr());
    if (container && depth >= kMaxDepth) throw fail("nested more than " + std::to_string(kMaxDepth) + " levels deep");
    if (PyDict_Check(v.ptr())) {
        nlohmann::json o = nlohmann::json::object();
        for (auto [k, item] : py::reinterpret_borrow<py::dict>(v)) {
            if (!PyUnicode_Check(k.ptr())) throw fail("expected str keys, got the " + type_name(k) + " key " + py::repr(k).cast<std::string>().substr(0, 40));
            const std::string key = k.cast<std::string>();
            o[key] = value(item, source, field.empty() ? key : field + "." + key, depth + 1);
        }
        return o;
    }
    if (PyList_Check(v.ptr()) || PyTuple_Check(v.ptr())) {
        nlohmann::json a = nlohmann::json::array();
        std::size_t k = 0;
        for (auto item : py::reinterpret_borrow<py::sequence>(v)) {
            ++k;
            a.push_back(value(item, source, field + "[" + std::to_string(k) + "]", depth + 1));
        }
        return a;
    }
    // numpy: an array as its nested list, a scalar as the Python number it holds.
    if (py::hasattr(v, "dtype")) {
        if (py::hasattr(v, "ndim") && v.attr("ndim").cast<int>() > 0) {
            if (depth >= kMaxDepth) throw fail("nested more than " + std::to_string(kMaxDepth) + " levels deep");
            return value(v.attr("tolist")(), source, field, depth);
        }
        if (py::hasattr(v, "item")) return value(v.attr("item")(), source, field, depth);
    }
    throw fail("expected a str, int, float, bool, list or dict, got " + type_name(v));
}

/// The interrupt poll of a job run from Python (app::Monitor::interrupt).
bool poll_python()
{
    if (interpreter_finalizing()) return true;  // stop; the GIL is not to be taken
    py::gil_scoped_acquire gil;
    return signal_seen();
}

}  // namespace

io::SceneSpec Scene::build(std::vector<std::string>* warnings) const
{
    return values ? io::scene_from_values(*values, kPythonScene, base_dir, warnings) : io::find_scene(name_or_path, warnings);
}

nlohmann::json to_values(py::handle v, const std::string& source)
{
    if (!PyDict_Check(v.ptr())) throw InputError(source, "", "expected a dict of the file's keys, got " + type_name(v));
    return value(v, source, "", 0);
}

py::object to_python(const nlohmann::json& j)
{
    using T = nlohmann::json::value_t;
    switch (j.type()) {
    case T::object: {
        py::dict d;
        for (const auto& [k, v] : j.items()) d[py::str(k)] = to_python(v);
        return d;
    }
    case T::array: {
        py::list l;
        for (const auto& v : j) l.append(to_python(v));
        return l;
    }
    case T::string: return py::str(j.get<std::string>());
    case T::boolean: return py::bool_(j.get<bool>());
    case T::number_integer: return py::int_(j.get<std::int64_t>());
    case T::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case T::number_float: return py::float_(j.get<double>());
    default: return py::none();
    }
}

std::optional<std::string> option_text(py::handle v)
{
    if (v.is_none()) return std::nullopt;
    if (PyUnicode_Check(v.ptr())) return v.cast<std::string>();
    if (py::hasattr(v, "__fspath__")) return py::str(py::module_::import("os").attr("fspath")(v)).cast<std::string>();
    if (PyFloat_Check(v.ptr())) return py::repr(v).cast<std::string>();
    return py::str(v).cast<std::string>();
}

std::string python_message(const InputError& e)
{
    if (e.source() != app::kCommandLine || e.field().rfind("--", 0) != 0) return e.what();
    const std::string prefix = e.source() + ": " + e.field() + ": ";
    const std::string what = e.what();
    return app::keyword_of(e.field()) + ": " + (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
}

namespace {

/// A Python int (not a bool) as it is; nullopt for any other type or one beyond 64 bits.
std::optional<long long> python_integer(py::handle v)
{
    if (!PyLong_Check(v.ptr()) || PyBool_Check(v.ptr())) return std::nullopt;
    int overflow = 0;
    const long long value = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    if (overflow != 0) return std::nullopt;  // read as text: the message shows the value given
    return value;
}

/// A Python int or float as a double; nullopt for any other type.
std::optional<double> python_number(py::handle v)
{
    if (PyBool_Check(v.ptr())) return std::nullopt;
    if (PyFloat_Check(v.ptr())) return PyFloat_AsDouble(v.ptr());
    if (PyLong_Check(v.ptr())) return v.cast<double>();
    return std::nullopt;
}

}  // namespace

// Typed values go to the checks as they are (no text); a string, or an int beyond 64 bits, is
// read as the command reads its option's text.
std::optional<app::Given<long long>> given_integer(py::handle v)
{
    if (v.is_none()) return std::nullopt;
    if (const auto i = python_integer(v)) return *i;
    return *option_text(v);
}

std::optional<app::Given<std::uint64_t>> given_seed(py::handle v)
{
    if (v.is_none()) return std::nullopt;
    if (const auto i = python_integer(v); i && *i >= 0) return static_cast<std::uint64_t>(*i);
    return *option_text(v);
}

std::optional<app::Given<double>> given_number(py::handle v)
{
    if (v.is_none()) return std::nullopt;
    if (const auto x = python_number(v)) return *x;
    return *option_text(v);
}

std::optional<long long> integer_arg(py::handle v, const app::ValueName& name, long long lo, long long hi)
{
    const auto g = given_integer(v);
    if (!g) return std::nullopt;
    return app::integer_value(*g, name, lo, hi);
}

std::optional<std::uint64_t> seed_arg(py::handle v, const app::ValueName& name)
{
    const auto g = given_seed(v);
    if (!g) return std::nullopt;
    return app::seed_value(*g, name);
}

std::optional<double> number_arg(py::handle v, const app::ValueName& name, double lo, double hi)
{
    const auto g = given_number(v);
    if (!g) return std::nullopt;
    return app::number_value(*g, name, lo, hi);
}

std::optional<double> positive_arg(py::handle v, const app::ValueName& name, double hi)
{
    const auto g = given_number(v);
    if (!g) return std::nullopt;
    return app::positive_value(*g, name, hi);
}

FabricArg fabric_arg(py::handle fabric)
{
    FabricArg a;
    if (py::isinstance<Fabric>(fabric)) {
        const Fabric& f = fabric.cast<const Fabric&>();
        a.name = f.data->name;
        a.given = {f.data, f.source};
    } else {
        a.name = option_text(fabric).value_or("");
    }
    return a;
}

namespace {

std::atomic<bool> g_exiting{false};      ///< set by stop_calls_at_exit as it starts
std::atomic<bool> g_exit_passed{false};  ///< set as it returns: the interpreter may finalize from then on
std::atomic<int> g_released{0};          ///< threads in without_gil

/// Waits for the process to end, touching nothing: for a thread without the GIL once taking it
/// back is unsafe (Python 3.11 ends a thread that takes the GIL while finalizing with
/// pthread_exit, whose unwinding through C++ frames aborts: "exception not rethrown").
[[noreturn]] void park_until_exit()
{
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
}

}  // namespace

/// The interpreter itself is finalizing: the GIL must not be taken.
bool python_finalizing()
{
#if PY_VERSION_HEX >= 0x030D0000
    return Py_IsFinalizing() != 0;
#else
    return _Py_IsFinalizing() != 0;
#endif
}

bool interpreter_finalizing() { return g_exiting.load() || python_finalizing(); }

void wait_out_finalization()
{
    // At exit but with the atexit hook still waiting for this call: return (and release the
    // call) as usual. Once the hook has passed (its 30 s were up) the interpreter may finalize
    // at any moment: taking the GIL could end this thread inside C++.
    if (g_exit_passed.load() || python_finalizing()) park_until_exit();
}

bool signal_seen()
{
    if (PyErr_CheckSignals() == 0) return false;
    PyErr_Clear();
    return true;
}

void warn(const std::vector<std::string>& warnings)
{
    for (const auto& w : warnings)
        if (PyErr_WarnEx(input_warning, w.c_str(), 1) != 0) throw py::error_already_set();
}

namespace {

std::timed_mutex g_call_mutex;
thread_local int t_call_depth = 0;        ///< CallLocks held by this thread
thread_local int t_callback_depth = 0;    ///< progress callbacks running on this thread

}  // namespace

CallLock::CallLock()
{
    if (t_callback_depth > 0)
        throw RuntimeError("a woven call from inside a progress callback of a running woven call would wait for itself; "
                           "call it after the running one returns (or from another thread)");
    if (t_call_depth++ > 0) return;
    try {
        for (;;) {
            bool locked = false;
            {
                py::gil_scoped_release release;
                locked = g_call_mutex.try_lock_for(std::chrono::milliseconds(50));
                // The GIL is taken back (the release's end) only where the interpreter cannot
                // finalize meanwhile: the atexit hook (stop_calls_at_exit) waits for the lock this
                // thread holds, or has not started. Once it has passed, or started while another
                // call holds the lock, a daemon thread here would be ended inside C++ (SIGABRT
                // "exception not rethrown" at exit, issue 53): it waits for the process to end.
                if (g_exit_passed.load() || (!locked && g_exiting.load())) park_until_exit();
            }
            if (locked) break;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        }
        // Once the interpreter's atexit callbacks run (stop_calls_at_exit, which holds the GIL
        // as this check does) no call starts: it could not finish before the interpreter does.
        if (g_exiting.load()) {
            g_call_mutex.unlock();
            throw RuntimeError("the interpreter is exiting: no woven call starts now");
        }
    } catch (...) {
        --t_call_depth;
        throw;
    }
}

CallLock::~CallLock()
{
    if (--t_call_depth == 0) g_call_mutex.unlock();
}

void stop_calls_at_exit()
{
    g_exiting = true;
    if (t_call_depth > 0) return;  // this thread's own call (an atexit callback inside one): nothing to wait for
    {
        const py::gil_scoped_release release;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        if (g_call_mutex.try_lock_until(deadline)) g_call_mutex.unlock();
        while (g_released.load() > 0 && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    g_exit_passed = true;
}

void without_gil(const std::function<void()>& f)
{
    if (g_exiting.load()) {  // the atexit hook has started (both hold the GIL): keep it
        f();
        return;
    }
    ++g_released;  // the hook now waits for this thread to take the GIL back
    std::exception_ptr failure;
    {
        py::gil_scoped_release release;
        try {
            f();
        } catch (...) {
            failure = std::current_exception();
        }
        if (g_exit_passed.load()) park_until_exit();  // the hook's 30 s were up
    }
    --g_released;
    if (failure) std::rethrow_exception(failure);
}

InCallback::InCallback() { ++t_callback_depth; }
InCallback::~InCallback() { --t_callback_depth; }

py::dict event_dict(const app::ProgressEvent& e)
{
    py::dict d;
    d["event"] = e.event;
    const std::string kind = e.event;
    if (kind == "activity") {
        d["label"] = e.label;
        d["detail"] = e.detail;
        d["fraction"] = e.fraction;
    } else if (kind == "step") {
        d["step"] = e.step;
        d["max_steps"] = e.max_steps;
        d["time_s"] = e.time_s;
        d["energy_J"] = e.energy_J;
        d["residual"] = e.residual;
        d["tolerance"] = e.tolerance;
        d["move_m"] = e.move_m;
        d["fraction"] = e.fraction;
    } else {
        d["step"] = e.step;
        d["iteration"] = e.iteration;
        d["total_iterations"] = e.total_iterations;
        d["time_step_s"] = e.time_step_s;
        d["residual"] = e.residual;
        d["tolerance"] = e.tolerance;
    }
    d["wall_s"] = e.wall_s;
    return d;
}

bool call_progress(py::handle progress, py::dict info, std::optional<py::error_already_set>& error)
{
    try {
        const InCallback in_callback;
        const py::object answer = progress(info);
        // Python's truth, not the object False: numpy's False and 0 stop too; None goes on.
        if (answer.is_none()) return true;
        const int truth = PyObject_IsTrue(answer.ptr());
        if (truth < 0) throw py::error_already_set();
        return truth != 0;
    } catch (py::error_already_set& e) {
        if (!e.matches(PyExc_KeyboardInterrupt) && !error) error = std::move(e);
        return false;
    }
}

void run_command(const std::function<void(const app::Monitor&)>& f, py::handle progress)
{
    const CallLock lock;
    if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw py::type_error("progress must be callable or None");
    std::exception_ptr failure;
    std::optional<py::error_already_set> callback_error;
    // The job's monitor: no display, Ctrl-C polled, progress events to the callable.
    app::Monitor monitor;
    monitor.quiet = true;
    monitor.interrupt = &poll_python;
    if (!progress.is_none())
        monitor.progress = [&](const app::ProgressEvent& e) {
            // The ends of a drape's steps and of an activity are for a display: not passed on.
            const std::string_view kind = e.event;
            if (kind == "steps-end" || kind == "activity-end") return true;
            if (interpreter_finalizing()) return false;
            py::gil_scoped_acquire gil;
            if (signal_seen()) return false;
            return call_progress(progress, event_dict(e), callback_error);
        };
    {
        py::gil_scoped_release release;
        try {
            f(monitor);
        } catch (...) {
            failure = std::current_exception();
        }
        wait_out_finalization();  // before the GIL is taken back
    }
    if (callback_error) throw std::move(*callback_error);
    if (failure) std::rethrow_exception(failure);
}

}  // namespace woven::python
