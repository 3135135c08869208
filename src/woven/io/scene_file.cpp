#include "woven/io/scene_file.hpp"
#include "woven/io/values.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/scene_obstacles.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

namespace fs = std::filesystem;

namespace {

const Range kCoordinate{-kMaxCoordinate_m, kMaxCoordinate_m, false, "m"};  ///< positions
const Range kClothSize{1e-3, 100, false, "m"};
const Range kAngle{-360, 360, false, "deg"};
const Range kCameraCoordinate{-1e4, 1e4, false, "m"};

void check_grid_size(long long nu, long long nv, const std::string& source, const std::string& field)
{
    if (nu < 3 || nv < 3)
        throw InputError(source, field, "expected at least 3 particles each way, got " + std::to_string(nu) + " x " +
                                            std::to_string(nv));
    const long long n = nu * nv;
    if (n > kMaxParticles)
        throw InputError(source, field,
                         std::to_string(nu) + " x " + std::to_string(nv) + " = " + std::to_string(n) +
                             " particles is too large (at most " + std::to_string(kMaxParticles) + ")");
}

void check_sigma(const ClothSpec& c, const std::string& source, const std::string& field)
{
    const double su = c.size_u / (c.nu - 1), sv = c.size_v / (c.nv - 1);
    if (std::abs(su - sv) > 1e-6 * std::max(su, sv))
        throw InputError(source, field,
                         "the spacing differs along u and v (size_u/(nu-1) = " + num_str(su) + " m, size_v/(nv-1) = " +
                             num_str(sv) + " m); the grid must be square-celled");
}

/// Every initial particle must be strictly outside every obstacle.
void check_start(const SceneSpec& s, const std::string& source)
{
    if (s.obstacles.empty()) return;
    const Positions x = s.cloth.initial_positions();
    const std::vector<char> kept = s.cloth.is_cut() ? s.cloth.cut(source).active : std::vector<char>(x.size(), 1);
    for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
        const auto& o = s.obstacles[k];
        const auto box = o.bounds();
        for (std::size_t p = 0; p < x.size(); ++p) {
            if (!kept[p]) continue;  // cut away by cloth.outline: not part of the cloth
            // Outside the bounds (with a margin) a particle cannot touch the obstacle.
            if (!box.empty() && ((x[p].array() < box.lo.array() - 1e-9).any() || (x[p].array() > box.hi.array() + 1e-9).any())
                && o.kind() != "plane")
                continue;
            const double d = o.distance(x[p]);
            if (!(d > 0)) {
                const int i = static_cast<int>(p) % s.cloth.nu, j = static_cast<int>(p) / s.cloth.nu;
                const std::string kind = k < s.obstacle_kinds.size() ? s.obstacle_kinds[k] : o.kind();
                throw InputError(source, "cloth",
                                 "particle (" + std::to_string(i) + ", " + std::to_string(j) + ") at " + vec_str(x[p]) +
                                     " starts inside or touching obstacle[" + std::to_string(k + 1) + "] (" + kind +
                                     "): signed distance " + num_str(d) +
                                     " m; raise cloth.height_m or move the obstacle");
            }
        }
    }
}

/// The checks that depend on the grid (also after --grid): spacing, contact distance, start.
void check_scene(const SceneSpec& s, const std::string& source, const std::string& field)
{
    check_sigma(s.cloth, source, field);
    const double sigma = s.cloth.sigma();
    if (!(sigma >= kMinSigma_m))
        throw InputError(source, field,
                         "the particle spacing " + num_str(sigma) + " m is below " + num_str(kMinSigma_m) +
                             " m; use fewer particles or a larger cloth");
    const double d = s.solver.contact_distance;
    if (!(d <= kMaxContactFraction * sigma))
        throw InputError(s.source_path, "solver.contact_distance_m",
                         "expected at most " + num_str(kMaxContactFraction) + " sigma = " +
                             num_str(kMaxContactFraction * sigma) + " m, got " + num_str(d));
    if (s.cloth.is_cut()) s.cloth.cut(s.source_path);  // the outline fits the grid (InputError naming cloth.outline)
    check_start(s, s.source_path);
}

