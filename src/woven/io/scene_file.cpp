#include "woven/io/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include <unistd.h>

#include <toml++/toml.h>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/geometry/mesh_obstacle.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/mesh_file.hpp"

namespace woven::io {

namespace fs = std::filesystem;

namespace {

/// Rough memory per particle of the fast solver (model stencils, sparse Hessian and its
/// Cholesky factor, solver vectors): a guard against grids the machine cannot hold.
constexpr double kBytesPerParticle = 4096;

std::string num_str(double v)
{
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

std::string vec_str(const Vec3& v) { return "(" + num_str(v.x()) + ", " + num_str(v.y()) + ", " + num_str(v.z()) + ")"; }

/// Typed access to the TOML tree with messages "<source>: <field>: <expected>"; collects
/// warnings for unknown keys.
class Reader {
public:
    Reader(std::string source, std::vector<std::string>* warnings) : source_(std::move(source)), warnings_(warnings) { }

    const std::string& source() const { return source_; }

    [[noreturn]] void fail(const std::string& field, const std::string& expected) const
    {
        throw InputError(source_, field, expected);
    }

    /// "(line N)" for a node with a known position.
    static std::string at(const toml::node& n)
    {
        const auto& b = n.source().begin;
        return b.line > 0 ? " (line " + std::to_string(b.line) + ")" : std::string();
    }

    void warn_unknown(const toml::table& t, const std::string& prefix, std::initializer_list<std::string_view> known) const
    {
        for (auto&& [k, v] : t) {
            if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
            if (warnings_)
                warnings_->push_back(source_ + ": " + prefix + std::string(k.str()) + ": unknown key, ignored" + at(v));
        }
    }

    /// A table (or absent: nullptr); anything else is an error.
    const toml::table* table(const toml::table& t, std::string_view key, const std::string& field) const
    {
        const toml::node* n = t.get(key);
        if (!n) return nullptr;
        if (!n->is_table()) fail(field, "expected a table" + at(*n));
        return n->as_table();
    }

    double number(const toml::node& n, const std::string& field) const
    {
        double v;
        if (const auto* f = n.as_floating_point())
            v = f->get();
        else if (const auto* i = n.as_integer())
            v = static_cast<double>(i->get());
        else
            fail(field, "expected a number" + at(n));
        if (!std::isfinite(v)) fail(field, "expected a finite number, got " + num_str(v) + at(n));
        return v;
    }

    std::optional<double> opt_number(const toml::table& t, std::string_view key, const std::string& field) const
    {
        const toml::node* n = t.get(key);
        if (!n) return std::nullopt;
        return number(*n, field);
    }

    double number(const toml::table& t, std::string_view key, const std::string& field, std::optional<double> def) const
    {
        if (auto v = opt_number(t, key, field)) return *v;
        if (!def) fail(field, "missing (required number)");
        return *def;
    }

    double positive(const toml::table& t, std::string_view key, const std::string& field, std::optional<double> def) const
    {
        const double v = number(t, key, field, def);
        if (!(v > 0)) fail(field, "expected a positive number, got " + num_str(v));
        return v;
    }

    double non_negative(const toml::table& t, std::string_view key, const std::string& field, std::optional<double> def) const
    {
        const double v = number(t, key, field, def);
        if (!(v >= 0)) fail(field, "expected a number >= 0, got " + num_str(v));
        return v;
    }

    long long integer(const toml::node& n, const std::string& field) const
    {
        if (const auto* i = n.as_integer()) return i->get();
        if (const auto* f = n.as_floating_point()) {
            const double v = f->get();
            if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9e15) return static_cast<long long>(v);
        }
        fail(field, "expected an integer" + at(n));
    }

    long long integer(const toml::table& t, std::string_view key, const std::string& field, std::optional<long long> def,
                      long long lo, long long hi) const
    {
        const toml::node* n = t.get(key);
        if (!n) {
            if (!def) fail(field, "missing (required integer)");
            return *def;
        }
        const long long v = integer(*n, field);
        if (v < lo || v > hi)
            fail(field, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                            std::to_string(v));
        return v;
    }

    std::string string(const toml::table& t, std::string_view key, const std::string& field,
                       std::optional<std::string> def) const
    {
        const toml::node* n = t.get(key);
        if (!n) {
            if (!def) fail(field, "missing (required string)");
            return *def;
        }
        if (const auto* s = n->as_string()) return s->get();
        fail(field, "expected a string" + at(*n));
    }

    /// A string from a fixed set of choices.
    std::string choice(const toml::table& t, std::string_view key, const std::string& field, const std::string& def,
                       std::initializer_list<std::string_view> choices) const
    {
        const std::string v = string(t, key, field, def);
        if (std::find(choices.begin(), choices.end(), v) != choices.end()) return v;
        std::string list;
        for (auto c : choices) list += (list.empty() ? "" : ", ") + std::string("\"") + std::string(c) + "\"";
        fail(field, "expected one of " + list + ", got \"" + v + "\"");
    }

    /// A fixed-length array of numbers.
    template <int N>
    Eigen::Matrix<double, N, 1> vec(const toml::table& t, std::string_view key, const std::string& field,
                                    std::optional<Eigen::Matrix<double, N, 1>> def) const
    {
        const toml::node* n = t.get(key);
        if (!n) {
            if (!def) fail(field, "missing (required array of " + std::to_string(N) + " numbers)");
            return *def;
        }
        const toml::array* a = n->as_array();
        if (!a || static_cast<int>(a->size()) != N)
            fail(field, "expected an array of " + std::to_string(N) + " numbers" + at(*n));
        Eigen::Matrix<double, N, 1> v;
        for (int k = 0; k < N; ++k) v[k] = number(*a->get(k), field);
        return v;
    }

private:
    std::string source_;
    std::vector<std::string>* warnings_;
};

/// Lexically normalised generic path ("a/b/../c" -> "a/c").
std::string normal_path(const fs::path& p) { return p.lexically_normal().generic_string(); }

/// Embedded file at `path`, if any.
std::optional<std::string_view> embedded(const std::string& path)
{
    for (const auto& f : data::embedded_files())
        if (f.path == path) return f.data;
    return std::nullopt;
}

/// The embedded asset a mesh path in a scene may stand for: the path itself, the path relative
/// to the scene's folder, or its tail from the last "assets/" component.
std::optional<std::pair<std::string, std::string_view>> embedded_mesh(const std::string& file, const std::string& base_dir)
{
    std::vector<std::string> candidates;
    if (!base_dir.empty()) candidates.push_back(normal_path(fs::path(base_dir) / file));
    candidates.push_back(normal_path(fs::path(file)));
    for (const auto& c : std::vector<std::string>(candidates)) {
        const auto k = c.rfind("assets/");
        if (k != std::string::npos && (k == 0 || c[k - 1] == '/')) candidates.push_back(c.substr(k));
    }
    for (const auto& c : candidates)
        if (auto d = embedded(c)) return std::make_pair(c, *d);
    return std::nullopt;
}

/// Rethrows a primitive's constructor error with the scene's source and the obstacle's field.
template <class F>
auto build(const Reader& r, const std::string& prefix, F&& make)
{
    try {
        return make();
    } catch (const InputError& e) {
        if (!e.source().empty()) throw;
        const std::string what = e.what();
        std::string expected = what;
        if (!e.field().empty() && what.rfind(e.field() + ": ", 0) == 0) expected = what.substr(e.field().size() + 2);
        r.fail(prefix + (e.field().empty() ? std::string("") : "." + e.field()), expected);
    }
}

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
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) {
        const double memory = double(pages) * double(page);
        if (double(n) * kBytesPerParticle > memory)
            throw InputError(source, field,
                             std::to_string(n) + " particles need about " + num_str(n * kBytesPerParticle / 1e9) +
                                 " GB, more than this machine's " + num_str(memory / 1e9) + " GB");
    }
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
    for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
        const auto& o = s.obstacles[k];
        const auto box = o.bounds();
        for (std::size_t p = 0; p < x.size(); ++p) {
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

void parse_cloth(const Reader& r, const toml::table& t, SceneSpec& s)
{
    r.warn_unknown(t, "cloth.", {"size_m", "grid", "centre_m", "height_m", "rotation_deg", "pinned", "clamped_edges", "fabric"});
    ClothSpec& c = s.cloth;
    const Vec2 size = r.vec<2>(t, "size_m", "cloth.size_m", Vec2(1.0, 1.0));
    if (!(size.x() > 0 && size.y() > 0))
        r.fail("cloth.size_m", "expected positive sizes, got [" + num_str(size.x()) + ", " + num_str(size.y()) + "]");
    c.size_u = size.x();
    c.size_v = size.y();
    if (const toml::node* g = t.get("grid")) {
        const toml::array* a = g->as_array();
        if (!a || a->size() != 2) r.fail("cloth.grid", "expected an array of 2 integers" + Reader::at(*g));
        const long long nu = r.integer(*a->get(0), "cloth.grid"), nv = r.integer(*a->get(1), "cloth.grid");
        check_grid_size(nu, nv, r.source(), "cloth.grid");
        c.nu = static_cast<int>(nu);
        c.nv = static_cast<int>(nv);
    }
    check_sigma(c, r.source(), "cloth.size_m, cloth.grid");
    const Vec2 centre = r.vec<2>(t, "centre_m", "cloth.centre_m", Vec2(0.0, 0.0));
    const double height = r.number(t, "height_m", "cloth.height_m", 0.51);
    c.centre = Vec3(centre.x(), centre.y(), height);
    c.yaw_deg = r.number(t, "rotation_deg", "cloth.rotation_deg", 0.0);
    if (const toml::node* p = t.get("pinned")) {
        const toml::array* a = p->as_array();
        if (!a) r.fail("cloth.pinned", "expected an array of [i, j] pairs" + Reader::at(*p));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const std::string field = "cloth.pinned[" + std::to_string(k + 1) + "]";
            const toml::array* ij = a->get(k)->as_array();
            if (!ij || ij->size() != 2) r.fail(field, "expected [i, j]" + Reader::at(*a->get(k)));
            const long long i = r.integer(*ij->get(0), field), j = r.integer(*ij->get(1), field);
            if (i < 0 || i >= c.nu || j < 0 || j >= c.nv)
                r.fail(field, "particle (" + std::to_string(i) + ", " + std::to_string(j) + ") out of range: i in [0, " +
                                  std::to_string(c.nu - 1) + "], j in [0, " + std::to_string(c.nv - 1) + "]");
            c.pinned.emplace_back(static_cast<int>(i), static_cast<int>(j));
        }
    }
    if (const toml::node* e = t.get("clamped_edges")) {
        const toml::array* a = e->as_array();
        if (!a) r.fail("cloth.clamped_edges", "expected an array of \"i0\", \"i1\", \"j0\", \"j1\"" + Reader::at(*e));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const auto* str = a->get(k)->as_string();
            const std::string v = str ? str->get() : std::string();
            if (v != "i0" && v != "i1" && v != "j0" && v != "j1")
                r.fail("cloth.clamped_edges", "expected \"i0\", \"i1\", \"j0\" or \"j1\"" + Reader::at(*a->get(k)));
            c.clamped_edges.push_back(v);
        }
    }
    if (t.contains("fabric")) s.fabric = r.string(t, "fabric", "cloth.fabric", std::nullopt);
}

