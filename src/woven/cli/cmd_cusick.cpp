// woven cusick FABRIC: the options as a cusick request (app/cusick.hpp); one line per run.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/app/cusick.hpp"
#include "woven/app/progress.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress_display.hpp"
#include "woven/common/error.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::cli {

namespace {

/// "2-12" or "3,5,7": fold counts from 2 to 64, ascending, no repeats.
std::vector<int> parse_modes(const std::string& text)
{
    std::vector<int> modes;
    const auto bad = [&] { return InputError(kCommandLine, "--modes", "expected a range such as 2-12 or a list such as 3,5,7 of fold counts in [2, 64], got '" + printable(text) + "'"); };
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

void print_run(const CusickRunLine& l)
{
    std::cout << "run " << l.run << "/" << l.runs << " seed " << l.seed << ": DC " << std::fixed << std::setprecision(1)
              << l.drape_coefficient_percent << " %, " << l.node_angles_deg.size() << " nodes at " << angles_text(l.node_angles_deg)
              << " deg from the warp, " << (l.converged ? "converged" : "NOT converged") << " in " << l.steps << " steps, "
              << std::setprecision(1) << l.wall_time_s << " s\n";
    std::cout.unsetf(std::ios::fixed);
}

CusickRequest cusick_request(const CusickCommandOptions& o)
{
    CusickRequest r;
    r.fabric = o.fabric;
    r.given_fabric = o.given_fabric;
    r.specimen_cm = parse_positive(o.specimen_cm, "--specimen-cm", kCusickMaxDiameter_cm);
    r.disc_cm = parse_positive(o.disc_cm, "--disc-cm", kCusickMaxDiameter_cm);
    if (o.spacing_cm) r.spacing_cm = parse_positive(*o.spacing_cm, "--spacing-cm", kCusickMaxSpacing_cm);
    r.seeds = static_cast<int>(parse_integer(o.seeds, "--seeds", kCusickSeedsRange[0], kCusickSeedsRange[1]));
    r.seed = parse_seed(o.seed, "--seed");
    if (auto t = parse_integer(o.threads, "--threads", kCusickThreadsRange[0], kCusickThreadsRange[1])) r.threads = static_cast<int>(*t);
    if (auto m = parse_integer(o.max_steps, "--max-steps", kCusickMaxStepsRange[0], kCusickMaxStepsRange[1])) r.max_steps = static_cast<int>(*m);
    if (o.shear_law) r.shear_law = parse_shear_law(*o.shear_law, "--shear-law");
    if (o.hysteresis) r.hysteresis = parse_hysteresis(*o.hysteresis, "--hysteresis");
    if (o.protocol) r.protocol = parse_choice(*o.protocol, "--protocol", testers::kCusickProtocolNames);
    if (o.shakes) r.shakes = static_cast<int>(parse_integer(*o.shakes, "--shakes", kCusickShakesRange[0], kCusickShakesRange[1]));
    if (o.bias) r.bias = parse_bias_bending(*o.bias, "--bias");
    if (o.solver) r.solver = parse_choice(*o.solver, "--solver", sim::kSolverKindNames);
    if (o.discretization) r.discretization = parse_choice(*o.discretization, "--discretization", model::kDiscretizationNames);
    if (o.fall_s) r.fall_s = parse_number(*o.fall_s, "--fall-s", 0, io::kMaxFallDuration_s);
    if (o.thread_compression)
        r.thread_compression = parse_number(*o.thread_compression, "--thread-compression", kThreadCompressionRange[0], kThreadCompressionRange[1]);
    if (o.grid_rotation_deg)
        r.grid_rotation_deg = parse_number(*o.grid_rotation_deg, "--grid-rotation-deg", kCusickGridRotationRange[0], kCusickGridRotationRange[1]);
    r.search = o.search;
    if (o.search && o.modes) r.modes = parse_modes(*o.modes);
    if (o.search && o.jobs) r.jobs = static_cast<int>(parse_integer(*o.jobs, "--jobs", kCusickJobsRange[0], kCusickJobsRange[1]));
    if (!o.search && o.modes) r.modes = std::vector<int>{};  // refused by the job: only with --search
    if (!o.search && o.jobs) r.jobs = 1;
    if (o.clamp) r.clamp = parse_choice(*o.clamp, "--clamp", testers::kCusickClampNames);
    if (o.clamp_margin) r.clamp_margin = parse_number(*o.clamp_margin, "--clamp-margin", kCusickClampMarginRange[0], kCusickClampMarginRange[1]);
    if (o.clamp_gap_mm) r.clamp_gap_mm = parse_positive(*o.clamp_gap_mm, "--clamp-gap-mm", 1e3 * testers::CusickOptions{}.solver.contact_distance);
    if (o.start) r.start = parse_path(*o.start, "--start");
    if (o.out) r.out = parse_path(*o.out, "--out");
    r.render = !o.no_render;
    r.on_warnings = print_warnings;
    r.on_start = [](const std::string& banner) {
        install_interrupt_handler();  // the runs begin: a signal now writes the runs done
        std::cerr << "woven: " << banner << "\n";
    };
    r.on_run = print_run;
    return r;
}

}  // namespace

int run_cusick(const CusickCommandOptions& o)
{
    const CusickResult result = cusick(cusick_request(o));
    std::cout << "wrote";
    for (const auto& w : result.files) std::cout << " " << join_path(result.out_dir, w);
    std::cout << " " << join_path(result.out_dir, "cusick.json") << "\n";
    if (result.interrupted) {
        std::cerr << "woven: interrupted; the outputs hold the runs done (not converged)\n";
        return interrupted_exit_code();
    }
    if (!result.all_converged) std::cerr << "woven: warning: not every run converged (raise --max-steps)\n";
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
        ->capture_default_str()
        ->type_name(positive_type(kCusickMaxDiameter_cm));
    sub->add_option("--disc-cm", o->disc_cm, "Support disc diameter, cm")
        ->capture_default_str()
        ->type_name(positive_type(kCusickMaxDiameter_cm));
    sub->add_option("--spacing-cm", o->spacing_cm, "Particle spacing, cm (default 0.5: where the drape coefficient has converged)")
        ->type_name(positive_type(kCusickMaxSpacing_cm));
    sub->add_option("--seeds", o->seeds, "Runs, each from a different small random perturbation of the flat start")
        ->capture_default_str()
        ->type_name(int_type(kCusickSeedsRange));
    sub->add_option("--seed", o->seed, "Seed of the first run (the others: seed + 1, ...)")->capture_default_str()->type_name(kSeedType);
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores)")->type_name(int_type(kCusickThreadsRange));
    sub->add_option("--max-steps", o->max_steps, "Step limit per run (0: the solver's default)")->type_name(int_type(kCusickMaxStepsRange));
    sub->add_option("--shear-law", o->shear_law,
                    "deembedded (the default: the material's law, docs/VALIDATION.md) or measured (the input curve as read)")
        ->type_name(choice_type(model::kShearLawNames));
    sub->add_option("--clamp", o->clamp,
                    "pinned (the default: the particles within the disc's radius + --clamp-margin spacings pinned) or discs "
                    "(the ring out to the rim held between the support disc and a clamp disc, true circles)")
        ->type_name(choice_type(testers::kCusickClampNames));
    sub->add_option("--clamp-margin", o->clamp_margin, "The pinned clamp's reach beyond the disc's rim, in spacings (default 0.5)")
        ->type_name(number_type(kCusickClampMarginRange[0], kCusickClampMarginRange[1]));
    sub->add_option("--clamp-gap-mm", o->clamp_gap_mm, "The discs clamp's gap between the discs, mm (default: the contact distance, 1 mm)")
        ->type_name(positive_type(1e3 * testers::CusickOptions{}.solver.contact_distance));
    sub->add_option("--hysteresis", o->hysteresis,
                    "loading-branch (the default: each KES curve's loading branch as an elastic energy) or friction (the mean "
                    "line plus friction inside the weave, its slip state carried through the drape)")
        ->type_name(choice_type(model::kHysteresisNames));
    sub->add_option("--protocol", o->protocol,
                    "release (the default: the clamped specimen released flat, its overhang falling to rest) or lowered (the "
                    "overhang on a plate lowered in 1 cm stages, each to rest, then the plate taken away: a monotonic loading)")
        ->type_name(choice_type(testers::kCusickProtocolNames));
    sub->add_option("--shakes", o->shakes,
                    "After the protocol, this many cycles of a quasi-static vertical shake of the disc (to rest at 1.5 g, at "
                    "0.5 g, in the clamp's frame), then to rest at g (default 0)")
        ->type_name(int_type(kCusickShakesRange));
    sub->add_option("--bias", o->bias, kBiasBendingHelp)->type_name(choice_type(model::kBiasBendingNames));
    sub->add_option("--solver", o->solver, "fast (the default: implicit steps, projected Newton) or paper (the paper's three phases, Sec. 3)")
        ->type_name(choice_type(sim::kSolverKindNames));
    sub->add_option("--discretization", o->discretization,
                    "convergent (the default) or paper (the paper's literal convention: full patches, the quintic stretch well)")
        ->type_name(choice_type(model::kDiscretizationNames));
    sub->add_option("--fall-s", o->fall_s,
                    "Fast solver: hold the steps at their first size (1/60 s) for this much simulated time before they grow, s "
                    "(default 0; docs/SOLVER.md, The fall)")
        ->type_name(number_type(0, io::kMaxFallDuration_s));
    sub->add_option("--thread-compression", o->thread_compression,
                    "The thread's stiffness in compression over its tensile stiffness: 1 (the default) a linear spring both ways, "
                    "0 the paper's Eq. (3), no resistance to shortening (convergent discretisation)")
        ->type_name(number_type(kThreadCompressionRange[0], kThreadCompressionRange[1]));
    sub->add_option("--grid-rotation-deg", o->grid_rotation_deg,
                    "Turn the specimen's threads about the disc's axis by this angle, degrees counter-clockwise from above (node "
                    "angles stay measured from the warp)")
        ->type_name(number_type(kCusickGridRotationRange[0], kCusickGridRotationRange[1]));
    sub->add_option("--start", o->start, "Start from this cusick.obj (of the same specimen and spacing) instead of the flat start");
    sub->add_flag("--search", o->search,
                  "Search the rest states: the release, one start per guide count (--modes: the overhang first falls onto "
                  "that many guide rods under it, which are then taken away) and the continuations from copies 4 and 16 "
                  "times stiffer in bending, each draped to rest; the prediction is the state of lowest energy, every "
                  "state listed in cusick.json");
    sub->add_option("--modes", o->modes, "--search: the guide counts, one (2, the default), a range 2-12 or a list 3,5,7");
    sub->add_option("--jobs", o->jobs, "--search: starts run at once (default 1; each on --threads threads)")
        ->type_name(int_type(kCusickJobsRange));
    sub->add_option("--out", o->out, "Output directory (default out/cusick-<fabric>)");
    sub->add_flag("--no-render", o->no_render, "Do not render drape.png");
    sub->callback([o, &exit_code] { exit_code = run_cusick(*o); });
}

}  // namespace woven::cli
