// woven kes-test FABRIC: the options as a kes-test request (app/kes_test.hpp); the table of
// input vs simulated values printed.
#include <cstdarg>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "woven/app/kes_test.hpp"
#include "woven/app/material.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::cli {

namespace {

/// printf into std::cout, not C's stdout.
[[gnu::format(printf, 1, 2)]] void print_out(const char* format, ...)
{
    char line[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(line, sizeof line, format, args);
    va_end(args);
    std::cout << line;
}

KesTestRequest kes_test_request(const KesTestOptions& options)
{
    KesTestRequest r;
    r.fabric = options.fabric;
    r.given_fabric = options.given_fabric;
    r.tests = parse_choice(options.test, "--test", kKesTestsNames);
    if (options.convergence && r.tests != KesTests::ALL && r.tests != KesTests::CANTILEVER)
        throw InputError(kCommandLine, "--convergence", "expected --test cantilever or all (a study of the cantilever test)");
    r.convergence = options.convergence;
    r.directions = parse_choice(options.direction, "--direction", kKesDirectionsNames);
    if (options.sigma_cm) r.sigma_cm = parse_number(*options.sigma_cm, "--sigma-cm", kKesSigmaRange_cm[0], kKesSigmaRange_cm[1]);
    if (options.shear_length_cm)
        r.shear_length_cm = parse_number(*options.shear_length_cm, "--shear-length-cm", kKesShearLengthRange_cm[0], kKesShearLengthRange_cm[1]);
    if (options.bending_form) r.bending_form = parse_choice(*options.bending_form, "--bending-form", kBendingFormNames);
    if (options.discretization) r.discretization = parse_choice(*options.discretization, "--discretization", model::kDiscretizationNames);
    if (options.shear_law) r.shear_law = parse_shear_law(*options.shear_law, "--shear-law");
    if (options.hysteresis) r.hysteresis = parse_hysteresis(*options.hysteresis, "--hysteresis");
    if (options.out) r.out = parse_path(*options.out, "--out");
    if (options.threads) r.threads = static_cast<int>(*parse_integer(options.threads, "--threads", 0, io::kMaxThreads));
    r.on_warnings = print_warnings;
    return r;
}

void print_convergence(const KesConvergence& c)
{
    print_out("cantilever convergence, %s: c = %.5g cm (elastica, 41.5 degree chord)\n", c.direction.c_str(),
              c.bending_length_m * units::kMToCm);
    print_out("%6s %10s %12s %12s %10s %7s\n", "L/c", "sigma_cm", "c_sim_cm", "c_exact_cm", "rel_err", "order");
    for (const auto& row : c.rows) {
        const double order = row["order"].is_null() ? NAN : row["order"].get<double>();
        print_out("%6.2f %10.5g %12.6g %12.6g %+9.4f%% %7.3g\n", row["overhang_ratio"].get<double>(),
                  row["sigma_m"].get<double>() * units::kMToCm, row["bending_length_m"].get<double>() * units::kMToCm,
                  row["elastica_bending_length_m"].get<double>() * units::kMToCm, 100 * row["rel_error"].get<double>(), order);
    }
}

void print_table(const KesTestResult& result)
{
    std::cout << "fabric " << result.fabric_name << " (bending form " << (result.model.bending_form == model::BendingForm::WORK ? "work" : "secant")
              << ", discretization " << model::to_string(result.model.discretization) << ", "
              << shear_law_text(result.model) << ", hysteresis " << model::to_string(result.model.hysteresis) << ")\n";
    print_out("%-10s %-5s %8s %12s %12s %9s %9s  %s\n", "test", "dir", "sigma_cm", "input", "simulated", "rel_err", "curve_err", "unit");
    for (const KesTestRow& r : result.rows) {
        print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %8.4f%%  %s\n", r.test.c_str(), r.direction.c_str(), r.sigma_m * units::kMToCm,
                    r.input, r.simulated, 100 * r.rel, 100 * r.curve, r.unit.c_str());
        if (r.central)
            print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %9s  %s\n", "  centre", r.direction.c_str(), r.sigma_m * units::kMToCm, r.input,
                        *r.central, 100 * *r.central_rel, "", r.unit.c_str());
        if (r.loop) {
            const KesLoopRow& l = *r.loop;
            const bool shear = l.shear;
            print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %8.4f%%  %s\n", shear ? "  2HG" : "  2HB", r.direction.c_str(),
                        r.sigma_m * units::kMToCm, l.input_hysteresis, l.simulated_hysteresis,
                        100 * (l.simulated_hysteresis - l.input_hysteresis) / l.input_hysteresis, 100 * l.loop_max_rel_error,
                        shear ? "gf/cm" : "gf.cm/cm");
            if (shear)
                print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %9s  %s\n", "  2HG5", r.direction.c_str(), r.sigma_m * units::kMToCm,
                            l.input_hysteresis5, l.simulated_hysteresis5, 100 * (l.simulated_hysteresis5 - l.input_hysteresis5) / l.input_hysteresis5,
                            "", "gf/cm");
        }
    }
    std::cout << "cantilever: input = the exact elastica's flexural rigidity W g c^3 for the input curve, rel_err = bending length vs the "
                 "elastica's, curve_err = largest shape difference / tip drop; bending, shear: input = the file's B, G (or its curve's KES "
                 "slope), curve_err = largest relative difference from the input curve over 0.5..2.5 1/cm, 0.5..8 deg; shear centre: the middle "
                 "half of the moving clamp, away from the specimen's free short edges (the material's law); 2HB, 2HG, 2HG5 (friction): the "
                 "loop's widths at 1 1/cm, 0.5 and 5 deg, simulated (B, G: the loop's mean branch slope), curve_err = the loop's largest "
                 "difference from the input loop / its amplitude\n";

}

}  // namespace

