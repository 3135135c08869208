// woven cusick FABRIC: the Cusick drape test (BS 5058, ISO 9073-9) on a simulated specimen:
// drape coefficient, nodes, the shadow picture, a render and the mesh (testers/cusick.hpp).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_easy_font.h>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/material.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/cli/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/start_file.hpp"
#include "woven/io/toml_reader.hpp"
#include "woven/io/surface_file.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/render/image.hpp"
#include "woven/testers/cusick.hpp"

namespace woven::cli {

namespace {

constexpr int kShadowPixels = 800;  ///< shadow.png is square, this many pixels a side

struct Canvas {
    render::Image img;
    void set(int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b)
    {
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
        std::uint8_t* p = &img.rgb[3 * (static_cast<size_t>(y) * img.width + x)];
        p[0] = r;
        p[1] = g;
        p[2] = b;
    }
    void text(const std::string& s, int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b)
    {
        std::vector<char> vbuf(s.size() * 270 + 64);
        std::string buf = s;
        const int quads = stb_easy_font_print(0, 0, buf.data(), nullptr, vbuf.data(), static_cast<int>(vbuf.size()));
        const float* v = reinterpret_cast<const float*>(vbuf.data());
        for (int q = 0; q < quads; ++q) {  // 4 vertices of 16 bytes (x, y, z, colour) per quad
            const float* a = v + q * 16;
            const int x0 = static_cast<int>(a[0]) * 2, y0 = static_cast<int>(a[1]) * 2, x1 = static_cast<int>(a[8]) * 2,
                      y1 = static_cast<int>(a[9]) * 2;
            for (int yy = y0; yy < y1; ++yy)
                for (int xx = x0; xx < x1; ++xx) set(x + xx, y + yy, r, g, b);
        }
    }
};

/// shadow.png: the shadow in black on white, seen from above with the warp (+y) up and the
/// weft (+x) to the right; the disc (blue) and the flat specimen (grey) circles, as on the
/// instrument's paper ring; the warp and weft axes and a red tick at each node.
render::Image shadow_picture(const geometry::TriangleMesh& surface, double specimen_radius, double disc_radius,
                             const analysis::Nodes& nodes, double dc, int nodes_count)
{
    const double half = 1.08 * specimen_radius;
    const double px = 2 * half / kShadowPixels;
    const analysis::ShadowRaster r = analysis::rasterize_shadow(surface, Vec2(-half, -half), px, kShadowPixels, kShadowPixels);
    Canvas c;
    c.img.width = c.img.height = kShadowPixels;
    c.img.rgb.assign(3 * static_cast<size_t>(kShadowPixels) * kShadowPixels, 255);
    for (int row = 0; row < kShadowPixels; ++row)
        for (int col = 0; col < kShadowPixels; ++col)
            if (r.covered[col + static_cast<size_t>(kShadowPixels) * row]) c.set(col, kShadowPixels - 1 - row, 0, 0, 0);
    const auto to_px = [&](double x, double y) {
        return std::pair<int, int>{static_cast<int>((x + half) / px), kShadowPixels - 1 - static_cast<int>((y + half) / px)};
    };
    const auto circle = [&](double rad, std::uint8_t R, std::uint8_t G, std::uint8_t B) {
        const int n = static_cast<int>(2 * M_PI * rad / px * 2);
        for (int k = 0; k < n; ++k) {
            const double a = 2 * M_PI * k / n;
            const auto [x, y] = to_px(rad * std::sin(a), rad * std::cos(a));
            for (int d = 0; d < 2; ++d) c.set(x + d, y, R, G, B);
        }
    };
    circle(specimen_radius, 150, 150, 150);
    circle(disc_radius, 40, 90, 220);
    // Axes: warp up (+y), weft right (+x), dotted grey through the centre.
    for (int k = 0; k < kShadowPixels; k += 4) {
        c.set(kShadowPixels / 2, k, 170, 170, 170);
        c.set(k, kShadowPixels / 2, 170, 170, 170);
    }
    c.text("warp (0 deg)", kShadowPixels / 2 + 6, 4, 200, 0, 0);
    c.text("weft (90 deg)", kShadowPixels - 175, kShadowPixels / 2 + 6, 200, 0, 0);
    for (int k = 0; k < nodes.count(); ++k) {
        const double a = nodes.angle_deg[k] * M_PI / 180;
        for (double t = nodes.radius_m[k]; t < specimen_radius * 1.06; t += 0.5 * px) {
            const auto [x, y] = to_px(t * std::sin(a), t * std::cos(a));
            c.set(x, y, 220, 0, 0);
            c.set(x + 1, y, 220, 0, 0);
        }
    }
    std::ostringstream label;
    label << "DC " << std::fixed << std::setprecision(1) << dc << " %, " << nodes_count << " nodes";
    c.text(label.str(), 6, kShadowPixels - 24, 0, 0, 0);
    return c.img;
}

/// drape.png: the draped specimen over the instrument, thread lines showing warp and weft.
render::Image drape_picture(const testers::CusickResult& r, const testers::CusickSetup& setup, const kes::FabricData& fabric)
{
    render::ClothSurface cloth;
    cloth.mesh = r.surface;
    cloth.uv.assign(r.surface_uv.begin(), r.surface_uv.end());
    cloth.spacing_m = r.spacing_m;
    return render_view(scene_view(std::move(cloth), setup.obstacles, fabric), render::View::CORNER, 1024, 768, "drape.png");
}

/// "2-12" or "3,5,7": fold counts from 2 to 64, ascending, no repeats.
std::vector<int> parse_modes(const std::string& text)
{
    std::vector<int> modes;
    const auto bad = [&] { return InputError(kCommandLine, "--modes", "expected a range such as 2-12 or a list such as 3,5,7 of fold counts in [2, 64], got '" + io::printable(text) + "'"); };
    const auto number = [&](const std::string& t) {
        if (t.empty() || t.size() > 2 || t.find_first_not_of("0123456789") != std::string::npos) throw bad();
        const int v = std::stoi(t);
        if (v < 2 || v > 64) throw bad();
        return v;
    };
    if (const auto dash = text.find('-'); dash != std::string::npos) {
        const int lo = number(text.substr(0, dash)), hi = number(text.substr(dash + 1));
        if (hi < lo) throw bad();
        for (int m = lo; m <= hi; ++m) modes.push_back(m);
        return modes;
    }
    std::size_t begin = 0;
    while (true) {
        const auto comma = text.find(',', begin);
        modes.push_back(number(text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin)));
        if (comma == std::string::npos) break;
        begin = comma + 1;
    }
    for (std::size_t k = 1; k < modes.size(); ++k)
        if (modes[k] <= modes[k - 1]) throw bad();
    return modes;
}

std::string angles_text(const std::vector<double>& a)
{
    std::ostringstream o;
    // Whole degrees in [0, 360): 359.9997 is printed as 0, not 360.
    for (size_t k = 0; k < a.size(); ++k) o << (k ? " " : "") << static_cast<long>(std::lround(a[k])) % 360;
    return o.str();
}

}  // namespace