/// [cloth.outline]: type = "rectangle" | "disc" | "annulus" | "polygon", with centre_m and
/// radius_m (disc, annulus), inner_radius_m (annulus), points_m (polygon: [[x, y], ...]), in m
/// relative to the cloth's centre in its rest plane. The geometry is checked against the grid
/// by check_scene (model::cut_grid).
model::Outline parse_outline(const TomlTable& t)
{
    model::Outline o;
    const std::string type = t.choice("type", std::nullopt, {"rectangle", "disc", "annulus", "polygon"});
    const Range length{0, 100, true, "m"};
    if (type == "disc" || type == "annulus") {
        o.kind = type == "disc" ? model::Outline::Kind::DISC : model::Outline::Kind::ANNULUS;
        o.centre = t.vec<2>("centre_m", kCoordinate, Vec2(0.0, 0.0));
        o.radius = t.number("radius_m", length, std::nullopt);
        if (type == "annulus") o.inner_radius = t.number("inner_radius_m", length, std::nullopt);
    } else if (type == "polygon") {
        o.kind = model::Outline::Kind::POLYGON;
        const toml::node* n = t.node("points_m");
        const toml::array* a = n ? n->as_array() : nullptr;
        if (!a) t.fail("points_m", "expected an array of [x, y] points in m");
        if (a->size() > model::kMaxOutlinePoints)  // before the self-intersection test, O(n^2)
            t.fail("points_m", "expected at most " + std::to_string(model::kMaxOutlinePoints) + " points, got " + std::to_string(a->size()));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const std::string field = t.field("points_m") + "[" + std::to_string(k + 1) + "]";
            const toml::array* xy = a->get(k)->as_array();
            if (!xy || xy->size() != 2) t.fail("points_m", "expected [x, y] at point " + std::to_string(k + 1) + TomlReader::at(*a->get(k)));
            o.points.emplace_back(t.to_number(*xy->get(0), field, kCoordinate), t.to_number(*xy->get(1), field, kCoordinate));
        }
    }
    return o;
}

void parse_cloth(const TomlTable& t, SceneSpec& s)
{
    ClothSpec& c = s.cloth;
    const Vec2 size = t.vec<2>("size_m", kClothSize, Vec2(1.0, 1.0));
    c.size_u = size.x();
    c.size_v = size.y();
    if (const toml::node* g = t.node("grid")) {
        const toml::array* a = g->as_array();
        if (!a || a->size() != 2) t.fail("grid", "expected an array of 2 integers" + TomlReader::at(*g));
        const long long nu = t.to_integer(*a->get(0), t.field("grid"), 0, kMaxParticles);
        const long long nv = t.to_integer(*a->get(1), t.field("grid"), 0, kMaxParticles);
        check_grid_size(nu, nv, s.source_path, t.field("grid"));
        c.nu = static_cast<int>(nu);
        c.nv = static_cast<int>(nv);
    }
    const Vec2 centre = t.vec<2>("centre_m", kCoordinate, Vec2(0.0, 0.0));
    const double height = t.number("height_m", kCoordinate, 0.51);
    c.centre = Vec3(centre.x(), centre.y(), height);
    c.yaw_deg = t.number("rotation_deg", kAngle, 0.0);
    if (const toml::node* p = t.node("pinned")) {
        const toml::array* a = p->as_array();
        if (!a) t.fail("pinned", "expected an array of [i, j] pairs" + TomlReader::at(*p));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const std::string field = t.field("pinned") + "[" + std::to_string(k + 1) + "]";
            const toml::array* ij = a->get(k)->as_array();
            if (!ij || ij->size() != 2)
                throw InputError(s.source_path, field, "expected [i, j]" + TomlReader::at(*a->get(k)));
            const long long i = t.to_integer(*ij->get(0), field, 0, c.nu - 1);
            const long long j = t.to_integer(*ij->get(1), field, 0, c.nv - 1);
            c.pinned.emplace_back(static_cast<int>(i), static_cast<int>(j));
        }
    }
    if (const toml::node* e = t.node("clamped_edges")) {
        const toml::array* a = e->as_array();
        const std::string expected = "expected an array of \"i0\", \"i1\", \"j0\", \"j1\"";
        if (!a) t.fail("clamped_edges", expected + TomlReader::at(*e));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const auto* str = a->get(k)->as_string();
            const std::string v = str ? str->get() : std::string();
            if (v != "i0" && v != "i1" && v != "j0" && v != "j1") t.fail("clamped_edges", expected + TomlReader::at(*a->get(k)));
            c.clamped_edges.push_back(v);
        }
    }
    if (t.has("fabric")) s.fabric = t.string("fabric", std::nullopt);
    if (const auto o = t.table("outline")) c.outline = parse_outline(*o);
}

