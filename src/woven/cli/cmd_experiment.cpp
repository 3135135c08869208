// woven experiment cube|map|figure1: the options as an experiment request (batch/experiment.hpp).
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/app/progress.hpp"
#include "woven/batch/experiment.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress_display.hpp"
#include "woven/common/error.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::cli {

using namespace woven::batch;

namespace {

struct ExperimentOptions {
    std::string which;
    std::string out = ExperimentRequest{}.out.string();
    std::string seeds = std::to_string(ExperimentRequest{}.seeds);
    std::optional<std::string> grid;
    std::string threads = std::to_string(ExperimentRequest{}.threads);
    std::string map_grid = "5x4";
    std::optional<std::string> reuse;
    std::optional<std::string> sweep;
    bool plan_only = false;
    std::string jobs = "1";
    std::optional<std::string> shard;
    std::vector<std::string> fabrics = ExperimentRequest{}.fabrics;
};

ExperimentRequest experiment_request(const ExperimentOptions& o, const std::string& command)
{
    ExperimentRequest r;
    r.which = parse_choice(o.which, "EXPERIMENT", kExperimentNames);
    r.out = o.out;
    r.seeds = static_cast<int>(parse_integer(o.seeds, "--seeds", kExperimentSeedsRange[0], kExperimentSeedsRange[1]));
    if (const auto g = parse_integer(o.grid, "--grid", kExperimentGridRange[0], kExperimentGridRange[1])) r.grid = static_cast<int>(*g);
    r.threads = static_cast<int>(parse_integer(o.threads, "--threads", 0, io::kMaxThreads));
    if (r.which == Experiment::MAP) {
        if (o.reuse && o.plan_only) throw InputError(kCommandLine, "--plan-only", "expected no --reuse (reused drapes need no plan)");
        char x = 0, extra = 0;
        if (std::sscanf(o.map_grid.c_str(), "%d%c%d%c", &r.map_rows, &x, &r.map_columns, &extra) != 3 || x != 'x')
            throw InputError(kCommandLine, "--map-grid", map_grid_expected());
    }
    if (o.reuse) r.reuse = o.reuse;
    if (o.sweep) r.sweep = parse_path(*o.sweep, "--sweep");
    r.plan_only = o.plan_only;
    r.jobs = static_cast<int>(parse_integer(o.jobs, "--jobs", kJobsRange[0], kJobsRange[1]));
    r.shard = shard_from(o.shard, [](const char* name) { return std::getenv(name); });
    r.executable = kThisProgram;
    r.fabrics = o.fabrics;
    r.command = command;
    r.on_warnings = print_warnings;
    r.on_sweep_line = print_line;
    r.on_drape = [](const std::string& what) { std::cerr << "woven: experiment: " << what << " ...\n" << std::flush; };
    return r;
}

int run_experiment(const ExperimentOptions& o, const std::string& command)
{
    const ExperimentRequest request = experiment_request(o, command);
    // The map of reused drapes is drawn in this process: a signal stops it before it publishes
    // (the sweep that drapes takes the signals over itself).
    if (request.which == Experiment::MAP && request.reuse) install_interrupt_handler();
    const ExperimentResult r = experiment(request);
    if (r.interrupted) {
        std::cerr << "woven: interrupted; nothing written (the folder keeps the previous complete set)\n";
        return r.signal != 0 ? 128 + r.signal : interrupted_exit_code();
    }
    std::cout << r.message << "\n";
    return kExitOk;
}

}  // namespace

void add_experiment_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<ExperimentOptions>();
    CLI::App* sub = app.add_subcommand("experiment", "Run one of the paper's experiments and write its figures and tables");
    sub->footer("cube: cotton, wool and polyester/cotton over the cube for --seeds seeds (Sec. 6, Fig. 8): cube_figure.png "
                "(corner, side, top views), cube_folds.md (fold table, how often each corner structure appears), "
                "cube_results.json.\nmap: the corner structure over synthetic fabrics (warp/weft bending ratio 1/4 .. 4, "
                "bending length 1 .. 5 cm; --map-grid): corner_map.png, corner_map.md, corner_map.json.\n"
                "figure1: the chair and the end table (Fig. 1): figure1_chair.png, figure1_table.png, figure1.md, figure1.json.\n"
                "The drapes are a sweep plan (docs/SWEEP-FORMAT.md; examples/experiment-cube.toml, experiment-figure1.toml) written "
                "as <sweep>/plan.toml and run as `woven sweep` runs it: one point folder per drape under --sweep, resumed (a drape whose "
                "folder verifies is not run again), --jobs at once, split by --shard I/N or the launcher's ranks (the rank that finds "
                "every drape done writes the figures). The figures and tables are then built from each point's report.json and "
                "drape.obj.\n"
                "Each experiment's files are one set, its JSON written last naming every file with its SHA-256. Ctrl-C (SIGINT) "
                "or SIGTERM stops the running drapes and exits with 130 or 143 without writing: the folder keeps the previous set "
                "(finished drapes stay in the sweep folder).");
    sub->add_option("EXPERIMENT", o->which, "The experiment")->required()->type_name(choice_type(kExperimentNames));
    sub->add_option("--out", o->out, "Output directory")->capture_default_str();
    sub->add_option("--seeds", o->seeds, "cube: seeds 1 .. N per fabric")
        ->capture_default_str()
        ->type_name(int_type(kExperimentSeedsRange));
    sub->add_option("--grid", o->grid, "Particles along the cloth's longer side (default: the scene's)")
        ->type_name(int_type(kExperimentGridRange));
    sub->add_option("--threads", o->threads, "Worker threads per drape (0: all cores)")
        ->capture_default_str()
        ->type_name(int_type(0, io::kMaxThreads));
    sub->add_option("--map-grid", o->map_grid, "map: RxL, R ratios by L bending lengths")
        ->capture_default_str()
        ->type_name("RxL (" + int_type(kMapGridRange) + " each)");
    sub->add_option("--reuse", o->reuse, "map: analyse the drapes of an earlier run again (its corner_map.json), without draping");
    sub->add_option("--sweep", o->sweep, "The sweep folder: the plan and one folder per drape (default out/experiment-<name>)");
    sub->add_flag("--plan-only", o->plan_only, "Write the plan (and the map's fabric files) into the sweep folder and stop");
    sub->add_option("--jobs", o->jobs, "Drapes run at once on this machine")->capture_default_str()->type_name(int_type(kJobsRange));
    sub->add_option("--shard", o->shard, "Run shard I of N (0 <= I < N) of the drapes, as `woven sweep --shard`")->type_name("I/N");
    sub->callback([o, &exit_code, sub] {
        // The command the results record: the options that change them (not where or how the
        // drapes ran: --sweep, --plan-only, --jobs, --shard).
        std::string command = "woven experiment " + o->which;
        for (const CLI::Option* opt : sub->get_options()) {
            if (opt->count() == 0 || opt->get_name() == "EXPERIMENT" || opt->get_lnames().empty()) continue;
            const std::string name = opt->get_lnames()[0];
            if (name == "sweep" || name == "plan-only" || name == "jobs" || name == "shard") continue;
            command += " --" + name + " " + opt->as<std::string>();
        }
        exit_code = run_experiment(*o, command);
    });
}

}  // namespace woven::cli
