#pragma once
// The check job (woven check FILE|DIR...): validates inputs and finished outputs without simulating.
//   *.toml  a fabric or a scene file, read by the commands' own readers (a scene's fabric and mesh
//           files too), and the fabric's curves fitted as a run fits them;
//   *.obj   a mesh, read by the obstacle reader;
//   a folder  a finished output set: its manifest (report.json, cusick.json or kes-report.json)
//           parses, every file it lists is there with its size and SHA-256, its numbers are
//           finite, and its OBJ meshes read; a sweep folder: every point listed as done
//           verifies; an experiment's folder: each of its sets verifies.
#include <string>
#include <vector>

namespace woven::app {

/// The manifests of the jobs' output sets, in the order they are looked for (check, report).
inline constexpr const char* kManifests[] = {"report.json", "cusick.json", "kes-report.json"};

/// One output folder checked: the problems found, one line each (none: a complete set, its
/// manifest's files there with their sizes and SHA-256); `what` gets the ok line's text.
std::vector<std::string> check_output_folder(const std::string& dir, std::string* what = nullptr);
/// The same for the one set of `dir` whose manifest is `manifest` (an experiment's folder holds
/// up to three: cube_results.json, corner_map.json, figure1.json).
std::vector<std::string> check_output_set(const std::string& dir, const std::string& manifest);

/// One file or folder checked.
struct CheckResult {
    std::vector<std::string> problems;  ///< one line each ("<file>: <field>: <what is wrong>")
    std::vector<std::string> warnings;  ///< the readers' warnings, as the commands show them
    std::string what;                   ///< sound: what it is ("fabric cotton", "output of drape, 5 files listed in report.json")
};
CheckResult check_path(const std::string& path);

}  // namespace woven::app
