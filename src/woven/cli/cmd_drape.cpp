// woven drape [SCENE]: drape a cloth over a scene's obstacles and write drape.obj, drape.ply, drape.glb,
// drape.png and report.json.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/app/drape.hpp"
#include "woven/app/drape_report.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress_display.hpp"
#include "woven/common/error.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::cli {

namespace {

/// The command's options as a typed request (app::drape_request checks them: the one-line
/// errors of bad values).
DrapeRequest drape_request(const DrapeOptions& options)
{
    DrapeValues v;
    v.grid = options.grid;
    v.solver = options.solver;
    v.seed = options.seed;
    v.threads = options.threads;
    v.max_steps = options.max_steps;
    v.perturb_m = options.perturb;
    v.hysteresis = options.hysteresis;
    v.bias = options.bias;
    v.start = options.start;
    DrapeRequest r = app::drape_request(v, Naming::OPTIONS);
    r.scene = options.scene;
    r.fabric = options.fabric;
    return r;
}

}  // namespace

int run_drape(const DrapeOptions& options)
{
    // 1. Validate everything: options, scene, fabric, model. Nothing is written before this.
    DrapeWriteOptions write;
    write.width = static_cast<int>(parse_integer(options.width, "--width", kPictureSizeRange[0], kPictureSizeRange[1]));
    write.height = static_cast<int>(parse_integer(options.height, "--height", kPictureSizeRange[0], kPictureSizeRange[1]));
    write.no_render = options.no_render;
    write.ply_ascii = options.ply_ascii;
    const std::string out_dir = parse_path(options.out, "--out");
    std::vector<std::string> warnings;
    const std::unique_ptr<DrapeSetup> setup = prepare_drape(drape_request(options), warnings);
    print_warnings(warnings);

    // 2. The output directory, before the (long) solve, so that a bad --out fails early.
    make_output_dir(out_dir);
    std::vector<std::string> targets = kDrapeFiles;
    targets.push_back("report.json");
    check_output_targets(out_dir, targets);

    // 3. Drape.
    install_interrupt_handler();
    Progress progress(setup->max_steps, setup->scene.solver.residual_tolerance);
    std::cerr << "woven: " << drape_banner(*setup) << "\n";
    sim::Result result = solve_drape(*setup, [&progress](const sim::StepInfo& s) { return progress(s); },
                                     [&progress](const sim::IterationInfo& i) { return progress.iteration(i); });
    progress.finish();
    const DrapeRun run = finish_drape(*setup, std::move(result), interrupt_requested());

    // 4. Outputs: one set, report.json last (drape_run.hpp).
    const nlohmann::json report = write_drape_outputs(run, out_dir, write);
    std::cout << drape_summary(report) << "wrote";
    for (const auto& name : report["outputs"]) std::cout << " " << join_path(out_dir, name.get<std::string>());
    std::cout << " " << join_path(out_dir, "report.json") << "\n";
    const sim::Result& r = run.result;
    if (run.interrupted || interrupt_requested()) {
        std::cerr << "woven: interrupted after " << r.steps << " steps; the outputs hold the state reached"
                  << (r.converged ? "\n" : " (not converged)\n");
        return interrupted_exit_code();
    }
    if (!r.converged)
        std::cerr << "woven: warning: not converged after " << r.steps
                  << " steps (the outputs hold the state reached; raise --max-steps)\n";
    return kExitOk;
}

void add_drape_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<DrapeOptions>();
    CLI::App* sub = app.add_subcommand("drape", "Drape a cloth over a scene's obstacles to static equilibrium");
    sub->footer("Writes drape.obj, drape.ply (with per-vertex fields), drape.glb (glTF 2.0, y-up), drape.png and report.json (last, naming every file with its SHA-256) "
                "to --out. Ctrl-C (SIGINT) or SIGTERM stops after the current step, writes the state reached and exits "
                "with 130 or 143 (a second signal quits at once, leaving the previous outputs as they were).");
    sub->add_option("SCENE", o->scene, "A built-in scene name (see `woven scenes`) or a scene .toml file")
        ->capture_default_str();
    sub->add_option("--fabric", o->fabric, "Fabric: a built-in name or a fabric .toml file (overrides the scene's)");
    sub->add_option("--grid", o->grid, "Particles along the cloth's longer side (the cloth's size is kept)")
        ->type_name(int_type(kGridRange));
    sub->add_option("--solver", o->solver, "Solver: fast (implicit steps, projected Newton) or paper (Sec. 3)")
        ->type_name(choice_type(sim::kSolverKindNames));
    sub->add_option("--seed", o->seed, "Random seed: the fast solver's start perturbation (--perturb), the paper solver's stochastic phase")
        ->type_name(kSeedType);
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores available to the process)")
        ->type_name(int_type(0, io::kMaxThreads));
    sub->add_option("--max-steps", o->max_steps, "Step limit (0: the solver's default)")->type_name(int_type(kMaxStepsRange));
    sub->add_option("--perturb", o->perturb,
                    "Fast solver: amplitude of the seeded random perturbation of the start, m (0: none; the seed is --seed)")
        ->type_name(number_type(0, io::kMaxPerturbation_m));
    sub->add_option("--hysteresis", o->hysteresis,
                    "loading-branch (each KES curve's loading branch as an elastic energy) or friction (the mean line plus friction "
                    "inside the weave, its slip state updated after each step: the drape remembers its path; fast solver); "
                    "overrides the scene's [model] hysteresis")
        ->type_name(choice_type(model::kHysteresisNames));
    sub->add_option("--bias", o->bias, std::string(kBiasBendingHelp) + "; overrides the scene's [model] bias_bending")
        ->type_name(choice_type(model::kBiasBendingNames));
    sub->add_option("--start", o->start,
                    "Start from this drape.obj (of the same scene and grid, e.g. an earlier drape's) instead of the scene's "
                    "flat start; its SHA-256 goes into report.json");
    sub->add_option("--out", o->out, "Output directory")->capture_default_str();
    sub->add_flag("--no-render", o->no_render, "Do not render drape.png");
    sub->add_flag("--ply-ascii", o->ply_ascii, "Write drape.ply as ASCII PLY (default: binary little-endian)");
    sub->add_option("--width", o->width, "Picture width, pixels")->capture_default_str()->type_name(int_type(kPictureSizeRange));
    sub->add_option("--height", o->height, "Picture height, pixels")->capture_default_str()->type_name(int_type(kPictureSizeRange));
    sub->callback([o, &exit_code] { exit_code = run_drape(*o); });
}

}  // namespace woven::cli
