// The check job (check.hpp): inputs and finished outputs validated without simulating.
#include "woven/app/check.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/files.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/sha256.hpp"
#include "woven/io/toml_reader.hpp"
#include "woven/kes/fit.hpp"
#include "woven/render/gltf_file.hpp"

namespace woven::app {

namespace {

namespace fs = std::filesystem;

/// The problems found so far, one line each.
struct Findings {
    std::vector<std::string> problems;
    void problem(const std::string& line) { problems.push_back(line); }
};

/// A scene file names a [cloth] or [[obstacle]] table (docs/SCENE-FORMAT.md); a fabric file
/// neither. A plain scan of the lines' starts (no regex: std::regex recurses per character).
bool looks_like_scene(const std::string& text)
{
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::size_t k = line.find_first_not_of(" \t");
        if (k == std::string::npos || line[k] != '[') continue;
        k = line.find_first_not_of("[ \t", k);
        if (k == std::string::npos) continue;
        for (const std::string table : {"cloth", "obstacle"})
            if (line.compare(k, table.size(), table) == 0) {
                const std::size_t e = line.find_first_not_of(" \t", k + table.size());
                if (e != std::string::npos && (line[e] == ']' || line[e] == '.')) return true;
            }
    }
    return false;
}

/// Fits the fabric's curves as a run does (kes::fit_fabric), errors naming its file.
void fit(const kes::FabricData& fabric, const std::string& name_or_path)
{
    with_fabric_source(fabric_source(name_or_path), [&] { (void)kes::fit_fabric(fabric); });
}

std::string check_toml(const std::string& path, std::vector<std::string>& warnings)
{
    // Read as the commands read their input (bounded, regular files only: a FIFO named x.toml
    // does not block check), then given to the scene or the fabric reader.
    const std::string text = io::read_input_file(path, io::kMaxTomlBytes, {"TOML file", "a fabric or scene .toml file"});
    if (looks_like_scene(text)) {
        const io::SceneSpec scene = io::load_scene(path, &warnings);
        if (scene.cloth.is_cut()) (void)scene.cloth.cut(scene.source_path);  // the outline keeps a cloth
        const kes::FabricData fabric = io::find_fabric(scene.fabric, &warnings);
        fit(fabric, scene.fabric);
        return "scene " + scene.name + ", " + std::to_string(scene.cloth.nu) + " x " + std::to_string(scene.cloth.nv) +
               " particles, " + std::to_string(scene.obstacle_kinds.size()) + " obstacles, fabric " +
               (fabric.name.empty() ? scene.fabric : fabric.name);
    }
    const kes::FabricData fabric = io::load_fabric_file(path, &warnings);
    fit(fabric, path);
    return "fabric " + fabric.name;
}

/// Every null (a non-finite number as JSON writes it) or non-finite number under `j`.
void non_finite(const nlohmann::json& j, const std::string& path, std::vector<std::string>& out)
{
    if (j.is_null() || (j.is_number_float() && !std::isfinite(j.get<double>()))) out.push_back(path);
    if (j.is_object())
        for (auto it = j.begin(); it != j.end(); ++it) non_finite(it.value(), path.empty() ? it.key() : path + "." + it.key(), out);
    if (j.is_array())
        for (std::size_t k = 0; k < j.size(); ++k) non_finite(j[k], path + "[" + std::to_string(k) + "]", out);
}

/// A name in a manifest: a plain file name in the folder (no separators, not . or ..).
bool plain_name(const std::string& n) { return !n.empty() && n != "." && n != ".." && n.find('/') == std::string::npos; }

/// Checks one file the manifest lists: present, a regular file, and (when given) its size and
/// SHA-256; an OBJ or a GLB also reads.
void check_listed(const fs::path& dir, const std::string& manifest, const std::string& name, const nlohmann::json* entry,
                  Findings& f)
{
    const std::string shown = (dir / name).string();
    if (!plain_name(name)) {
        f.problem(manifest + ": files: '" + name + "' is not a file name in the folder");
        return;
    }
    std::error_code ec;
    if (!fs::exists(dir / name, ec)) {
        f.problem(shown + ": file: listed in " + manifest + " but missing");
        return;
    }
    // Bounded and regular files only (a FIFO does not block check, a link to /dev/zero is not read).
    std::optional<std::string> data;
    try {
        data = io::read_output_member(shown);
    } catch (const InputError& e) {
        f.problem(e.what());
        return;
    }
    if (entry) {
        if (!entry->is_object() || !(*entry)["bytes"].is_number_unsigned() || !(*entry)["sha256"].is_string()) {
            f.problem(manifest + ": files." + name + ": expected {\"bytes\": n, \"sha256\": \"<hex>\"}");
            return;
        }
        const auto bytes = (*entry)["bytes"].get<std::uint64_t>();
        if (bytes != data->size())
            f.problem(shown + ": bytes: " + std::to_string(data->size()) + ", the manifest says " + std::to_string(bytes));
        else if ((*entry)["sha256"].get<std::string>() != io::sha256_hex(*data))
            f.problem(shown + ": sha256: differs from " + manifest + "'s (the file changed after the run)");
    }
    try {
        if (name.ends_with(".obj")) (void)io::parse_obj_mesh(*data, shown);
        if (name.ends_with(".glb")) (void)render::check_glb(*data, shown);
    } catch (const InputError& e) {
        f.problem(e.what());
    }
}

/// The experiments' manifests (cmd_experiment.cpp); the three may share a folder.
constexpr const char* kExperimentManifests[] = {"cube_results.json", "corner_map.json", "figure1.json"};

std::string check_set(const fs::path& dir, const std::string& name, Findings& f);

std::string check_folder(const fs::path& dir, Findings& f)
{
    std::string name;
    for (const char* m : kManifests)
        if (fs::exists(dir / m)) {
            name = m;
            break;
        }
    if (name.empty()) {
        f.problem(dir.string() + ": manifest: no report.json, cusick.json or kes-report.json (not a finished woven output folder)");
        return {};
    }
    return check_set(dir, name, f);
}

/// A sweep folder (sweep.json, `woven sweep`): the merged table parses and every point it lists
/// as done verifies as an output folder; failed and missing points are counted, not problems (a
/// sweep may be unfinished).
std::string check_sweep(const fs::path& dir, Findings& f)
{
    const std::size_t before = f.problems.size();
    const std::string manifest = (dir / "sweep.json").string();
    const auto text = read_output_file(manifest);
    if (!text) {
        f.problem(manifest + ": file: cannot read");
        return {};
    }
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(*text);
    } catch (const nlohmann::json::exception& e) {
        f.problem(manifest + ": json: does not parse (" + e.what() + ")");
        return {};
    }
    if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array() || !j.contains("command") || !j["command"].is_string()) {
        f.problem(manifest + ": rows: expected the merged table of `woven sweep` (command, axes, rows)");
        return {};
    }
    std::size_t done = 0, other = 0;
    for (const auto& r : j["rows"]) {
        const std::string point = r.is_object() ? r.value("point", std::string()) : std::string();
        if (point.empty() || point.find('/') != std::string::npos || point[0] == '.') {
            f.problem(manifest + ": rows: expected point folder names, got '" + point + "'");
            continue;
        }
        if (r.value("status", std::string()) != "done") {
            ++other;
            continue;
        }
        ++done;
        check_folder(dir / point, f);
    }
    if (f.problems.size() != before) return {};
    return "sweep " + j.value("name", std::string()) + " of " + j["command"].get<std::string>() + ", " + std::to_string(done + other) +
           " points: " + std::to_string(done) + " done and verified, " + std::to_string(other) + " not done";
}

