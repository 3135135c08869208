// The cusick job (cusick.hpp): the Cusick drape test on a simulated specimen.
#include "woven/app/cusick.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/app/drape_report.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/sim/resources.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/app/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/start_file.hpp"
#include "woven/io/surface_file.hpp"
#include "woven/io/toml_reader.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/render/gltf_file.hpp"
#include "woven/render/image.hpp"
#include "woven/render/instrument_plots.hpp"
#include "woven/testers/cusick.hpp"

namespace woven::app {

namespace {

constexpr int kShadowPixels = 800;  ///< shadow.png is square, this many pixels a side

/// shadow.png (render::shadow_picture) of the draped surface.
render::Image shadow_picture(const geometry::TriangleMesh& surface, double specimen_radius, double disc_radius,
                             const analysis::Nodes& nodes, double dc)
{
    const double half = render::shadow_half_width(specimen_radius);
    const analysis::ShadowRaster r = analysis::rasterize_shadow(surface, Vec2(-half, -half), 2 * half / kShadowPixels, kShadowPixels, kShadowPixels);
    return render::shadow_picture(r.covered, kShadowPixels, specimen_radius, disc_radius, nodes.angle_deg, nodes.radius_m, dc);
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

/// The request's values as the tester's options (InputError "command line: --<option>: ...",
/// the command's messages).
testers::CusickOptions cusick_options(const CusickRequest& r)
{
    testers::CusickOptions co;
    co.specimen_diameter_m = 0.01 * positive_in_range(r.specimen_cm, "--specimen-cm", kCusickMaxDiameter_cm);
    co.disc_diameter_m = 0.01 * positive_in_range(r.disc_cm, "--disc-cm", kCusickMaxDiameter_cm);
    if (r.spacing_cm) co.spacing_m = 0.01 * positive_in_range(*r.spacing_cm, "--spacing-cm", kCusickMaxSpacing_cm);
    const int runs = static_cast<int>(integer_in_range(r.seeds, "--seeds", kCusickSeedsRange[0], kCusickSeedsRange[1]));
    // Run k uses seed + k: the last must not wrap round to 0.
    const std::uint64_t max_seed0 = std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(runs - 1);
    if (r.seed > max_seed0)
        throw InputError(kCommandLine, "--seed",
                         "expected at most " + std::to_string(max_seed0) + " with --seeds " + std::to_string(runs) +
                             " (the runs' seeds are seed .. seed + " + std::to_string(runs - 1) + "), got '" + std::to_string(r.seed) + "'");
    if (r.threads) co.solver.threads = static_cast<int>(integer_in_range(*r.threads, "--threads", kCusickThreadsRange[0], kCusickThreadsRange[1]));
    if (r.max_steps)
        co.solver.max_steps = static_cast<int>(integer_in_range(*r.max_steps, "--max-steps", kCusickMaxStepsRange[0], kCusickMaxStepsRange[1]));
    if (r.shear_law) co.model.shear_law = *r.shear_law;
    if (r.hysteresis) co.model.hysteresis = *r.hysteresis;
    if (r.protocol) co.protocol = *r.protocol;
    if (r.shakes) co.shakes = static_cast<int>(integer_in_range(*r.shakes, "--shakes", kCusickShakesRange[0], kCusickShakesRange[1]));
    if (r.bias) co.model.bias_bending = *r.bias;
    if (r.solver) co.solver.kind = *r.solver;
    if (r.discretization) co.model.discretization = *r.discretization;
    if (r.fall_s) {
        if (co.solver.kind != sim::SolverKind::FAST) throw InputError(kCommandLine, "--fall-s", "expected only with the fast solver");
        co.solver.fast.fall_duration = number_in_range(*r.fall_s, "--fall-s", 0, io::kMaxFallDuration_s);
    }
    if (r.thread_compression) {
        if (co.model.discretization != model::Discretization::CONVERGENT)
            throw InputError(kCommandLine, "--thread-compression", "expected only with the convergent discretisation");
        co.model.thread_compression = number_in_range(*r.thread_compression, "--thread-compression", kThreadCompressionRange[0], kThreadCompressionRange[1]);
    }
    if (r.grid_rotation_deg) co.grid_rotation_deg = number_in_range(*r.grid_rotation_deg, "--grid-rotation-deg", kCusickGridRotationRange[0], kCusickGridRotationRange[1]);
    if (!r.search && (r.modes || r.jobs)) throw InputError(kCommandLine, r.modes ? "--modes" : "--jobs", "expected only with --search");
    if (r.search && r.start) throw InputError(kCommandLine, "--start", "expected without --search (the search makes its own starts)");
    if (r.clamp) co.clamp = *r.clamp;
    if (r.clamp_margin) {
        if (co.clamp != testers::CusickClamp::PINNED) throw InputError(kCommandLine, "--clamp-margin", "expected only with --clamp pinned");
        co.clamp_margin = number_in_range(*r.clamp_margin, "--clamp-margin", kCusickClampMarginRange[0], kCusickClampMarginRange[1]);
    }
    if (r.clamp_gap_mm) {
        if (co.clamp != testers::CusickClamp::DISCS) throw InputError(kCommandLine, "--clamp-gap-mm", "expected only with --clamp discs");
        co.clamp_gap_m = 1e-3 * positive_in_range(*r.clamp_gap_mm, "--clamp-gap-mm", 1e3 * co.solver.contact_distance);
    }
    return co;
}

/// The search's starts (--search): the release, the guide counts, the continuations from copies
/// 4 and 16 times stiffer in bending.
testers::CusickSearchOptions search_options(const CusickRequest& r)
{
    testers::CusickSearchOptions search;
    if (!r.search) return search;
    search.modes = r.modes.value_or(kCusickDefaultModes);
    for (std::size_t k = 0; k < search.modes.size(); ++k)
        if (search.modes[k] < 2 || search.modes[k] > 64 || (k > 0 && search.modes[k] <= search.modes[k - 1]))
            throw InputError(kCommandLine, "--modes", "expected fold counts in [2, 64], ascending, no repeats");
    if (search.modes.empty()) throw InputError(kCommandLine, "--modes", "expected at least one fold count");
    search.stiffer = {4.0, 16.0};
    if (r.jobs) search.jobs = static_cast<int>(integer_in_range(*r.jobs, "--jobs", kCusickJobsRange[0], kCusickJobsRange[1]));
    return search;
}

/// The specimen on the instrument; an impossible one is an error of the option that made it.
testers::CusickSetup cusick_setup(const testers::CusickOptions& co)
{
    try {
        return testers::make_cusick_setup(co);
    } catch (const InputError& e) {
        const std::string f = e.field();
        const std::string opt = f == "specimen_diameter_m" ? "--specimen-cm"
                                : f == "disc_diameter_m"   ? "--disc-cm"
                                : f == "clamp_margin"      ? "--clamp-margin"
                                                           : "--spacing-cm";
        const std::string what = e.what();
        throw InputError(kCommandLine, opt, what.substr(what.find(f + ": ") + f.size() + 2));
    }
}

/// The drape estimate (one for every job that drapes), before anything large is built. A
/// search runs `jobs` starts at once in this process: each its own solve.
void check_cusick_memory(const testers::CusickSetup& setup, const testers::CusickOptions& co, const CusickRequest& r,
                         const testers::CusickSearchOptions& search)
{
    sim::MemoryEstimate need = sim::estimate_drape_memory(setup.cut.count, sim::threads_to_use(co.solver.threads));
    const int at_once = r.search ? std::max(1, search.jobs) : 1;
    need.address_space_bytes += (at_once - 1) * need.resident_bytes;
    need.resident_bytes *= at_once;
    check_memory_estimate(need, setup.cut.count, kCommandLine, r.spacing_cm ? "--spacing-cm" : "--specimen-cm",
                          at_once > 1 ? "use a larger --spacing-cm or fewer --jobs" : "use a larger --spacing-cm");
}

/// Every file of the set, known before the runs: published together, cusick.json last
/// (io::OutputSet), so an interrupted or failed run never leaves a mixed directory.
std::vector<std::string> cusick_members(int runs, std::uint64_t seed0)
{
    std::vector<std::string> members{"cusick.obj", "cusick.glb", "drape.png"};
    for (int k = 0; k < runs; ++k)
        members.push_back(runs == 1 ? "shadow.png" : "shadow-seed" + std::to_string(seed0 + static_cast<std::uint64_t>(k)) + ".png");
    return members;
}

/// The run's one-line description.
std::string cusick_banner(const std::string& name, const testers::CusickOptions& co, const testers::CusickSetup& setup, int runs)
{
    const double R = 0.5 * co.specimen_diameter_m, rd = 0.5 * co.disc_diameter_m;
    std::ostringstream s;
    s << "cusick " << name << ": specimen " << 2 * R * 100 << " cm on a " << 2 * rd * 100 << " cm disc, spacing " << co.spacing_m * 100
      << " cm (" << setup.cut.count << " particles), " << shear_law_text(co.model) << ", hysteresis " << model::to_string(co.model.hysteresis)
      << ", protocol " << testers::protocol_name(co.protocol) << (co.shakes > 0 ? " and " + std::to_string(co.shakes) + " shakes" : std::string());
    if (co.solver.kind != sim::SolverKind::FAST) s << ", solver " << sim::to_string(co.solver.kind);
    if (co.model.discretization != model::Discretization::CONVERGENT) s << ", discretization " << model::to_string(co.model.discretization);
    if (co.solver.fast.fall_duration > 0) s << ", fall " << co.solver.fast.fall_duration << " s";
    if (co.model.thread_compression != 1) s << ", thread compression " << co.model.thread_compression;
    if (co.grid_rotation_deg != 0) s << ", threads turned " << co.grid_rotation_deg << " deg";
    s << ", " << runs << (runs == 1 ? " run" : " runs");
    return s.str();
}

/// One seed's drape (or, with search, its rest states), the progress shown as a drape's.
testers::CusickSearch run_seed(const kes::FabricData& fabric, const testers::CusickOptions& ck, bool search_states,
                               const testers::CusickSearchOptions& search)
{
    const int max_steps = ck.solver.max_steps > 0 ? ck.solver.max_steps : sim::default_max_steps(ck.solver.kind);
    Progress progress(max_steps, ck.solver.residual_tolerance);
    testers::CusickSearch found = testers::run_cusick_seed(
        fabric, ck, search_states ? &search : nullptr, [&progress](const sim::StepInfo& s) { return progress(s); },
        [&progress](const sim::IterationInfo& i) { return progress.iteration(i); });
    progress.finish();
    if (found.prediction < 0) throw RuntimeError("cusick: the search reached no rest state");
    return found;
}

/// cusick.json's `states` of a search: each rest state found.
nlohmann::json states_json(const testers::CusickSearch& found)
{
    nlohmann::json states = nlohmann::json::array();
    for (const testers::CusickState& st : found.states) {
        const testers::CusickResult& sr = st.result;
        states.push_back({{"start", testers::start_name(st.start)},
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
    return states;
}

/// One entry of cusick.json's `runs`.
nlohmann::json run_json(const testers::CusickSearch& found, std::uint64_t seed, bool search_states, bool interrupted)
{
    const testers::CusickResult& r = found.states[static_cast<std::size_t>(found.prediction)].result;
    const analysis::Nodes& nd = r.shadow.nodes;
    nlohmann::json j;
    j["seed"] = seed;
    if (search_states) {
        j["states"] = states_json(found);
        j["prediction"] = {{"rule", "lowest energy"}, {"state", found.prediction}};
    }
    j["drape_coefficient_percent"] = r.shadow.drape_coefficient_percent;
    j["nodes"] = nd.count();
    j["node_angles_deg"] = nd.angle_deg;
    j["node_depths_m"] = nd.depth_m;
    j["node_radii_m"] = nd.radius_m;
    j["node_amplitudes_m"] = nd.amplitude_m;
    j["shadow_area_m2"] = r.shadow.shadow_area_m2;
    j.update(solver_result_json(r.drape, false));
    j["interrupted"] = interrupted;
    j["stages"] = r.stages;
    j["max_residual_rel"] = r.drape.equilibrium.max_residual_rel;
    j["energy_J"] = r.drape.energy.total();
    return j;
}

/// What every run of a cusick job shares.
struct CusickRun {
    const CusickRequest& request;
    const kes::FabricData& fabric;
    const std::string& name;
    const testers::CusickOptions& co;
    const testers::CusickSetup& setup;
    const std::string& out_dir;
    io::OutputSet& set;
};

/// Run k's files: its shadow picture and, for the first run, the specimen's mesh and picture.
void add_run_files(const CusickRun& c, const testers::CusickResult& r, int k, std::uint64_t seed)
{
    const analysis::Nodes& nd = r.shadow.nodes;
    const double R = 0.5 * c.co.specimen_diameter_m, rd = 0.5 * c.co.disc_diameter_m;
    const std::string suffix = c.request.seeds == 1 ? "" : "-seed" + std::to_string(seed);
    const std::string shadow_name = "shadow" + suffix + ".png";
    io::require_finite_positions(r.drape.x, "cusick: the drape of seed " + std::to_string(seed));
    c.set.add(shadow_name, render::encode_png(shadow_picture(r.surface, R, rd, nd, r.shadow.drape_coefficient_percent),
                                              join_path(c.out_dir, shadow_name)));
    if (k != 0) return;
    c.set.add("cusick.obj", io::surface_obj(r.surface, r.surface_uv,
                                            "cusick: draped specimen, fabric " + c.name + ", spacing " + std::to_string(r.spacing_m) + " m"));
    c.set.add("cusick.glb", render::display_glb(render::surface_gltf_mesh(r.surface, r.surface_uv), c.setup.obstacles, c.co.solver.contact_distance,
                                                     c.fabric.color, "the draped surface", "the .obj file holds it as solved"));
    if (c.request.render && !interrupt_requested())
        c.set.add("drape.png", render::encode_png(drape_picture(r, c.setup, c.fabric), join_path(c.out_dir, "drape.png")));
}

/// cusick.json without its runs and summary.
nlohmann::json cusick_report(const CusickRun& c, const testers::CusickSearchOptions& search, const std::string& start_sha256)
{
    const testers::CusickOptions& co = c.co;
    const testers::CusickSetup& setup = c.setup;
    const double R = 0.5 * co.specimen_diameter_m, rd = 0.5 * co.disc_diameter_m;
    nlohmann::json rep;
    rep["version"] = WOVEN_VERSION;
    rep["fabric"] = c.name;
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
    rep["solver"] = sim::to_string(co.solver.kind);
    rep["discretization"] = model::to_string(co.model.discretization);
    if (co.solver.kind == sim::SolverKind::FAST) rep["fall_duration_s"] = co.solver.fast.fall_duration;
    if (co.model.discretization == model::Discretization::CONVERGENT) rep["thread_compression"] = co.model.thread_compression;
    rep["grid_rotation_deg"] = co.grid_rotation_deg;
    rep["start_sha256"] = start_sha256;  // empty: the flat start
    rep["search"] = {{"modes", search.modes}, {"stiffer", search.stiffer}, {"release", search.release},
                     {"rule", c.request.search ? "lowest energy" : "the release"}};
    if (co.shakes > 0) rep["shake_amplitude_g"] = co.shake_amplitude;
    rep["shear_scale"] = co.model.shear_scale;
    rep["specimen_area_m2"] = setup.cut.total_area;
    rep["specimen_mass_kg"] = setup.cut.total_area * c.fabric.areal_density_mg_cm2 * 1e-2;
    rep["angle_reference"] = "0 deg = warp (+y, grid v), 90 deg = weft (+x, grid u), seen from above";
    rep["node_min_prominence_m"] = co.shadow.min_prominence_fraction * (R - rd);
    return rep;
}

/// The runs' statistics (more than one run): the drape coefficient's mean and spread, the node
/// counts.
void add_run_statistics(nlohmann::json& rep, const std::vector<double>& dcs, const std::vector<int>& counts)
{
    const testers::CusickStatistics st = testers::cusick_statistics(dcs, counts);
    rep["drape_coefficient_mean"] = st.drape_coefficient_mean;
    rep["drape_coefficient_std"] = st.drape_coefficient_std;
    rep["nodes_per_run"] = counts;
    nlohmann::json pj = nlohmann::json::object();
    for (const auto& [c, m] : st.runs_per_node_count) pj[std::to_string(c)] = m;
    rep["runs_per_node_count"] = pj;
}

}  // namespace

CusickResult cusick(const CusickRequest& request)
{
    const auto started = std::chrono::steady_clock::now();
    const MonitorScope monitor(request.monitor);
    // 1. Validate everything before writing anything.
    testers::CusickOptions co = cusick_options(request);
    const testers::CusickSearchOptions search = search_options(request);
    const int runs = request.seeds;
    std::vector<std::string> warnings;
    const kes::FabricData fabric = command_fabric(request.fabric, request.given_fabric, &warnings);
    if (request.on_warnings) request.on_warnings(warnings);
    warnings.clear();  // delivered
    const std::string name = fabric.name.empty() ? request.fabric : fabric.name;
    const std::string out_dir = path_given(request.out, "--out").value_or(join_path("out", "cusick-" + safe_file_name(name)));
    const testers::CusickSetup setup = cusick_setup(co);
    check_cusick_memory(setup, co, request, search);
    with_fabric_source(command_fabric_source(request.fabric, request.given_fabric), [&] { resolve_shear_law(fabric, co.model, warnings); });
    if (request.on_warnings && !warnings.empty()) request.on_warnings(warnings);
    std::string start_sha256;
    if (request.start) {
        const std::string path = path_given(request.start->string(), "--start");
        io::StartState start = io::load_start(path, setup.grid, setup.cut.active, setup.initial);
        // As the flat start: outside the instrument, within the specimen's diameter of the disc's
        // top centre (a particle 1 km away drove the shadow measurement to 9.3 GB).
        std::vector<int> held = setup.clamped;
        held.insert(held.end(), setup.sandwiched.begin(), setup.sandwiched.end());
        const io::StartBounds bounds{&setup.obstacles, Vec3(0, 0, setup.disc_top_z), co.specimen_diameter_m, "the instrument's bounds"};
        io::check_start_positions(start.x, setup.cut.active, held, bounds, path, "v",
                                  [&](int p) { return "line " + std::to_string(start.line[static_cast<std::size_t>(p)]); });
        co.start = std::move(start.x);
        start_sha256 = start.sha256;
    }
    make_output_dir(out_dir);
    std::vector<std::string> members = cusick_members(runs, request.seed);
    members.push_back("cusick.json");
    check_output_targets(out_dir, members);
    members.pop_back();
    io::OutputSet set(out_dir, members);

    // 2. The runs: seeds seed, seed + 1, ...
    if (request.on_start) request.on_start(cusick_banner(name, co, setup, runs));
    const CusickRun c{request, fabric, name, co, setup, out_dir, set};
    CusickResult result;
    nlohmann::json run_list = nlohmann::json::array(), first;
    std::vector<double> dcs;
    std::vector<int> counts;
    for (int k = 0; k < runs && !result.interrupted; ++k) {
        testers::CusickOptions ck = co;
        ck.solver.seed = request.seed + static_cast<std::uint64_t>(k);
        const testers::CusickSearch found = run_seed(fabric, ck, request.search, search);
        const testers::CusickResult& r = found.states[static_cast<std::size_t>(found.prediction)].result;
        result.interrupted = interrupt_requested() || found.interrupted;
        const nlohmann::json j = run_json(found, ck.solver.seed, request.search, result.interrupted);
        result.all_converged = result.all_converged && r.drape.converged;
        dcs.push_back(r.shadow.drape_coefficient_percent);
        counts.push_back(r.shadow.nodes.count());
        add_run_files(c, r, k, ck.solver.seed);
        if (k == 0) first = j;
        run_list.push_back(j);
        const CusickRunLine line{k + 1, runs, ck.solver.seed, r.shadow.drape_coefficient_percent, r.shadow.nodes.angle_deg,
                                 r.drape.converged, r.drape.steps, r.drape.wall_time};
        result.runs.push_back(line);
        if (request.on_run) request.on_run(line);
    }

    // A signal after the last solve (during its pictures: drape.png takes seconds, or its
    // on_run) interrupts the job as one during the solve does: a scheduler's time limit must not
    // read as success. Asked before the report; one during the publish waits for it (io::OutputSet).
    if (!result.interrupted && interrupt_requested()) {
        result.interrupted = true;
        if (!run_list.empty()) run_list.back()["interrupted"] = true;
    }

    // 3. cusick.json.
    nlohmann::json rep = cusick_report(c, search, start_sha256);
    for (const char* key : {"drape_coefficient_percent", "nodes", "node_angles_deg", "node_depths_m"}) rep[key] = first[key];
    rep["converged"] = result.all_converged;
    rep["interrupted"] = result.interrupted;
    rep["residual_tolerance"] = co.solver.residual_tolerance;
    rep["runs"] = run_list;
    if (runs > 1) add_run_statistics(rep, dcs, counts);
    rep["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();  // the job's, its runs and pictures, to the report's writing
    io::require_finite(rep, "cusick");
    rep["files"] = set.files_json();
    set.publish("cusick.json", rep.dump(2) + "\n");
    result.report = std::move(rep);
    result.out_dir = out_dir;
    result.files = set.names();
    return result;
}

}  // namespace woven::app