int run_cusick(const CusickCommandOptions& o)
{
    // 1. Validate everything before writing anything.
    testers::CusickOptions co;
    co.specimen_diameter_m = 0.01 * parse_positive(o.specimen_cm, "--specimen-cm", 200);
    co.disc_diameter_m = 0.01 * parse_positive(o.disc_cm, "--disc-cm", 200);
    if (o.spacing_cm) co.spacing_m = 0.01 * parse_positive(*o.spacing_cm, "--spacing-cm", 10);
    const int runs = static_cast<int>(parse_integer(o.seeds, "--seeds", 1, 1000));
    const std::uint64_t seed0 = parse_seed(o.seed, "--seed");
    // Run k uses seed0 + k: the last must not wrap round to 0.
    const std::uint64_t max_seed0 = std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(runs - 1);
    if (seed0 > max_seed0)
        throw InputError(kCommandLine, "--seed",
                         "expected at most " + std::to_string(max_seed0) + " with --seeds " + std::to_string(runs) +
                             " (the runs' seeds are seed .. seed + " + std::to_string(runs - 1) + "), got '" + o.seed + "'");
    if (auto t = parse_integer(o.threads, "--threads", 0, 4096)) co.solver.threads = static_cast<int>(*t);
    if (auto m = parse_integer(o.max_steps, "--max-steps", 0, 1000000)) co.solver.max_steps = static_cast<int>(*m);
    if (o.shear_law)
        co.model.shear_law = parse_shear_law(*o.shear_law, "--shear-law");
    if (o.hysteresis) co.model.hysteresis = parse_hysteresis(*o.hysteresis, "--hysteresis");
    if (o.protocol)
        co.protocol = parse_choice(*o.protocol, "--protocol", testers::kCusickProtocolNames);
    if (o.shakes) co.shakes = static_cast<int>(parse_integer(*o.shakes, "--shakes", 0, 100));
    if (o.bias) co.model.bias_bending = parse_bias_bending(*o.bias, "--bias");
    testers::CusickSearchOptions search;
    if (!o.search && (o.modes || o.jobs)) throw InputError(kCommandLine, o.modes ? "--modes" : "--jobs", "expected only with --search");
    if (o.search && o.start) throw InputError(kCommandLine, "--start", "expected without --search (the search makes its own starts)");
    if (o.search) {
        search.modes = parse_modes(o.modes.value_or("2"));
        search.stiffer = {4.0, 16.0};
        if (o.jobs) search.jobs = static_cast<int>(parse_integer(*o.jobs, "--jobs", 1, 64));
    }
    if (o.clamp) co.clamp = parse_choice(*o.clamp, "--clamp", testers::kCusickClampNames);
    if (o.clamp_margin) {
        if (co.clamp != testers::CusickClamp::PINNED)
            throw InputError(kCommandLine, "--clamp-margin", "expected only with --clamp pinned");
        co.clamp_margin = parse_number(*o.clamp_margin, "--clamp-margin", -2, 2);
    }
    if (o.clamp_gap_mm) {
        if (co.clamp != testers::CusickClamp::DISCS) throw InputError(kCommandLine, "--clamp-gap-mm", "expected only with --clamp discs");
        co.clamp_gap_m = 1e-3 * parse_positive(*o.clamp_gap_mm, "--clamp-gap-mm", 1e3 * co.solver.contact_distance);
    }
    std::vector<std::string> warnings;
    const kes::FabricData fabric = command_fabric(o.fabric, o.given_fabric, &warnings);
    print_warnings(warnings);
    const std::string name = fabric.name.empty() ? o.fabric : fabric.name;
    const std::string out_dir = o.out ? parse_path(*o.out, "--out") : join_path("out", "cusick-" + safe_file_name(name));
    testers::CusickSetup setup;
    try {
        setup = testers::make_cusick_setup(co);
    } catch (const InputError& e) {
        const std::string f = e.field();
        const std::string opt = f == "specimen_diameter_m" ? "--specimen-cm"
                                : f == "disc_diameter_m"   ? "--disc-cm"
                                : f == "clamp_margin"      ? "--clamp-margin"
                                                           : "--spacing-cm";
        const std::string what = e.what();
        throw InputError(kCommandLine, opt, what.substr(what.find(f + ": ") + f.size() + 2));
    }
    // The drape estimate (one for every command that drapes), before anything large is built.
    // --search runs --jobs starts at once in this process: each its own solve.
    MemoryEstimate need = estimate_drape_memory(setup.cut.count, threads_to_use(co.solver.threads));
    const int at_once = o.search ? std::max(1, search.jobs) : 1;
    need.address_space_bytes += (at_once - 1) * need.resident_bytes;
    need.resident_bytes *= at_once;
    check_memory_estimate(need, setup.cut.count, kCommandLine, o.spacing_cm ? "--spacing-cm" : "--specimen-cm",
                          at_once > 1 ? "use a larger --spacing-cm or fewer --jobs" : "use a larger --spacing-cm");
    with_fabric_source(command_fabric_source(o.fabric, o.given_fabric), [&] { resolve_shear_law(fabric, co.model); });
    std::string start_sha256;
    if (o.start) {
        io::StartState start = io::load_start(parse_path(*o.start, "--start"), setup.grid, setup.cut.active, setup.initial);
        co.start = std::move(start.x);
        start_sha256 = start.sha256;
    }
    make_output_dir(out_dir);
    // Every file of the set, known before the runs: published together, cusick.json last
    // (io::OutputSet), so an interrupted or failed run never leaves a mixed directory.
    std::vector<std::string> members{"cusick.obj", "cusick.glb", "drape.png"};
    for (int k = 0; k < runs; ++k)
        members.push_back(runs == 1 ? "shadow.png" : "shadow-seed" + std::to_string(seed0 + static_cast<std::uint64_t>(k)) + ".png");
    members.push_back("cusick.json");
    check_output_targets(out_dir, members);
    members.pop_back();
    io::OutputSet set(out_dir, members);
    install_interrupt_handler();

    // 2. The runs: seeds seed0, seed0 + 1, ...
    const double R = 0.5 * co.specimen_diameter_m, rd = 0.5 * co.disc_diameter_m;
    std::cerr << "woven: cusick " << name << ": specimen " << 2 * R * 100 << " cm on a " << 2 * rd * 100 << " cm disc, spacing "
              << co.spacing_m * 100 << " cm (" << setup.cut.count << " particles), " << shear_law_text(co.model) << ", hysteresis "
              << model::to_string(co.model.hysteresis) << ", protocol " << testers::protocol_name(co.protocol)
              << (co.shakes > 0 ? " and " + std::to_string(co.shakes) + " shakes" : std::string()) << ", " << runs
              << (runs == 1 ? " run\n" : " runs\n");
    nlohmann::json run_list = nlohmann::json::array();
    std::vector<double> dcs;
    std::vector<int> counts;
    const auto out = [&](const std::string& f) { return join_path(out_dir, f); };
    bool all_converged = true, interrupted = false;
    nlohmann::json first;
    for (int k = 0; k < runs && !interrupted; ++k) {
        testers::CusickOptions ck = co;
        ck.solver.seed = seed0 + static_cast<std::uint64_t>(k);
        const int max_steps = ck.solver.max_steps > 0 ? ck.solver.max_steps : sim::default_max_steps(ck.solver.kind);
        Progress progress(max_steps, ck.solver.residual_tolerance);
        testers::CusickSearch found;
        if (o.search) {
            found = testers::search_cusick(fabric, ck, search, [&progress](const sim::StepInfo& s) { return progress(s); });
        } else {
            found.states.push_back({{}, testers::run_cusick(fabric, ck, [&progress](const sim::StepInfo& s) { return progress(s); })});
            found.prediction = 0;
            found.interrupted = found.states[0].result.drape.interrupted;
        }
        progress.finish();
        if (found.prediction < 0) throw RuntimeError("cusick: the search reached no rest state");
        const testers::CusickResult& r = found.states[static_cast<std::size_t>(found.prediction)].result;
        interrupted = interrupt_requested() || found.interrupted;
        const analysis::Nodes& nd = r.shadow.nodes;
        nlohmann::json j;
        j["seed"] = ck.solver.seed;
        if (o.search) {
            nlohmann::json states = nlohmann::json::array();
            for (const testers::CusickState& st : found.states) {
                const testers::CusickResult& sr = st.result;
                const std::string start = st.start.guides > 0 ? std::to_string(st.start.guides) + " guides"
                                          : st.start.stiffer > 0 ? "from " + std::to_string(static_cast<int>(st.start.stiffer)) + " x B"
                                                                 : std::string("release");
                states.push_back({{"start", start},
                                  {"guides", st.start.guides},
                                  {"stiffer", st.start.stiffer},
                                  {"phase_deg", st.start.phase_rad * 180 / M_PI},
                                  {"drape_coefficient_percent", sr.shadow.drape_coefficient_percent},
                                  {"nodes", sr.shadow.nodes.count()},
                                  {"node_angles_deg", sr.shadow.nodes.angle_deg},
                                  {"energy_J", sr.drape.energy.total()},
                                  {"converged", sr.drape.converged},
                                  {"steps", sr.drape.steps},
                                  {"wall_time_s", sr.drape.wall_time}});
            }
            j["states"] = states;
            j["prediction"] = {{"rule", "lowest energy"}, {"state", found.prediction}};
        }
        j["drape_coefficient_percent"] = r.shadow.drape_coefficient_percent;
        j["nodes"] = nd.count();
        j["node_angles_deg"] = nd.angle_deg;
        j["node_depths_m"] = nd.depth_m;
        j["node_radii_m"] = nd.radius_m;
        j["node_amplitudes_m"] = nd.amplitude_m;
        j["shadow_area_m2"] = r.shadow.shadow_area_m2;
        j["converged"] = r.drape.converged;
        j["interrupted"] = interrupted;
        j["steps"] = r.drape.steps;
        j["iterations"] = r.drape.iterations;
        j["wall_time_s"] = r.drape.wall_time;
        j["stages"] = r.stages;
        j["max_residual_rel"] = r.drape.equilibrium.max_residual_rel;
        j["energy_J"] = r.drape.energy.total();
        all_converged = all_converged && r.drape.converged;
        dcs.push_back(r.shadow.drape_coefficient_percent);
        counts.push_back(nd.count());
        const std::string suffix = runs == 1 ? "" : "-seed" + std::to_string(ck.solver.seed);
        const std::string shadow_name = "shadow" + suffix + ".png";
        require_finite_positions(r.drape.x, "cusick: the drape of seed " + std::to_string(ck.solver.seed));
        set.add(shadow_name, render::encode_png(shadow_picture(r.surface, R, rd, nd, r.shadow.drape_coefficient_percent, nd.count()),
                                                out(shadow_name)));
        if (k == 0) {
            set.add("cusick.obj", io::surface_obj(r.surface, r.surface_uv,
                                                  "cusick: draped specimen, fabric " + name + ", spacing " + std::to_string(r.spacing_m) + " m"));
            set.add("cusick.glb", io::draped_surface_glb(r.surface, r.surface_uv, setup.obstacles, ck.solver.contact_distance, fabric.color));
            if (!o.no_render && !interrupt_requested()) {
                set.add("drape.png", render::encode_png(drape_picture(r, setup, fabric), out("drape.png")));
            }
            first = j;
        }
        run_list.push_back(j);
        std::cout << "run " << k + 1 << "/" << runs << " seed " << ck.solver.seed << ": DC " << std::fixed << std::setprecision(1)
                  << r.shadow.drape_coefficient_percent << " %, " << nd.count() << " nodes at " << angles_text(nd.angle_deg)
                  << " deg from the warp, " << (r.drape.converged ? "converged" : "NOT converged") << " in " << r.drape.steps << " steps, "
                  << std::setprecision(1) << r.drape.wall_time << " s\n";
        std::cout.unsetf(std::ios::fixed);
    }

    // 3. cusick.json.
    nlohmann::json rep;
    rep["version"] = WOVEN_VERSION;
    rep["fabric"] = name;
    rep["specimen_diameter_m"] = co.specimen_diameter_m;
    rep["disc_diameter_m"] = co.disc_diameter_m;
    rep["spacing_m"] = co.spacing_m;
    rep["grid"] = {setup.grid.nu, setup.grid.nv};
    rep["particles"] = setup.cut.count;
    rep["clamp"] = testers::clamp_name(co.clamp);
    rep["clamped_particles"] = setup.clamped.size();
    rep["sandwiched_particles"] = setup.sandwiched.size();
    rep["clamp_radius_m"] = setup.clamp_radius;
    rep["pinned_radius_m"] = setup.pinned_radius;
    if (co.clamp == testers::CusickClamp::DISCS) rep["clamp_gap_m"] = setup.clamp_disc_bottom_z - setup.disc_top_z;
    rep["perturbation_m"] = co.perturbation_m;
    rep["hysteresis"] = model::to_string(co.model.hysteresis);
    rep["protocol"] = testers::protocol_name(co.protocol);
    if (co.protocol == testers::CusickProtocol::LOWERED) rep["lower_step_m"] = testers::lower_step_m(co);
    rep["shakes"] = co.shakes;
    rep["bias_bending"] = model::to_string(co.model.bias_bending);
    rep["start_sha256"] = start_sha256;  // empty: the flat start
    rep["search"] = {{"modes", search.modes}, {"stiffer", search.stiffer}, {"release", search.release},
                     {"rule", o.search ? "lowest energy" : "the release"}};
    if (co.shakes > 0) rep["shake_amplitude_g"] = co.shake_amplitude;
    rep["shear_scale"] = co.model.shear_scale;
    rep["specimen_area_m2"] = setup.cut.total_area;
    rep["specimen_mass_kg"] = setup.cut.total_area * fabric.areal_density_mg_cm2 * 1e-2;
    rep["angle_reference"] = "0 deg = warp (+y, grid v), 90 deg = weft (+x, grid u), seen from above";
    rep["node_min_prominence_m"] = co.shadow.min_prominence_fraction * (R - rd);
    for (const char* key : {"drape_coefficient_percent", "nodes", "node_angles_deg", "node_depths_m"}) rep[key] = first[key];
    rep["converged"] = all_converged;
    rep["interrupted"] = interrupted;
    rep["residual_tolerance"] = co.solver.residual_tolerance;
    rep["runs"] = run_list;
    if (runs > 1) {
        const double n = static_cast<double>(dcs.size());
        double mean = 0, var = 0;
        for (double d : dcs) mean += d / n;
        for (double d : dcs) var += (d - mean) * (d - mean) / std::max(1.0, n - 1);
        rep["drape_coefficient_mean"] = mean;
        rep["drape_coefficient_std"] = std::sqrt(var);
        rep["nodes_per_run"] = counts;
        std::map<int, int> per;
        for (int c : counts) ++per[c];
        nlohmann::json pj = nlohmann::json::object();
        for (const auto& [c, m] : per) pj[std::to_string(c)] = m;
        rep["runs_per_node_count"] = pj;
    }
    require_finite(rep, "cusick");
    rep["files"] = set.files_json();
    set.publish("cusick.json", rep.dump(2) + "\n");
    std::cout << "wrote";
    for (const auto& w : set.names()) std::cout << " " << out(w);
    std::cout << " " << out("cusick.json") << "\n";
    if (interrupted) {
        std::cerr << "woven: interrupted; the outputs hold the runs done (not converged)\n";
        return interrupted_exit_code();
    }
    if (!all_converged) std::cerr << "woven: warning: not every run converged (raise --max-steps)\n";
    return kExitOk;
}