/// An experiment's folder: each of the experiments' sets there verifies.
std::string check_experiment(const fs::path& dir, Findings& f)
{
    std::string what;
    for (const char* m : kExperimentManifests) {
        if (!fs::exists(dir / m)) continue;
        const std::string w = check_set(dir, m, f);
        if (!w.empty()) what += (what.empty() ? "" : "; ") + w;
    }
    return what;
}

/// A folder as `woven check` takes it: a sweep, an experiment's figures or one output set.
std::string check_any_folder(const fs::path& dir, Findings& f)
{
    if (fs::exists(dir / "sweep.json")) return check_sweep(dir, f);
    for (const char* m : kManifests)
        if (fs::exists(dir / m)) return check_folder(dir, f);
    for (const char* m : kExperimentManifests)
        if (fs::exists(dir / m)) return check_experiment(dir, f);
    f.problem(dir.string() + ": manifest: no report.json, cusick.json, kes-report.json, sweep.json or an experiment's "
              "cube_results.json, corner_map.json or figure1.json (not a finished woven output folder)");
    return {};
}

/// One set: its manifest `name` in `dir` lists every file with its size and SHA-256.
std::string check_set(const fs::path& dir, const std::string& name, Findings& f)
{
    const std::size_t before = f.problems.size();
    const std::string manifest = (dir / name).string();
    nlohmann::json j;
    try {
        j = io::read_output_json(manifest, io::kMaxManifestBytes, "the manifest a woven command wrote");
    } catch (const InputError& e) {
        f.problem(e.what());
        return {};
    }
    if (!j.is_object()) {
        f.problem(manifest + ": json: expected an object");
        return {};
    }
    // Every command: {"name": {"bytes", "sha256"}}; a list of names (kes-test before issue 36) is
    // still read: each file must be there.
    if (!j.contains("files")) {
        f.problem(manifest + ": files: missing (the list of the set's files)");
    } else if (j["files"].is_object()) {
        for (auto it = j["files"].begin(); it != j["files"].end(); ++it) check_listed(dir, manifest, it.key(), &it.value(), f);
    } else if (j["files"].is_array()) {
        for (const auto& n : j["files"]) {
            if (!n.is_string()) {
                f.problem(manifest + ": files: expected file names");
                continue;
            }
            if (n.get<std::string>() != name) check_listed(dir, manifest, n.get<std::string>(), nullptr, f);
        }
    } else {
        f.problem(manifest + ": files: expected an object or a list");
    }
    // Numbers: the commands write a non-finite number as null and never publish one (but for
    // `folds`, a drape's analysis over a box, null elsewhere); kes-test reports a test that
    // could not measure as null, so its report is not held to this, nor the experiments' tables.
    const bool experiment = std::find(std::begin(kExperimentManifests), std::end(kExperimentManifests), name) != std::end(kExperimentManifests);
    if (name != "kes-report.json" && !experiment) {
        std::vector<std::string> bad;
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!((it.key() == "folds" || it.key() == "start_sha256" || it.key() == "search") && it.value().is_null()))
                non_finite(it.value(), it.key(), bad);  // the documented nulls: no box, no --start, no --search
        for (const auto& b : bad) f.problem(manifest + ": " + b + ": not a finite number");
    }
    if (f.problems.size() != before) return {};
    const std::string command = j.contains("command") && j["command"].is_string() ? j["command"].get<std::string>()
                                : name == "cusick.json"                           ? "cusick"
                                : experiment                                      ? "experiment"
                                                                                  : "drape or fit";
    return "output of " + command + ", " + std::to_string(j.contains("files") ? j["files"].size() : 0) + " files listed in " + name;
}

}  // namespace

