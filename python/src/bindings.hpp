#pragma once
// Shared by the binding files of the Python module (python/): woven's fabrics and scenes as
// Python objects, conversions of Python values, warnings, and running a command's code with
// the GIL released, its printing captured and Ctrl-C polled.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

#include "woven/cli/commands.hpp"
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
/// The text a command line would carry for an option's value: None -> nullopt, str as is,
/// os.PathLike as its path, anything else as str(value) (repr for a float, which reads back).
std::optional<std::string> option_text(py::handle value);
/// A fabric argument: a name or path (str, os.PathLike) or a woven.Fabric.
struct FabricArg {
    std::string name;
    cli::GivenFabric given;
};
FabricArg fabric_arg(py::handle fabric);
/// woven.InputWarning (a UserWarning), made by module.cpp.
extern PyObject* input_warning;
/// Issues each warning as a Python warning of category woven.InputWarning.
void warn(const std::vector<std::string>& warnings);
/// Runs `f` (a command's code) with the GIL released, std::cout and std::cerr captured, the
/// progress line off and Ctrl-C (a signal the interpreter has seen) polled as an interrupt.
/// The lines "woven: warning: ..." it printed are issued as Python warnings. Returns true when
/// it was interrupted; `out` receives what it printed on stdout.
bool run_command(const std::function<void()>& f, std::string* out = nullptr);
/// True (and the interpreter's error cleared) when a signal handler raised, i.e. Ctrl-C was
/// pressed; call with the GIL held.
bool signal_seen();

// One function per file, called by module.cpp.
void bind_fabric_scene(py::module_& m);  // fabric_scene.cpp
void bind_drape(py::module_& m);         // drape.cpp
void bind_testers(py::module_& m);       // testers.cpp

}  // namespace woven::python