void add_cusick_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<CusickCommandOptions>();
    CLI::App* sub = app.add_subcommand("cusick", "Cusick drape test: drape coefficient and nodes of a circular specimen on a disc");
    sub->footer("The specimen (a disc cut from the particle grid, warp along +y) is clamped centred on the support disc and "
                "drapes to rest; DC = (A_shadow - A_disc) / (A_specimen - A_disc) x 100 %. Writes shadow.png (top view, warp "
                "up), drape.png, cusick.obj, cusick.glb (the specimen for display over the instrument) and cusick.json to --out; one line per run on stdout. Node angles are measured "
                "from the warp towards the weft.");
    sub->add_option("FABRIC", o->fabric, "A built-in fabric (see `woven fabrics`) or a fabric .toml file")->required();
    sub->add_option("--specimen-cm", o->specimen_cm, "Specimen diameter, cm (the standard's 30; 24 and 36 are also used)")
        ->capture_default_str();
    sub->add_option("--disc-cm", o->disc_cm, "Support disc diameter, cm")->capture_default_str();
    sub->add_option("--spacing-cm", o->spacing_cm, "Particle spacing, cm (default 0.5: where the drape coefficient has converged)");
    sub->add_option("--seeds", o->seeds, "Runs, each from a different small random perturbation of the flat start")->capture_default_str()->type_name("INT");
    sub->add_option("--seed", o->seed, "Seed of the first run (the others: seed + 1, ...)")->capture_default_str()->type_name("INT");
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores)")->type_name("INT");
    sub->add_option("--max-steps", o->max_steps, "Step limit per run (0: the solver's default)")->type_name("INT");
    sub->add_option("--shear-law", o->shear_law, "deembedded (the default: the material's law, docs/VALIDATION.md) or measured (the input curve as read)");
    sub->add_option("--clamp", o->clamp,
                    "pinned (the default: the particles within the disc's radius + --clamp-margin spacings pinned) or discs "
                    "(the ring out to the rim held between the support disc and a clamp disc, true circles)");
    sub->add_option("--clamp-margin", o->clamp_margin, "The pinned clamp's reach beyond the disc's rim, in spacings (default 0.5)");
    sub->add_option("--clamp-gap-mm", o->clamp_gap_mm, "The discs clamp's gap between the discs, mm (default: the contact distance, 1 mm)");
    sub->add_option("--hysteresis", o->hysteresis,
                    "loading-branch (the default: each KES curve's loading branch as an elastic energy) or friction (the mean "
                    "line plus friction inside the weave, its slip state carried through the drape)");
    sub->add_option("--protocol", o->protocol,
                    "release (the default: the clamped specimen released flat, its overhang falling to rest) or lowered (the "
                    "overhang on a plate lowered in 1 cm stages, each to rest, then the plate taken away: a monotonic loading)");
    sub->add_option("--shakes", o->shakes,
                    "After the protocol, this many cycles of a quasi-static vertical shake of the disc (to rest at 1.5 g, at "
                    "0.5 g, in the clamp's frame), then to rest at g (default 0)")->type_name("INT");
    sub->add_option("--bias", o->bias, kBiasBendingHelp);
    sub->add_option("--start", o->start, "Start from this cusick.obj (of the same specimen and spacing) instead of the flat start");
    sub->add_flag("--search", o->search,
                  "Search the rest states: the release, one start per guide count (--modes: the overhang first falls onto "
                  "that many guide rods under it, which are then taken away) and the continuations from copies 4 and 16 "
                  "times stiffer in bending, each draped to rest; the prediction is the state of lowest energy, every "
                  "state listed in cusick.json");
    sub->add_option("--modes", o->modes, "--search: the guide counts, one (2, the default), a range 2-12 or a list 3,5,7");
    sub->add_option("--jobs", o->jobs, "--search: starts run at once (default 1; each on --threads threads)")->type_name("INT");
    sub->add_option("--out", o->out, "Output directory (default out/cusick-<fabric>)");
    sub->add_flag("--no-render", o->no_render, "Do not render drape.png");
    sub->callback([o, &exit_code] { exit_code = run_cusick(*o); });
}

}  // namespace woven::cli
