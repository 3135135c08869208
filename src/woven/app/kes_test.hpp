#pragma once
// The kes-test job (woven kes-test, woven.kes_test): the virtual instruments (testers/) run on
// the model: the cantilever (ASTM D1388), KES-FB2 pure bending and KES-FB1 shear, each a static
// simulation of a specimen of the model's particles, against the fabric's input values; their
// curves (CSV), plots and kes-report.json written as one output set.
#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/choice.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/kes_protocol.hpp"
#include "woven/testers/specimen.hpp"

namespace woven::app {

/// --test: which instruments run.
enum class KesTests { CANTILEVER, BENDING, SHEAR, ALL };
inline constexpr std::array<Named<KesTests>, 4> kKesTestsNames{
    {{KesTests::CANTILEVER, "cantilever"}, {KesTests::BENDING, "bending"}, {KesTests::SHEAR, "shear"}, {KesTests::ALL, "all"}}};
/// --direction: the specimens' directions.
enum class KesDirections { WARP, WEFT, BOTH };
inline constexpr std::array<Named<KesDirections>, 3> kKesDirectionsNames{
    {{KesDirections::WARP, "warp"}, {KesDirections::WEFT, "weft"}, {KesDirections::BOTH, "both"}}};
/// --bending-form's names.
inline constexpr std::array<Named<model::BendingForm>, 2> kBendingFormNames{
    {{model::BendingForm::WORK, "work"}, {model::BendingForm::SECANT, "secant"}}};

/// The limits of the request's spacings, cm.
inline constexpr double kKesSigmaRange_cm[2] = {0.02, 2.0};          ///< --sigma-cm
inline constexpr double kKesShearLengthRange_cm[2] = {5, 200};        ///< --shear-length-cm

struct KesTestRequest {
    std::string fabric;                  ///< a built-in fabric name or a fabric .toml file
    GivenFabric given_fabric;            ///< a fabric given as data instead (Python's woven.Fabric)
    KesTests tests = KesTests::ALL;
    KesDirections directions = KesDirections::BOTH;
    std::optional<double> sigma_cm;      ///< the specimens' spacing (default: cantilever 0.25, bending 0.1, shear 0.25)
    std::optional<double> shear_length_cm;  ///< the FB1 specimen's length (default the instrument's 20)
    std::optional<model::BendingForm> bending_form;        ///< default: the model's
    std::optional<model::Discretization> discretization;   ///< default: the model's
    std::optional<model::ShearLaw> shear_law;              ///< default: the model's (deembedded)
    std::optional<model::Hysteresis> hysteresis;           ///< default here: friction (full loops)
    int threads = 0;                     ///< oneTBB, OpenMP and BLAS threads (0: all cores), at most io::kMaxThreads
    std::optional<std::filesystem::path> out;  ///< absent: out/kes-<name>
    bool convergence = false;            ///< also the cantilever's grid convergence study
    /// Gets the fabric's warnings once it is read (before any test runs).
    std::function<void(const std::vector<std::string>&)> on_warnings;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    Monitor monitor;
};

/// The summary rows (testers/kes_protocol.hpp).
using KesLoopRow = testers::KesLoopRow;
using KesTestRow = testers::KesTestRow;

/// The cantilever's convergence study in one direction (kes-report.json's
/// cantilever_convergence rows: overhang_ratio, sigma_m, bending_length_m,
/// elastica_bending_length_m, rel_error, order).
struct KesConvergence {
    std::string direction;
    double bending_length_m = 0;  ///< c of the elastica at the 41.5 degree chord
    nlohmann::json rows;
};

struct KesTestResult {
    std::string fabric_name;
    model::ModelOptions model;  ///< the model the specimens were made of (shear_scale resolved)
    std::vector<KesTestRow> rows;
    std::vector<KesConvergence> convergence;
    nlohmann::json report;      ///< kes-report.json as written (with its `files`)
    std::string out_dir;
    int files = 0;              ///< files written, kes-report.json included
};

/// Checks the request (every value, then the fabric, the memory of the largest specimen and the
/// output folder) before anything runs or is written, runs the tests and writes the set,
/// kes-report.json last. Progress: an Activity ("kes-test <name>").
KesTestResult kes_test(const KesTestRequest& request);

}  // namespace woven::app
