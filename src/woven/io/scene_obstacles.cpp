#include "woven/io/scene_obstacles.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <iterator>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/geometry/mesh_obstacle.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::io {

namespace fs = std::filesystem;

std::string normal_path(const fs::path& p) { return p.lexically_normal().generic_string(); }

std::optional<std::string_view> embedded_file(const std::string& path)
{
    for (const auto& f : data::embedded_files())
        if (f.path == path) return f.data;
    return std::nullopt;
}

namespace {

// Plausible bounds of an obstacle's numbers (docs/SCENE-FORMAT.md "Bounds").
const Range kObstacleCoordinate{-kMaxCoordinate_m, kMaxCoordinate_m, false, "m"};  ///< positions
const Range kLength{kMinLength_m, kMaxLength_m, false, "m"};                      ///< sizes, radii, thicknesses
const Range kObstacleAngle{-360, 360, false, "deg"};
const Range kDirection{-1e6, 1e6, false, ""};  ///< normals and axes (normalised by the obstacle)
const Range kMeshScale{1e-6, 1e6, false, ""};

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
        if (auto d = embedded_file(c)) return std::make_pair(c, *d);
    return std::nullopt;
}

/// Rethrows a primitive's constructor error with the scene's source and the obstacle's field.
template <class F>
std::unique_ptr<geometry::Obstacle> build(const TomlTable& t, F&& make)
{
    try {
        return make();
    } catch (const InputError& e) {
        if (!e.source().empty()) throw;
        const std::string what = e.what();
        std::string expected = what;
        if (!e.field().empty() && what.rfind(e.field() + ": ", 0) == 0) expected = what.substr(e.field().size() + 2);
        t.fail_self(e.field().empty() ? expected : e.field() + ": " + expected);
    }
}

Vec3 direction(const TomlTable& t, std::string_view key, const Vec3& def)
{
    const Vec3 v = t.vec<3>(key, kDirection, def);
    if (!(v.norm() > 1e-9)) t.fail(key, "expected a non-zero vector, got " + vec_str(v));
    return v;
}

using ObstaclePtr = std::unique_ptr<geometry::Obstacle>;

ObstaclePtr build_plane(const TomlTable& t, const ObstacleContext&)
{
    const Vec3 point = t.vec<3>("point_m", kObstacleCoordinate, Vec3(0, 0, 0));
    const Vec3 normal = direction(t, "normal", Vec3(0, 0, 1));
    const double size = t.number("render_size_m", Range{kMinLength_m, 1e4, false, "m"}, 6.0);
    return build(t, [&] { return std::make_unique<geometry::Plane>(point, normal, size); });
}

ObstaclePtr build_box(const TomlTable& t, const ObstacleContext&)
{
    const Vec3 centre = t.vec<3>("centre_m", kObstacleCoordinate, std::nullopt);
    const Vec3 size = t.vec<3>("size_m", kLength, std::nullopt);
    const double yaw = t.number("rotation_deg", kObstacleAngle, 0.0) * units::kDegToRad;
    return build(t, [&] { return std::make_unique<geometry::Box>(centre, 0.5 * size, yaw); });
}

ObstaclePtr build_sphere(const TomlTable& t, const ObstacleContext&)
{
    const Vec3 centre = t.vec<3>("centre_m", kObstacleCoordinate, std::nullopt);
    const double radius = t.number("radius_m", kLength, std::nullopt);
    return build(t, [&] { return std::make_unique<geometry::Sphere>(centre, radius); });
}

ObstaclePtr build_cylinder(const TomlTable& t, const ObstacleContext&)
{
    const Vec3 base = t.vec<3>("base_m", kObstacleCoordinate, std::nullopt);
    const double radius = t.number("radius_m", kLength, std::nullopt);
    const double height = t.number("height_m", kLength, std::nullopt);
    const Vec3 axis = direction(t, "axis", Vec3(0, 0, 1));
    return build(t, [&] { return std::make_unique<geometry::Cylinder>(base, radius, height, axis); });
}

ObstaclePtr build_disc(const TomlTable& t, const ObstacleContext&)
{
    const Vec3 top = t.vec<3>("centre_m", kObstacleCoordinate, std::nullopt);
    const double radius = t.number("radius_m", kLength, std::nullopt);
    const double thickness = t.number("thickness_m", kLength, 0.003);
    return build(t, [&] {
        return std::make_unique<geometry::Cylinder>(top - Vec3(0, 0, thickness), radius, thickness, Vec3::UnitZ());
    });
}

ObstaclePtr finish_mesh(const TomlTable& t, geometry::TriangleMesh mesh, double scale, const Vec3& rotation, const Vec3& translate);

