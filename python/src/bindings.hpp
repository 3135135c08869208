#pragma once
// Shared by the binding files of the Python module (python/): woven's fabrics and scenes as
// Python objects, conversions of Python values, warnings, and running a command's code with
// the GIL released, its printing captured and Ctrl-C polled.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/error.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/kes/fabric.hpp"

namespace woven::python {

namespace py = pybind11;

/// The sources that name a fabric or scene made from Python values in messages.
inline constexpr const char* kPythonFabric = "Python fabric";
inline constexpr const char* kPythonScene = "Python scene";

/// woven.Fabric: a fabric read from a file, a built-in, or made from values.
struct Fabric {
    std::shared_ptr<const kes::FabricData> data;
    std::string source;  ///< names it in messages: the path, "built-in fabric 'cotton'" or "Python fabric"
};

/// woven.Obstacle: one obstacle of a scene as the values of its [[obstacle]] table
/// (docs/SCENE-FORMAT.md), checked by the scene reader's own builder when made.
struct Obstacle {
    nlohmann::json values;
    std::string kind;
    std::shared_ptr<const geometry::Obstacle> built;  ///< for its attributes
};
/// The source that names an obstacle made from Python values in messages.
inline constexpr const char* kPythonObstacle = "Python obstacle";

/// woven.Scene. io::SceneSpec holds its obstacles and cannot be copied, so a scene keeps how it
/// was made and builds a fresh one for each drape (the same reading as the first).
struct Scene {
    std::string name_or_path;              ///< loaded (io::find_scene), or
    std::optional<nlohmann::json> values;  ///< made from values (io::scene_from_values)
    std::string base_dir;                  ///< relative paths in the values resolve against it
    std::shared_ptr<const io::SceneSpec> spec;  ///< the scene as read, for its attributes