std::vector<std::string> check_output_folder(const std::string& dir, std::string* what)
{
    Findings f;
    const std::string w = check_folder(fs::path(dir), f);
    if (what) *what = w;
    return f.problems;
}

std::vector<std::string> check_output_set(const std::string& dir, const std::string& manifest)
{
    Findings f;
    (void)check_set(fs::path(dir), manifest, f);
    return f.problems;
}

CheckResult check_path(const std::string& arg)
{
    Findings f;
    CheckResult r;
    try {
        std::error_code ec;
        const fs::path p(arg);
        if (fs::is_directory(p, ec)) {
            r.what = check_any_folder(p, f);
        } else if (!fs::exists(p, ec)) {
            f.problem(arg + ": file: no such file or folder");
        } else if (p.extension() == ".toml") {
            r.what = check_toml(arg, r.warnings);
        } else if (p.extension() == ".obj") {
            const auto mesh = io::load_obj_mesh(arg);
            r.what = "mesh, " + std::to_string(mesh.vertices.size()) + " vertices, " + std::to_string(mesh.faces.size()) + " triangles";
        } else {
            f.problem(arg + ": file: expected a fabric or scene .toml, an .obj mesh or an output folder");
        }
    } catch (const InputError& e) {
        f.problem(e.what());
    } catch (const std::exception& e) {
        f.problem(arg + ": " + e.what());
    }
    r.problems = std::move(f.problems);
    return r;
}

}  // namespace woven::app
