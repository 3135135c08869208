// woven render MESH: a picture of a draped cloth (drape.obj) over a scene's obstacles, from one
// of the views of the paper's Fig. 8.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/app/drape.hpp"
#include "woven/app/scene_view.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/render/image.hpp"

namespace woven::cli {

namespace {

struct RenderCommandOptions {
    std::string mesh;
    std::optional<std::string> scene;
    std::optional<std::string> fabric;
    std::string view;  // empty: scene with --scene, else corner
    std::string size = "1024x768";
    std::string out = "render.png";
};

/// --size's type in --help: "WxH (INT in [1, 16384] each)".
std::string size_type() { return "WxH (" + int_type(kPictureSizeRange) + " each)"; }

/// "WxH" -> (W, H), each in kPictureSizeRange.
std::pair<int, int> parse_size(const std::string& s)
{
    int w = 0, h = 0;
    char x = 0, extra = 0;
    const auto in_range = [](int v) { return v >= kPictureSizeRange[0] && v <= kPictureSizeRange[1]; };
    if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || !in_range(w) || !in_range(h))
        throw InputError(kCommandLine, "--size",
                         "expected WxH, each an integer in [" + std::to_string(kPictureSizeRange[0]) + ", "
                             + std::to_string(kPictureSizeRange[1]) + "] (e.g. 1024x768), got '" + printable(s, 40) + "'");
    return {w, h};
}

/// The grid size written by io::cloth_obj ("# grid NU x NV particles"), if the text has one.
std::optional<std::pair<int, int>> obj_grid(const std::string& text)
{
    std::istringstream in(text);
    std::string line;
    for (int n = 0; n < 20 && std::getline(in, line); ++n) {
        int nu = 0, nv = 0;
        if (std::sscanf(line.c_str(), "# grid %d x %d", &nu, &nv) == 2 && nu >= 2 && nv >= 2) return std::pair{nu, nv};
    }
    return std::nullopt;
}

int run_render(const RenderCommandOptions& o)
{
    const auto [width, height] = parse_size(o.size);
    std::string view_name = o.view.empty() ? (o.scene ? "scene" : "corner") : o.view;
    const std::optional<render::View> view = parse_choice(view_name, "--view", render::kViewNames);
    if (o.out.empty()) throw InputError(kCommandLine, "--out", "expected a PNG file name");
    {
        // A directory (or anything but a file) is bad usage, as for the other commands.
        namespace fs = std::filesystem;
        std::error_code ec;
        const auto st = fs::symlink_status(o.out, ec);
        if (!ec && fs::is_directory(st)) throw InputError(kCommandLine, "--out", o.out + " is a directory; expected a PNG file name");
        if (!ec && fs::exists(st) && !fs::is_regular_file(st))
            throw InputError(kCommandLine, "--out", o.out + " exists and is not a regular file");
    }

    std::vector<std::string> warnings;
    std::optional<io::SceneSpec> scene;
    if (o.scene) scene = io::find_scene(*o.scene, &warnings);
    std::string fabric_name = o.fabric ? *o.fabric : scene ? scene->fabric : std::string("cotton");
    const kes::FabricData fabric = io::find_fabric(fabric_name, &warnings);
    print_warnings(warnings);

    const std::string obj = io::read_input_file(o.mesh, io::kMaxObjBytes, {"mesh file", "an OBJ file"});
    const geometry::TriangleMesh mesh = io::parse_obj_mesh(obj, o.mesh);
    render::ClothSurface cloth;
    const auto grid = obj_grid(obj);
    if (grid && mesh.vertices.size() == static_cast<std::size_t>(grid->first) * grid->second) {
        const Positions x(mesh.vertices.begin(), mesh.vertices.end());
        cloth = render::grid_surface(x, grid->first, grid->second);
    } else {  // any other mesh: drawn as it is, without thread lines
        cloth.mesh = mesh;
        double len = 0;
        for (const auto& f : mesh.faces) len += (mesh.vertices[f[0]] - mesh.vertices[f[1]]).norm();
        cloth.spacing_m = mesh.faces.empty() ? 0 : len / mesh.faces.size();
    }

    // The folder is created as the other commands create theirs (before the picture is made);
    // the file is written under a unique temporary name and renamed into place.
    if (const auto parent = std::filesystem::path(o.out).parent_path(); !parent.empty()) make_output_dir(parent.string());

    geometry::ObstacleSet floor_only;  // without a scene: a floor under the lowest vertex
    if (!scene) {
        double zmin = mesh.vertices.front().z();
        for (const Vec3& v : mesh.vertices) zmin = std::min(zmin, v.z());
        floor_only.add(std::make_unique<geometry::Plane>(Vec3(0, 0, zmin), Vec3::UnitZ()));
    }
    const render::DrapeScene ds
        = scene_view(std::move(cloth), scene ? scene->obstacles : floor_only, fabric, scene ? &scene->camera : nullptr);
    const render::Image img = render_view(ds, *view, width, height, o.out);
    io::write_file_atomic(o.out, render::encode_png(img, o.out));
    std::cout << "wrote " << o.out << " (" << width << " x " << height << ", view " << render::view_name(*view) << ")\n";
    return kExitOk;
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<RenderCommandOptions>();
    CLI::App* sub = app.add_subcommand("render", "Render a draped cloth mesh (drape.obj) over a scene's obstacles");
    sub->footer("Views (the paper's Fig. 8): front (from -y), corner (the +x -y corner along its diagonal, 20 deg "
                "above), side (from +x), top, scene (the scene camera's direction). The camera frames the cloth "
                "and obstacles tightly. A mesh written by woven drape is drawn as a smooth surface through its "
                "particles with thread lines (warp darker than weft).");
    sub->add_option("MESH", o->mesh, "The cloth: an OBJ file (e.g. out/drape.obj)")->required();
    sub->add_option("--scene", o->scene, "The scene whose obstacles to draw (built-in name or .toml); else a floor only");
    sub->add_option("--fabric", o->fabric, "The fabric whose colour to use (default: the scene's, else cotton)");
    sub->add_option("--view", o->view, "The view (default: scene with --scene, else corner)")->type_name(choice_type(render::kViewNames));
    sub->add_option("--size", o->size, "Picture size WxH in pixels")->capture_default_str()->type_name(size_type());
    sub->add_option("--out", o->out, "Output PNG file")->capture_default_str();
    sub->callback([o, &exit_code] { exit_code = run_render(*o); });
}

}  // namespace woven::cli