std::unique_ptr<geometry::Obstacle> parse_obstacle(const Reader& r, const toml::table& t, const std::string& prefix,
                                                   const std::string& base_dir, bool builtin, std::string& kind)
{
    using namespace geometry;
    kind = r.string(t, "type", prefix + ".type", std::nullopt);
    const double deg = units::kDegToRad;
    if (kind == "plane") {
        r.warn_unknown(t, prefix + ".", {"type", "point_m", "normal", "render_size_m"});
        const Vec3 point = r.vec<3>(t, "point_m", prefix + ".point_m", Vec3(0, 0, 0));
        const Vec3 normal = r.vec<3>(t, "normal", prefix + ".normal", Vec3(0, 0, 1));
        if (!(normal.norm() > 0)) r.fail(prefix + ".normal", "expected a non-zero vector");
        const double size = r.positive(t, "render_size_m", prefix + ".render_size_m", 6.0);
        return build(r, prefix, [&] { return std::make_unique<Plane>(point, normal, size); });
    }
    if (kind == "box") {
        r.warn_unknown(t, prefix + ".", {"type", "centre_m", "size_m", "rotation_deg"});
        const Vec3 centre = r.vec<3>(t, "centre_m", prefix + ".centre_m", std::nullopt);
        const Vec3 size = r.vec<3>(t, "size_m", prefix + ".size_m", std::nullopt);
        if (!(size.array() > 0).all()) r.fail(prefix + ".size_m", "expected positive sizes, got " + vec_str(size));
        const double yaw = r.number(t, "rotation_deg", prefix + ".rotation_deg", 0.0) * deg;
        return build(r, prefix, [&] { return std::make_unique<Box>(centre, 0.5 * size, yaw); });
    }
    if (kind == "sphere") {
        r.warn_unknown(t, prefix + ".", {"type", "centre_m", "radius_m"});
        const Vec3 centre = r.vec<3>(t, "centre_m", prefix + ".centre_m", std::nullopt);
        const double radius = r.positive(t, "radius_m", prefix + ".radius_m", std::nullopt);
        return build(r, prefix, [&] { return std::make_unique<Sphere>(centre, radius); });
    }
    if (kind == "cylinder") {
        r.warn_unknown(t, prefix + ".", {"type", "base_m", "radius_m", "height_m", "axis"});
        const Vec3 base = r.vec<3>(t, "base_m", prefix + ".base_m", std::nullopt);
        const double radius = r.positive(t, "radius_m", prefix + ".radius_m", std::nullopt);
        const double height = r.positive(t, "height_m", prefix + ".height_m", std::nullopt);
        const Vec3 axis = r.vec<3>(t, "axis", prefix + ".axis", Vec3(0, 0, 1));
        if (!(axis.norm() > 0)) r.fail(prefix + ".axis", "expected a non-zero vector");
        return build(r, prefix, [&] { return std::make_unique<Cylinder>(base, radius, height, axis); });
    }
    if (kind == "disc") {
        r.warn_unknown(t, prefix + ".", {"type", "centre_m", "radius_m", "thickness_m"});
        const Vec3 top = r.vec<3>(t, "centre_m", prefix + ".centre_m", std::nullopt);
        const double radius = r.positive(t, "radius_m", prefix + ".radius_m", std::nullopt);
        const double thickness = r.positive(t, "thickness_m", prefix + ".thickness_m", 0.003);
        return build(r, prefix, [&] {
            return std::make_unique<Cylinder>(top - Vec3(0, 0, thickness), radius, thickness, Vec3::UnitZ());
        });
    }
    if (kind == "mesh") {
        r.warn_unknown(t, prefix + ".", {"type", "file", "scale", "rotation_deg", "translate_m"});
        const std::string file = r.string(t, "file", prefix + ".file", std::nullopt);
        const double scale = r.positive(t, "scale", prefix + ".scale", 1.0);
        const Vec3 rotation = r.vec<3>(t, "rotation_deg", prefix + ".rotation_deg", Vec3(0, 0, 0));
        const Vec3 translate = r.vec<3>(t, "translate_m", prefix + ".translate_m", Vec3(0, 0, 0));
        const fs::path path = fs::path(file).is_absolute() || base_dir.empty() ? fs::path(file) : fs::path(base_dir) / file;
        TriangleMesh mesh;
        std::error_code ec;
        const auto asset = embedded_mesh(file, base_dir);
        try {
            if (builtin && asset)
                mesh = parse_obj_mesh(asset->second, asset->first);
            else if (fs::is_regular_file(path, ec))
                mesh = load_obj_mesh(path.string());
            else if (asset)
                mesh = parse_obj_mesh(asset->second, asset->first);
            else
                r.fail(prefix + ".file", "no such mesh file: " + path.string());
        } catch (const InputError& e) {
            if (e.source() == r.source()) throw;
            r.fail(prefix + ".file", e.what());  // "<scene>: obstacle[k].file: <mesh>: faces: ..."
        }
        mesh = transform(mesh, scale, rotation, translate);
        return build(r, prefix, [&] { return std::make_unique<MeshObstacle>(std::move(mesh)); });
    }
    r.fail(prefix + ".type",
           "unknown obstacle type \"" + kind + "\" (expected plane, box, sphere, cylinder, disc or mesh)");
}