    io::SceneSpec build(std::vector<std::string>* warnings) const;
};

// convert.cpp
/// A Python value (dict, list, tuple, str, int, float, bool, numpy arrays and scalars) as a tree
/// of values for io::*_from_values; InputError "<source>: <field>: ..." for anything else.
nlohmann::json to_values(py::handle value, const std::string& source);
/// A JSON document (a report) as Python dicts, lists, str, int, float, bool and None.
py::object to_python(const nlohmann::json& j);
/// An InputError's message as Python shows it: a field named by a command-line option of the
/// command line ("command line: --max-steps: ...") is named by its keyword ("max_steps: ...").
std::string python_message(const InputError& e);
/// The text a command line would carry for an option's value: None -> nullopt, str as is,
/// os.PathLike as its path, anything else as str(value) (repr for a float, which reads back).
std::optional<std::string> option_text(py::handle value);
/// An option's Python value for the request builders (app/files.hpp Given): None -> nullopt; an
/// int (not a bool) within 64 bits, or a float for a number, as it is; anything else as its
/// text (option_text), read as the command reads it.
std::optional<app::Given<long long>> given_integer(py::handle value);
std::optional<app::Given<std::uint64_t>> given_seed(py::handle value);  ///< an int >= 0 as it is
std::optional<app::Given<double>> given_number(py::handle value);
/// The typed value of an option given as a Python value (given_*), checked: None -> nullopt;
/// InputError "command line: <option>: expected ..." as the command's own for a value that is
/// not one, or out of [lo, hi].
std::optional<long long> integer_arg(py::handle value, const app::ValueName& name, long long lo, long long hi);
std::optional<std::uint64_t> seed_arg(py::handle value, const app::ValueName& name);
std::optional<double> number_arg(py::handle value, const app::ValueName& name, double lo, double hi);
/// A number in (0, hi] ("expected a number in (0, hi], got ...").
std::optional<double> positive_arg(py::handle value, const app::ValueName& name, double hi);
/// The enum value a Python str names in `table` (common/choice.hpp); None -> nullopt.
template <class E, std::size_t N>
std::optional<E> choice_arg(py::handle value, const app::ValueName& name, const std::array<Named<E>, N>& table)
{
    const std::optional<std::string> text = option_text(value);
    if (!text) return std::nullopt;
    return app::named_choice(*text, name, table);
}
/// A fabric argument: a name or path (str, os.PathLike) or a woven.Fabric.
struct FabricArg {
    std::string name;
    app::GivenFabric given;
};
FabricArg fabric_arg(py::handle fabric);
/// woven.InputWarning (a UserWarning), made by module.cpp.
extern PyObject* input_warning;
/// Issues each warning as a Python warning of category woven.InputWarning.
void warn(const std::vector<std::string>& warnings);
/// One woven call at a time in a process: the commands' printing (std::cout and std::cerr,
/// captured), the interrupt poll and the solver's thread counts (OpenMP, oneTBB, the BLAS) are
/// process-wide, so calls from several Python threads run one after the other, each with its own
/// state. Taken with the GIL held; it waits without the GIL, and Ctrl-C while it waits raises
/// KeyboardInterrupt. Nested on one thread it is held once. A woven call from a progress callback
/// of a running call raises woven.Error (it would wait for itself).
/// At interpreter exit the atexit hook (stop_calls_at_exit) waits for the call holding it, so a
/// daemon thread may release and take back the GIL while it holds it, never after: a binding
/// holds it for the whole call, its results converted to Python included (Python code run then
/// can hand the GIL to the exiting main thread).
class CallLock {
public:
    CallLock();
    ~CallLock();
    CallLock(const CallLock&) = delete;
    CallLock& operator=(const CallLock&) = delete;
};
/// Marks this thread as running a progress callback for its lifetime (see CallLock).
class InCallback {
public:
    InCallback();
    ~InCallback();
    InCallback(const InCallback&) = delete;
    InCallback& operator=(const InCallback&) = delete;
};
/// Runs `f` (a job), holding a CallLock, with the GIL released; `f` gets the Monitor to put in
/// its request (app/progress.hpp): Ctrl-C (a signal the interpreter has seen) polled as an
/// interrupt, and the progress events to `progress` (a callable, or None) as dicts; False or
/// KeyboardInterrupt from it stops the job as Ctrl-C does; another exception from it is raised
/// once the job has stopped. The job prints nothing (app never does); its warnings come back in
/// its result or its request's on_warnings, which the caller issues as Python warnings (warn).
void run_command(const std::function<void(const app::Monitor&)>& f, py::handle progress = py::none());
/// An app::ProgressEvent as the dict a progress callable gets: a step's and an iteration's with
/// the keys of woven.drape's progress (every job's the same), an activity's with its label and detail.
py::dict event_dict(const app::ProgressEvent& e);
/// Calls `progress(info)` (marked InCallback): false when it returned False or raised; the first
/// exception other than KeyboardInterrupt is kept in `error`. With the GIL held.
bool call_progress(py::handle progress, py::dict info, std::optional<py::error_already_set>& error);
/// True (and the interpreter's error cleared) when a signal handler raised, i.e. Ctrl-C was
/// pressed; call with the GIL held.
bool signal_seen();
/// True once the interpreter is shutting down (a daemon thread still in a woven call): from its
/// atexit callbacks on (stop_calls_at_exit), or finalizing. A running call stops at its next step
/// and must not take the GIL once it is finalizing.
bool interpreter_finalizing();
/// Registered with Python's atexit (the module's init): asks a woven call running on another
/// thread to stop, and waits for it (at most 30 s, the GIL released), so that no solve still
/// runs while the process exits (issue 53: "pure virtual method called", SIGSEGV, SIGABRT).
void stop_calls_at_exit();
/// Runs `f` with the GIL released, for short work outside a woven call (reading a fabric or a
/// scene): the atexit hook waits for it as for a call, so the GIL is taken back before the
/// interpreter can finalize; once the hook has started, `f` runs with the GIL held.
void without_gil(const std::function<void()>& f);
/// On a thread without the GIL, before it takes it back: when the interpreter is shutting down,
/// waits for the process to end instead of returning (issue 53: SIGABRT at exit).
void wait_out_finalization();

// One function per file, called by module.cpp.
void bind_fabric_scene(py::module_& m);  // fabric_scene.cpp
void bind_drape(py::module_& m);         // drape.cpp
void bind_testers(py::module_& m);       // testers.cpp
void bind_obstacle(py::module_& m);      // obstacle.cpp
void bind_garment(py::module_& m);       // garment.cpp

}  // namespace woven::python