int run_kes_test(const KesTestOptions& options)
{
    const KesTestResult result = kes_test(kes_test_request(options));
    for (const KesConvergence& c : result.convergence) print_convergence(c);
    print_table(result);
    std::cout << "wrote " << result.files << " files to " << result.out_dir << "\n";
    return kExitOk;
}

void add_kes_test_command(CLI::App& app, int& exit_code)
{
    auto options = std::make_shared<KesTestOptions>();
    CLI::App* sub = app.add_subcommand("kes-test", "Run the virtual cantilever, KES-FB2 bending and KES-FB1 shear tests on the model");
    sub->footer("Each test is a static simulation of a specimen of the model's particles (docs/VALIDATION.md says how each maps onto the "
                "grid). Prints input vs simulated summary values and writes to --out (default out/kes-<name>): <test>_<direction>.csv, "
                "cantilever.png, bending.png, shear.png and kes-report.json (list 'tests': test, direction, sigma_m, input_summary, "
                "simulated_summary, summary_rel_error, curve_max_rel_error; cantilever also bending_length_m, elastica_bending_length_m; shear also central_summary, central_rel_error: the middle half of the clamp, away from the free short edges; bending and shear also "
                "input_hysteresis and simulated_hysteresis ({\"2HB\": gf.cm/cm} or {\"2HG\", \"2HG5\": gf/cm}), hysteresis_rel_error (the worst) and "
                "loop_max_rel_error, null without a loop). With --hysteresis friction (the default) bending and shear run full loops "
                "(0 -> +2.5 -> -2.5 -> 0 1/cm, 0 -> +8 -> -8 -> 0 degrees) for the curves given with a hysteresis width: <test>_loop_<direction>.csv "
                "and <test>_loop.png. The files are one set: "
                "kes-report.json is written last and names every file with its size and SHA-256; files of an earlier run's other tests are removed.");
    sub->add_option("FABRIC", options->fabric, "A built-in fabric name (see `woven fabrics`) or a fabric .toml file")->required();
    sub->add_option("--test", options->test, "cantilever, bending, shear or all")
        ->capture_default_str()
        ->type_name(choice_type(kKesTestsNames));
    sub->add_option("--direction", options->direction, "warp, weft or both")
        ->capture_default_str()
        ->type_name(choice_type(kKesDirectionsNames));
    sub->add_option("--sigma-cm", options->sigma_cm,
                    "Particle spacing of the specimens, cm (default: cantilever 0.25, bending 0.1, shear 0.25)")
        ->type_name(number_type(kKesSigmaRange_cm[0], kKesSigmaRange_cm[1]));
    sub->add_option("--shear-length-cm", options->shear_length_cm,
                    "FB1 specimen length along the clamps, cm (default 20, the instrument's; longer shows the free ends' effect on G)")
        ->type_name(number_type(kKesShearLengthRange_cm[0], kKesShearLengthRange_cm[1]));
    sub->add_option("--bending-form", options->bending_form, "work or secant (default: the model's, work)")
        ->type_name(choice_type(kBendingFormNames));
    sub->add_option("--discretization", options->discretization, "convergent or paper (default: the model's, convergent)")
        ->type_name(choice_type(model::kDiscretizationNames));
    sub->add_option(
           "--shear-law", options->shear_law,
           "deembedded (the material's law, raised by the FB1 specimen's end effect: the default) or measured (the input curve as read)")
        ->type_name(choice_type(model::kShearLawNames));
    sub->add_option("--hysteresis", options->hysteresis,
                    "friction (the default here: the mean line plus friction elements, full KES loops) or loading-branch (the loading "
                    "branch as an elastic energy, the loading sweep only)")
        ->type_name(choice_type(model::kHysteresisNames));
    sub->add_option("--threads", options->threads, "Worker threads: oneTBB, OpenMP and the BLAS (0: all cores, the default)")
        ->type_name(int_type(0, io::kMaxThreads));
    sub->add_option("--out", options->out, "Output directory (default out/kes-<name>)");
    sub->add_flag("--convergence", options->convergence,
                  "Also the cantilever's grid convergence: bending length vs the exact elastica at L/c = 1..3 and spacings S, S/2, S/4 "
                  "(S = --sigma-cm, default 0.5), with the observed order (in kes-report.json: cantilever_convergence)");
    sub->callback([options, &exit_code] { exit_code = run_kes_test(*options); });
}

}  // namespace woven::cli