void parse_solver(const Reader& r, const toml::table& t, sim::SolverOptions& o)
{
    r.warn_unknown(t, "solver.", {"kind", "seed", "max_steps", "residual_tolerance", "move_tolerance_m", "time_step_s",
                                  "contact_distance_m", "viscosity_per_s", "friction", "threads"});
    o.kind = r.choice(t, "kind", "solver.kind", "fast", {"fast", "paper"}) == "paper" ? sim::SolverKind::PAPER
                                                                                      : sim::SolverKind::FAST;
    o.seed = static_cast<std::uint64_t>(r.integer(t, "seed", "solver.seed", static_cast<long long>(o.seed), 0,
                                                  std::numeric_limits<long long>::max()));
    o.max_steps = static_cast<int>(r.integer(t, "max_steps", "solver.max_steps", o.max_steps, 0, 1'000'000'000));
    o.residual_tolerance = r.positive(t, "residual_tolerance", "solver.residual_tolerance", o.residual_tolerance);
    o.move_tolerance = r.positive(t, "move_tolerance_m", "solver.move_tolerance_m", o.move_tolerance);
    o.time_step = r.positive(t, "time_step_s", "solver.time_step_s", o.time_step);
    o.contact_distance = r.positive(t, "contact_distance_m", "solver.contact_distance_m", o.contact_distance);
    o.viscosity = r.non_negative(t, "viscosity_per_s", "solver.viscosity_per_s", o.viscosity);
    o.friction = r.non_negative(t, "friction", "solver.friction", o.friction);
    o.threads = static_cast<int>(r.integer(t, "threads", "solver.threads", o.threads, 0, 4096));
}

void parse_model(const Reader& r, const toml::table& t, model::ModelOptions& o)
{
    r.warn_unknown(t, "model.", {"bending_form", "gram_force", "gravity_m_s2", "C0_J"});
    o.bending_form = r.choice(t, "bending_form", "model.bending_form", "secant", {"secant", "work"}) == "work"
                         ? model::BendingForm::WORK
                         : model::BendingForm::SECANT;
    o.gram_force = r.choice(t, "gram_force", "model.gram_force", "paper", {"paper", "standard"}) == "standard"
                       ? units::GramForce::STANDARD
                       : units::GramForce::PAPER;
    o.gravity = r.positive(t, "gravity_m_s2", "model.gravity_m_s2", o.gravity);
    o.C0 = r.non_negative(t, "C0_J", "model.C0_J", o.C0);
}

void parse_camera(const Reader& r, const toml::table& t, CameraSpec& c)
{
    r.warn_unknown(t, "camera.", {"eye_m", "target_m", "fov_deg"});
    c.eye = r.vec<3>(t, "eye_m", "camera.eye_m", std::nullopt);
    c.target = r.vec<3>(t, "target_m", "camera.target_m", std::nullopt);
    if ((c.eye - c.target).norm() <= 0) r.fail("camera.target_m", "must differ from camera.eye_m");
    c.fov_deg = r.number(t, "fov_deg", "camera.fov_deg", c.fov_deg);
    if (!(c.fov_deg > 0 && c.fov_deg < 180)) r.fail("camera.fov_deg", "expected a number in (0, 180), got " + num_str(c.fov_deg));
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

SceneSpec parse_scene_impl(std::string_view text, const std::string& source, const std::string& base_dir,
                           std::vector<std::string>* warnings, bool builtin)
{
    toml::table root;
    try {
        root = toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        throw InputError(source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) +
                         ": TOML syntax: " + std::string(e.description()));
    }
    const Reader r(source, warnings);
    r.warn_unknown(root, "", {"name", "description", "fabric", "cloth", "obstacle", "solver", "model", "camera"});

    SceneSpec s;
    s.source_path = source;
    s.name = r.string(root, "name", "name", fs::path(source).stem().string());
    s.description = r.string(root, "description", "description", std::string());
    if (root.contains("fabric")) s.fabric = r.string(root, "fabric", "fabric", std::nullopt);
    if (const auto* t = r.table(root, "cloth", "cloth")) parse_cloth(r, *t, s);
    s.fabric = resolve_fabric(s.fabric, builtin ? std::string() : base_dir);

    if (const toml::node* obs = root.get("obstacle")) {
        const toml::array* a = obs->as_array();
        if (!a) r.fail("obstacle", "expected an array of tables ([[obstacle]])" + Reader::at(*obs));
        for (std::size_t k = 0; k < a->size(); ++k) {
            const std::string prefix = "obstacle[" + std::to_string(k + 1) + "]";
            const toml::table* t = a->get(k)->as_table();
            if (!t) r.fail(prefix, "expected a table" + Reader::at(*a->get(k)));
            std::string kind;
            s.obstacles.add(parse_obstacle(r, *t, prefix, base_dir, builtin, kind));
            s.obstacle_kinds.push_back(kind);
        }
    }
    if (const auto* t = r.table(root, "solver", "solver")) parse_solver(r, *t, s.solver);
    if (const auto* t = r.table(root, "model", "model")) parse_model(r, *t, s.model);
    if (const auto* t = r.table(root, "camera", "camera")) parse_camera(r, *t, s.camera);
    check_start(s, source);
    return s;
}

}  // namespace

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
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(path, "file", "no such scene file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "file", "cannot read the scene file");
    std::ostringstream text;
    text << in.rdbuf();
    std::string base = fs::path(path).parent_path().string();
    if (base.empty()) base = ".";
    return parse_scene_impl(text.str(), path, base, warnings, false);
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
    if (fs::is_regular_file(name_or_path, ec)) return load_scene(name_or_path, warnings);
    std::string key = name_or_path;
    if (key.rfind("scenes/", 0) != 0) key = "scenes/" + key;
    if (!key.ends_with(".toml")) key += ".toml";
    if (auto d = embedded(key)) return parse_scene_impl(*d, key, "scenes", warnings, true);
    std::string names;
    for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError(name_or_path, "scene", "no such scene file or built-in scene (built-in: " + names + ")");
}

void apply_overrides(SceneSpec& scene, const SceneOverrides& o, const std::string& source)
{
    ClothSpec& c = scene.cloth;
    if (o.grid) {
        const int n = *o.grid;
        check_grid_size(n, n, source, "--grid");
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
        check_grid_size(c.nu, c.nv, source, "--grid");
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
    if (o.grid) check_start(scene, scene.source_path);
}

}  // namespace woven::io