void parse_solver(const TomlTable& t, sim::SolverOptions& o)
{
    o.kind = t.choice("kind", sim::SolverKind::FAST, sim::kSolverKindNames);
    o.seed = static_cast<std::uint64_t>(
        t.integer("seed", 0, std::numeric_limits<long long>::max(), static_cast<long long>(o.seed)));
    o.max_steps = static_cast<int>(t.integer("max_steps", 0, 1'000'000'000, o.max_steps));
    o.residual_tolerance = t.number("residual_tolerance", Range{0, 1, true, ""}, o.residual_tolerance);
    o.move_tolerance = t.number("move_tolerance_m", Range{0, 1, true, "m"}, o.move_tolerance);
    o.time_step = t.number("time_step_s", Range{0, 10, true, "s"}, o.time_step);
    o.contact_distance = t.number("contact_distance_m", Range{0, 1, true, "m"}, o.contact_distance);
    o.viscosity = t.number("viscosity_per_s", Range{0, 1e3, false, "1/s"}, o.viscosity);
    o.friction = t.number("friction", Range{0, 10, false, ""}, o.friction);
    o.threads = static_cast<int>(t.integer("threads", 0, kMaxThreads, o.threads));
    o.perturbation = t.number("perturbation_m", Range{0, kMaxPerturbation_m, false, "m"}, o.perturbation);
    o.fast.creep_softening = t.number("creep_softening", Range{1, kMaxCreepSoftening, false, ""}, o.fast.creep_softening);
    o.fast.fall_duration = t.number("fall_duration_s", Range{0, kMaxFallDuration_s, false, "s"}, o.fast.fall_duration);
}

void parse_model(const TomlTable& t, model::ModelOptions& o)
{
    const bool work = o.bending_form == model::BendingForm::WORK;  // the model's default unless given
    o.bending_form = t.choice("bending_form", work ? "work" : "secant", {"secant", "work"}) == "work" ? model::BendingForm::WORK
                                                                                                     : model::BendingForm::SECANT;
    o.discretization = t.choice("discretization", o.discretization, model::kDiscretizationNames);
    o.shear_law = t.choice("shear_law", o.shear_law, model::kShearLawNames);
    o.hysteresis = t.choice("hysteresis", o.hysteresis, model::kHysteresisNames);
    o.bias_bending = t.choice("bias_bending", o.bias_bending, model::kBiasBendingNames);
    o.tensile_stiffness = t.number("tensile_stiffness_N_m", Range{0, 1e9, false, "N/m"}, o.tensile_stiffness);
    o.thread_compression = t.number("thread_compression", Range{0, 1, false, ""}, o.thread_compression);
    o.gram_force = t.choice("gram_force", units::GramForce::PAPER, units::kGramForceNames);
    o.gravity = t.number("gravity_m_s2", Range{0, 1000, true, "m/s^2"}, o.gravity);
    o.C0 = t.number("C0_J", Range{0, 1e3, false, "J"}, o.C0);
}

void parse_camera(const TomlTable& t, CameraSpec& c)
{
    c.eye = t.vec<3>("eye_m", kCameraCoordinate, std::nullopt);
    c.target = t.vec<3>("target_m", kCameraCoordinate, std::nullopt);
    if (!((c.eye - c.target).norm() > 1e-6)) t.fail("target_m", "must differ from camera.eye_m");
    c.fov_deg = t.number("fov_deg", Range{0, 179, true, "deg"}, c.fov_deg);
    c.given = true;
}

/// A fabric given as a path (contains '/' or ends in ".toml") resolves against base_dir.
std::string resolve_fabric(const std::string& fabric, const std::string& base_dir)
{
    const bool is_path = fabric.find('/') != std::string::npos ||
                         (fabric.size() > 5 && fabric.compare(fabric.size() - 5, 5, ".toml") == 0);
    if (!is_path || base_dir.empty() || fs::path(fabric).is_absolute()) return fabric;
    return normal_path(fs::path(base_dir) / fabric);
}

SceneSpec read_scene(const TomlReader& reader, const std::string& base_dir, std::vector<std::string>* warnings, bool builtin)
{
    const std::string& source = reader.source();
    if (reader.empty())
        reader.fail("file", "the scene is empty; expected at least a [cloth] table and an [[obstacle]]");
    const TomlTable r = reader.root();

    SceneSpec s;
    s.source_path = source;
    s.name = r.string("name", fs::path(source).stem().string());
    s.description = r.string("description", std::string());
    if (r.has("fabric")) s.fabric = r.string("fabric", std::nullopt);
    if (const auto t = r.table("cloth")) parse_cloth(*t, s);
    s.fabric = resolve_fabric(s.fabric, builtin ? std::string() : base_dir);

    const ObstacleContext ctx{base_dir, builtin};
    for (const TomlTable& t : r.tables("obstacle")) {
        std::string kind;
        s.obstacles.add(build_obstacle(t, ctx, kind));
        s.obstacle_kinds.push_back(kind);
    }
    if (const auto t = r.table("solver")) parse_solver(*t, s.solver);
    if (const auto t = r.table("model")) parse_model(*t, s.model);
    if (const auto t = r.table("camera")) parse_camera(*t, s.camera);
    check_scene(s, source, "cloth.size_m, cloth.grid");
    if (warnings) {
        for (auto& w : reader.unknown_keys()) warnings->push_back(std::move(w));
        if (s.obstacles.empty()) warnings->push_back(source + ": obstacle: no obstacles; the cloth falls freely");
    }
    return s;
}

SceneSpec parse_scene_impl(std::string_view text, const std::string& source, const std::string& base_dir,
                           std::vector<std::string>* warnings, bool builtin)
{
    return read_scene(TomlReader(text, source), base_dir, warnings, builtin);
}

}  // namespace

SceneSpec scene_from_values(const nlohmann::json& values, const std::string& source, const std::string& base_dir,
                            std::vector<std::string>* warnings)
{
    return read_scene(TomlReader(table_from_values(values, source), source), base_dir, warnings, false);
}

std::unique_ptr<geometry::Obstacle> obstacle_from_values(const nlohmann::json& values, const std::string& source,
                                                         const std::string& base_dir, std::string* kind,
                                                         std::vector<std::string>* warnings)
{
    const TomlReader reader(table_from_values(values, source), source);
    std::string k;
    auto obstacle = build_obstacle(reader.root(), ObstacleContext{base_dir, false}, k);
    if (warnings)
        for (auto& w : reader.unknown_keys()) warnings->push_back(std::move(w));
    if (kind) *kind = k;
    return obstacle;
}

Positions ClothSpec::initial_positions() const { return model::flat_grid(grid(), centre, yaw_deg * units::kDegToRad); }

std::vector<int> SceneSpec::pinned_indices() const
{
    std::set<int> out;
    const int nu = cloth.nu, nv = cloth.nv;
    for (const auto& [i, j] : cloth.pinned)
        if (i >= 0 && i < nu && j >= 0 && j < nv) out.insert(i + nu * j);
    for (const auto& e : cloth.clamped_edges) {
        if (e == "i0" || e == "i1")
            for (int j = 0; j < nv; ++j) out.insert((e == "i0" ? 0 : nu - 1) + nu * j);
        else if (e == "j0" || e == "j1")
            for (int i = 0; i < nu; ++i) out.insert(i + nu * (e == "j0" ? 0 : nv - 1));
    }
    return {out.begin(), out.end()};
}

SceneSpec parse_scene(std::string_view toml_text, const std::string& source, const std::string& base_dir,
                      std::vector<std::string>* warnings)
{
    return parse_scene_impl(toml_text, source, base_dir, warnings, false);
}

SceneSpec load_scene(const std::string& path, std::vector<std::string>* warnings)
{
    const std::string text = read_input_file(path, kMaxTomlBytes, {"scene file", "a scene .toml file"});
    std::string base = fs::path(path).parent_path().string();
    if (base.empty()) base = ".";
    return parse_scene_impl(text, path, base, warnings, false);
}

std::vector<std::string> builtin_scene_names()
{
    std::vector<std::string> names;
    for (const auto& f : data::embedded_files()) {
        const fs::path p(f.path);
        if (p.parent_path() == "scenes" && p.extension() == ".toml") names.push_back(p.stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

SceneSpec find_scene(const std::string& name_or_path, std::vector<std::string>* warnings)
{
    std::error_code ec;
    // A file (or a path that names something that is not one: a FIFO, a device, a directory,
    // refused by load_scene) before the built-in names.
    if (fs::is_regular_file(name_or_path, ec) ||
        (fs::exists(name_or_path, ec) && (name_or_path.find('/') != std::string::npos || name_or_path.ends_with(".toml"))))
        return load_scene(name_or_path, warnings);
    std::string key = name_or_path;
    if (key.rfind("scenes/", 0) != 0) key = "scenes/" + key;
    if (!key.ends_with(".toml")) key += ".toml";
    if (auto d = embedded_file(key)) return parse_scene_impl(*d, key, "scenes", warnings, true);
    std::string names;
    for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError(name_or_path, "scene", "no such scene file or built-in scene (built-in: " + names + ")");
}

void apply_overrides(SceneSpec& scene, const SceneOverrides& o, const std::string& source, const std::string& grid_field)
{
    ClothSpec& c = scene.cloth;
    if (o.grid) {
        const int n = *o.grid;
        check_grid_size(n, n, source, grid_field);
        const int old_nu = c.nu, old_nv = c.nv;
        if (c.size_u >= c.size_v) {
            const double sigma = c.size_u / (n - 1);
            c.nu = n;
            c.nv = std::max(3, static_cast<int>(std::lround(c.size_v / sigma)) + 1);
            c.size_v = (c.nv - 1) * sigma;
        } else {
            const double sigma = c.size_v / (n - 1);
            c.nv = n;
            c.nu = std::max(3, static_cast<int>(std::lround(c.size_u / sigma)) + 1);
            c.size_u = (c.nu - 1) * sigma;
        }
        check_grid_size(c.nu, c.nv, source, grid_field);
        for (auto& [i, j] : c.pinned) {
            i = static_cast<int>(std::lround(double(i) * (c.nu - 1) / (old_nu - 1)));
            j = static_cast<int>(std::lround(double(j) * (c.nv - 1) / (old_nv - 1)));
        }
        std::sort(c.pinned.begin(), c.pinned.end());
        c.pinned.erase(std::unique(c.pinned.begin(), c.pinned.end()), c.pinned.end());
    }
    if (o.fabric) scene.fabric = *o.fabric;
    if (o.solver) scene.solver.kind = *o.solver;
    if (o.seed) scene.solver.seed = *o.seed;
    if (o.max_steps) {
        if (*o.max_steps < 0) throw InputError(source, "--max-steps", "expected an integer >= 0");
        scene.solver.max_steps = *o.max_steps;
    }
    if (o.threads) {
        if (*o.threads < 0) throw InputError(source, "--threads", "expected an integer >= 0");
        scene.solver.threads = *o.threads;
    }
    if (o.grid) check_scene(scene, source, grid_field);
}

}  // namespace woven::io
