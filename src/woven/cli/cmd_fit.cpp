// woven fit FABRIC: the options as a fit request (app/fit.hpp), its summary printed.
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "woven/app/fit.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"

namespace woven::cli {

int run_fit(const FitOptions& options)
{
    FitRequest request;
    request.fabric = options.fabric;
    request.given_fabric = options.given_fabric;
    request.sigma_cm = parse_number(options.sigma_cm, "--sigma-cm", kFitSigmaRange_cm[0], kFitSigmaRange_cm[1]);
    if (options.out) request.out = parse_path(*options.out, "--out");
    request.on_warnings = print_warnings;
    const FitResult result = fit(request);
    std::cout << result.summary << "wrote " << result.files << " files to " << result.out_dir << "\n";
    return kExitOk;
}

void add_fit_command(CLI::App& app, int& exit_code)
{
    auto options = std::make_shared<FitOptions>();
    CLI::App* sub = app.add_subcommand("fit", "Fit a fabric's KES curves and plot the energies built from them");
    sub->footer("Fits the bending (warp, weft) and shear curves as the paper's Sec. 5.1 does and writes to --out: "
                "<curve>_fit.png (data, fit, segment junctions), bending_{warp,weft}_energy.{png,csv} (B(theta), J) "
                "and trellis_energy.{png,csv} (T(phi), J). Prints the fitted segments.");
    sub->add_option("FABRIC", options->fabric, "A built-in fabric name (see `woven fabrics`) or a fabric .toml file")
        ->required();
    sub->add_option("--out", options->out, "Output directory (default out/fit-<name>)");
    sub->add_option("--sigma-cm", options->sigma_cm, "Particle spacing sigma for the energy tables, cm (drape's smallest spacing to 1 m)")
        ->capture_default_str()
        ->type_name(number_type(kFitSigmaRange_cm[0], kFitSigmaRange_cm[1]));
    sub->callback([options, &exit_code] { exit_code = run_fit(*options); });
}

}  // namespace woven::cli
