#pragma once
// The fit job (woven fit, woven.fit): the paper's Sec. 5.1 fit of a fabric's KES curves and the
// bending and trellis energy functions built from them (Sec. 5.2-5.4), written as plots, CSV
// tables and report.json (one output set).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/units.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/kes/fit.hpp"
#include "woven/render/instrument_plots.hpp"

namespace woven::app {

/// The particle spacings the energy tables may be made for, cm: from drape's smallest (1e-4 m,
/// io::kMinSigma_m) to 1 m; outside, the energy functions are not numbers (1e-160 gave NaN).
inline constexpr double kFitSigmaRange_cm[2] = {io::kMinSigma_m * units::kMToCm, 100};

struct FitRequest {
    std::string fabric;                        ///< a built-in fabric name or a fabric .toml file
    GivenFabric given_fabric;                  ///< a fabric given as data instead (Python's woven.Fabric)
    double sigma_cm = 2;                       ///< the spacing of the energy tables (--sigma-cm), kFitSigmaRange_cm
    std::optional<std::filesystem::path> out;  ///< absent: out/fit-<name>
    /// Gets the fabric's warnings once it is read (before the fit).
    std::function<void(const std::vector<std::string>&)> on_warnings;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    Monitor monitor;
};

struct FitResult {
    nlohmann::json report;  ///< report.json as written (with its `files`)
    std::string summary;    ///< each curve's fit and the trellis continuation, one line each
    std::string out_dir;    ///< the folder written
    int files = 0;          ///< files written, report.json included
};

/// Fits, checks every number, then writes the set (report.json last). InputError for a bad
/// request or fabric (fitting errors name the fabric's file); nothing is written then.
FitResult fit(const FitRequest& request);

/// The KES curve `data` and `fit` at n + 1 evenly spaced x over [0, the end of the data or the
/// fit's], with the fit's segment junctions when asked (render::curve_fit_plot's title,
/// labels and colour left to the caller).
render::CurveFitView curve_fit_view(const kes::Curve& data, const kes::CurveFit& fit, int n, bool junctions);

}  // namespace woven::app
