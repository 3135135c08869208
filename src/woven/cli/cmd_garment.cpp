// woven garment FILE: cut a garment's pattern pieces from the fabric's thread grid, sew them
// around the body and drape them; write garment.glb, garment.png and report.json.
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/app/garment.hpp"
#include "woven/app/progress.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress_display.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::cli {

namespace {

struct GarmentOptions {
    std::string file;
    std::optional<std::string> fabric, spacing_cm, threads, max_steps, seed;
    std::string out = "out/garment";
    std::string width = "800", height = "1000";
    bool no_render = false;
};

int run_garment(const GarmentOptions& o)
{
    GarmentRequest r;
    r.file = parse_path(o.file, "FILE");
    r.fabric = o.fabric;
    if (o.spacing_cm) r.spacing_cm = parse_number(*o.spacing_cm, "--spacing", io::kGarmentSpacingCm[0], io::kGarmentSpacingCm[1]);
    if (const auto t = parse_integer(o.threads, "--threads", 0, io::kMaxThreads)) r.threads = static_cast<int>(*t);
    if (const auto m = parse_integer(o.max_steps, "--max-steps", 0, 1'000'000'000)) r.max_steps = static_cast<int>(*m);
    if (o.seed) r.seed = parse_seed(*o.seed, "--seed");
    const int width = static_cast<int>(parse_integer(o.width, "--width", 1, 16384));
    const int height = static_cast<int>(parse_integer(o.height, "--height", 1, 16384));
    const std::string out_dir = parse_path(o.out, "--out");
    std::vector<std::string> warnings;
    std::unique_ptr<GarmentSetup> setup = prepare_garment(r, warnings);
    print_warnings(warnings);
    make_output_dir(out_dir);
    check_output_targets(out_dir, {"garment.glb", "garment.png", "report.json"});

    install_interrupt_handler();
    int particles = 0;
    for (char a : setup->cloth.active) particles += a;
    std::cerr << "woven: garment '" << setup->spec.name << "' in " << setup->fabric_label << ": " << setup->spec.pattern.pieces.size()
              << " pieces, " << setup->spec.pattern.seams.size() << " seams, " << particles << " particles at "
              << format_g(setup->cloth.grid.sigma * 100, 3) << " cm, " << setup->threads.used << " thread(s); seams ramped over "
              << setup->seam_stiffness.size() << " stages\n";
    std::unique_ptr<Progress> progress;
    const GarmentRun run = solve_garment(
        *setup, [&](const sim::StepInfo& s) { return (*progress)(s); }, [&](const sim::IterationInfo& i) { return progress->iteration(i); },
        [&](int stage, int stages, double k) {
            progress.reset();
            std::cerr << strf("woven: stage %d of %d: seams at %.4g N/m\n", stage, stages, k);
            progress = std::make_unique<Progress>(setup->solver.max_steps, setup->solver.residual_tolerance);
        });
    progress.reset();
    const nlohmann::json rep = write_garment_outputs(*setup, run, out_dir, width, height, o.no_render);
    std::cout << strf("garment '%s' (%s, %.3g cm): hem %d nodes, flare %.3f, hem %.1f cm below the waist, length drop %.1f cm; "
                      "seam gap at most %.3g of the spacing; %d steps, %.1f s\n",
                      setup->spec.name.c_str(), setup->fabric_label.c_str(), setup->cloth.grid.sigma * 100, rep["hem"]["nodes"].get<int>(),
                      rep["hem"]["flare"].get<double>(), rep["hem"]["below_waist_m"].get<double>() * 100,
                      rep["hem"]["length_drop_m"].get<double>() * 100, rep["seam_max_gap_over_spacing"].get<double>(), run.total.steps,
                      run.total.wall_time);
    std::cout << "wrote";
    for (const auto& name : rep["outputs"]) std::cout << " " << join_path(out_dir, name.get<std::string>());
    std::cout << " " << join_path(out_dir, "report.json") << "\n";
    if (run.interrupted || interrupt_requested()) return interrupted_exit_code();
    if (!run.total.converged) std::cerr << "woven: warning: the last stage did not converge (raise --max-steps)\n";
    return kExitOk;
}

}  // namespace

void add_garment_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<GarmentOptions>();
    CLI::App* sub = app.add_subcommand("garment", "Cut a garment's pattern pieces from the fabric, sew them around a body and drape them");
    sub->footer("The garment file (docs/GARMENT-FORMAT.md) gives the pieces (outlines in cm, grain, placement around the body), the "
                "seams, the body (the built-in dress form or an OBJ) and the fabric. Writes garment.glb (the cloth and the body, glTF "
                "2.0, y-up), garment.png and report.json (last: the hem's nodes, radius per angle, flare and length drop, each "
                "seam's gaps and forces, naming every file with its SHA-256) to --out. Bad input, a piece that starts inside the "
                "body, pieces placed on each other or a seam that crosses the body: one line, exit 2.");
    sub->add_option("FILE", o->file, "A garment .toml file")->required();
    sub->add_option("--fabric", o->fabric, "Fabric: a built-in name or a fabric .toml file (overrides the file's)");
    sub->add_option("--spacing", o->spacing_cm, "Thread grid spacing, cm (overrides the file's spacing_cm)")->type_name("CM");
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores available to the process)")->type_name("INT");
    sub->add_option("--max-steps", o->max_steps, "Step limit of each stage of the seams' ramp (0: the solver's default)")->type_name("INT");
    sub->add_option("--seed", o->seed, "Random seed of the fast solver's start perturbation")->type_name("INT");
    sub->add_option("--out", o->out, "Output directory")->capture_default_str();
    sub->add_flag("--no-render", o->no_render, "Do not render garment.png");
    sub->add_option("--width", o->width, "Picture width, pixels")->capture_default_str()->type_name("INT");
    sub->add_option("--height", o->height, "Picture height, pixels")->capture_default_str()->type_name("INT");
    sub->callback([o, &exit_code] { exit_code = run_garment(*o); });
}

}  // namespace woven::cli