/// A mesh written in the table (from Python, woven.Obstacle.mesh): `vertices_m` [[x, y, z], ...]
/// and `faces` [[a, b, c], ...], 0-based vertex indices; rows are named from 0 as numpy names them
/// (`vertices_m[0]`), at most kMaxInlineMeshRows of each.
geometry::TriangleMesh inline_mesh(const TomlTable& t)
{
    const auto rows = [&](std::string_view key, const std::string& what) -> const toml::array& {
        const toml::node* n = t.node(key);
        const toml::array* a = n ? n->as_array() : nullptr;
        if (!a || a->empty()) t.fail(key, "expected " + what);
        if (static_cast<long long>(a->size()) > kMaxInlineMeshRows)
            t.fail(key,
                   "expected at most " + std::to_string(kMaxInlineMeshRows)
                       + " rows (about 1 KB each given as values; a larger mesh from a file: type = \"mesh\", file = ...), got "
                       + std::to_string(a->size()));
        return *a;
    };
    const toml::array& v = rows("vertices_m", "a non-empty array of [x, y, z] vertices in m");
    const toml::array& f = rows("faces", "a non-empty array of [a, b, c] triangles (0-based indices into vertices_m)");
    geometry::TriangleMesh mesh;
    mesh.vertices.reserve(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) {
        const std::string field = t.field("vertices_m") + "[" + std::to_string(k) + "]";
        const toml::array* xyz = v.get(k)->as_array();
        if (!xyz || xyz->size() != 3) t.fail_at(field, "expected [x, y, z] in m" + TomlReader::at(*v.get(k)));
        mesh.vertices.emplace_back(t.to_number(*xyz->get(0), field, kObstacleCoordinate), t.to_number(*xyz->get(1), field, kObstacleCoordinate),
                                   t.to_number(*xyz->get(2), field, kObstacleCoordinate));
    }
    const long long last = static_cast<long long>(v.size()) - 1;
    mesh.faces.reserve(f.size());
    for (std::size_t k = 0; k < f.size(); ++k) {
        const std::string field = t.field("faces") + "[" + std::to_string(k) + "]";
        const toml::array* abc = f.get(k)->as_array();
        if (!abc || abc->size() != 3) t.fail_at(field, "expected [a, b, c], 0-based vertex indices" + TomlReader::at(*f.get(k)));
        std::array<int, 3> face{};
        for (int c = 0; c < 3; ++c) face[c] = static_cast<int>(t.to_integer(*abc->get(c), field, 0, last));
        if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2]) t.fail_at(field, "expected three different vertices");
        mesh.faces.emplace_back(face[0], face[1], face[2]);
    }
    return mesh;
}

ObstaclePtr build_mesh(const TomlTable& t, const ObstacleContext& ctx)
{
    const bool given = t.has("vertices_m") || t.has("faces");
    if (given && t.has("file")) t.fail_self("expected either file or vertices_m and faces, not both");
    const std::string file = given ? std::string() : t.string("file", std::nullopt);
    const double scale = t.number("scale", kMeshScale, 1.0);
    const Vec3 rotation = t.vec<3>("rotation_deg", kObstacleAngle, Vec3(0, 0, 0));
    const Vec3 translate = t.vec<3>("translate_m", kObstacleCoordinate, Vec3(0, 0, 0));
    if (given) return finish_mesh(t, inline_mesh(t), scale, rotation, translate);
    const fs::path path = fs::path(file).is_absolute() || ctx.base_dir.empty() ? fs::path(file) : fs::path(ctx.base_dir) / file;
    geometry::TriangleMesh mesh;
    std::error_code ec;
    const auto asset = embedded_mesh(file, ctx.base_dir);
    try {
        if (ctx.builtin && asset)
            mesh = parse_obj_mesh(asset->second, asset->first);
        else if (fs::is_regular_file(path, ec) || (!asset && fs::exists(path, ec)))  // a FIFO or device: refused by the reader
            mesh = load_obj_mesh(path.string());
        else if (asset)
            mesh = parse_obj_mesh(asset->second, asset->first);
        else
            t.fail("file", "no such mesh file: " + printable(path.string(), 200));
    } catch (const InputError& e) {
        if (e.field() == t.field("file")) throw;
        t.fail("file", e.what());  // "<scene>: obstacle[k].file: <mesh>:<line>: f: ..."
    }
    return finish_mesh(t, std::move(mesh), scale, rotation, translate);
}

/// The mesh placed (scaled, rotated, translated) and checked to lie in the scene's bounds.
ObstaclePtr finish_mesh(const TomlTable& t, geometry::TriangleMesh mesh, double scale, const Vec3& rotation, const Vec3& translate)
{
    mesh = geometry::transform(mesh, scale, rotation, translate);
    geometry::Aabb box;
    for (const Vec3& p : mesh.vertices) box.extend(p);
    const double reach = std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff());
    const double extent = (box.hi - box.lo).maxCoeff();
    if (!(reach <= kMaxCoordinate_m) || !(extent >= kMinLength_m))
        t.fail_self("the scaled, rotated and translated mesh spans " + vec_str(box.lo) + " .. " + vec_str(box.hi) +
                    " m; expected it within " + kObstacleCoordinate.str() + " and at least " + num_str(kMinLength_m) +
                    " m across (check scale and translate_m)");
    return build(t, [&] { return std::make_unique<geometry::MeshObstacle>(std::move(mesh)); });
}

/// The obstacle types of `[[obstacle]] type = ...`, one builder each.
struct ObstacleType {
    std::string_view name;
    ObstaclePtr (*build)(const TomlTable&, const ObstacleContext&);
};
constexpr ObstacleType kObstacleTypes[] = {
    {"plane", build_plane}, {"box", build_box},   {"sphere", build_sphere},
    {"cylinder", build_cylinder}, {"disc", build_disc}, {"mesh", build_mesh},
};

}  // namespace

std::unique_ptr<geometry::Obstacle> build_obstacle(const TomlTable& t, const ObstacleContext& context, std::string& kind)
{
    kind = t.string("type", std::nullopt);
    const auto type = std::find_if(std::begin(kObstacleTypes), std::end(kObstacleTypes),
                                   [&](const ObstacleType& o) { return o.name == kind; });
    if (type == std::end(kObstacleTypes))
        t.fail("type", "unknown obstacle type \"" + printable(kind) + "\" (expected plane, box, sphere, cylinder, disc or mesh)");
    return type->build(t, context);
}

}  // namespace woven::io
