#pragma once
// The KES protocol (woven kes-test): which instruments run on which specimens, in which order,
// and the summary each gives: the cantilever (cantilever.hpp), KES-FB2 pure bending
// (kes_bending.hpp) and KES-FB1 shear (kes_shear.hpp) in the warp and weft directions, and the
// cantilever's grid convergence study; the specimens' sizes for a memory estimate.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "woven/common/units.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/resources.hpp"
#include "woven/testers/cantilever.hpp"
#include "woven/testers/kes_bending.hpp"
#include "woven/testers/kes_shear.hpp"
#include "woven/testers/specimen.hpp"

namespace woven::testers {

/// The protocol's default spacings (m): the cantilever, FB2 bending, FB1 shear, and the
/// convergence study's coarsest (then halved twice).
inline constexpr double kKesCantileverSpacing = 0.25 * units::kCmToM;
inline constexpr double kKesBendingSpacing = 0.1 * units::kCmToM;
inline constexpr double kKesShearSpacing = 0.25 * units::kCmToM;
inline constexpr double kKesConvergenceSpacing = 2 * 0.25 * units::kCmToM;

/// What runs and on what.
struct KesProtocolOptions {
    bool cantilever = true, bending = true, shear = true;
    bool convergence = false;  ///< the cantilever's convergence study (after the tests)
    std::vector<Direction> directions{Direction::WARP, Direction::WEFT};
    std::optional<double> sigma;               ///< every specimen's spacing, m (absent: the defaults above)
    double shear_length = ShearTestOptions{}.length;  ///< the FB1 specimen's length, m
    model::ModelOptions model;                 ///< the model the specimens are made of
};

/// A friction loop's widths (bending: 2HB; shear: 2HG and 2HG5), input and simulated.
struct KesLoopRow {
    bool shear = false;
    double input_hysteresis = 0, simulated_hysteresis = 0;    ///< 2HB (gf.cm/cm) or 2HG (gf/cm)
    double input_hysteresis5 = 0, simulated_hysteresis5 = 0;  ///< shear: 2HG5 (gf/cm)
    double hysteresis_rel_error = 0, loop_max_rel_error = 0;
};

/// One test in one direction: the input and simulated summary values (KES units: B in
/// gf.cm2/cm, G in gf/(cm.deg)).
struct KesTestRow {
    std::string test, direction, unit;
    double sigma_m = 0, input = 0, simulated = 0, rel = 0, curve = 0;
    std::optional<double> bending_length_m, elastica_bending_length_m;  ///< cantilever
    std::optional<double> central, central_rel;  ///< shear: the middle half of the clamp (kes_shear.hpp)
    int solves_or_iterations = 0;
    std::optional<KesLoopRow> loop;  ///< bending, shear with a loop run (friction)
};

/// One spacing of one overhang of the cantilever's convergence study.
struct ConvergencePoint {
    double overhang_ratio = 0;           ///< L / c
    double sigma = 0;                    ///< the spacing used, m
    double bending_length = 0;           ///< of the simulated strip, m
    double elastica_bending_length = 0;  ///< of the exact elastica, m
    double rel_error = 0;
    std::optional<double> order;         ///< observed order against the previous spacing (absent at the first, or undefined)
};

/// The cantilever's convergence study in one direction.
struct CantileverConvergence {
    Direction direction = Direction::WARP;
    double bending_length = 0;  ///< c of the elastica at the 41.5 degree chord, m
    std::vector<ConvergencePoint> points;
};

/// Everything the protocol measured, each list in the order of options.directions.
struct KesProtocolResult {
    std::vector<CantileverResult> cantilever;
    std::vector<KesCurveResult> bending, shear;
    std::vector<CantileverConvergence> convergence;
    std::vector<KesTestRow> rows;  ///< the summary: cantilever, bending, shear rows
};

/// Progress: the share of (test, direction) runs done and what runs ("shear warp, iteration 3").
using KesProgress = std::function<void(double fraction, const std::string& what)>;

/// Runs the protocol: the cantilevers, then bending, then shear, then the convergence study.
KesProtocolResult run_kes_tests(const kes::FabricData& fabric, const KesProtocolOptions& options, const KesProgress& on_progress = {});

/// Shape error of a simulated strip against the elastica: max |z_sim - z_el(s)| over the strip's
/// rows (rows 2 ..), heights from clamp_z, relative to the elastica's tip drop.
double shape_error(const CantileverShape& sim, const ElasticaSolution& el, double clamp_z);

/// The cantilever's convergence study: at overhangs L/c = 1 .. 3 (c the elastica's bending
/// length), the bending length from the tip chord angle (converted with the linear elastica,
/// bending_length_from_chord) of the simulated strip and of the exact elastica of the input
/// curve, at spacings S, S/2, S/4 (S = base.sigma); the observed order between successive ones.
CantileverConvergence cantilever_convergence(const kes::FabricData& fabric, Direction d, const CantileverOptions& base,
                                             const model::ModelOptions& mo);

/// The summary row of a cantilever test; of bending or shear results (`unit`: their B or G unit).
KesTestRow kes_row(const CantileverResult& r, units::GramForce gram_force);
KesTestRow kes_row(const KesCurveResult& r, const std::string& unit);

/// Particles of the largest specimen of each test the options run (0: not run or not
/// estimable), as the testers lay them out: the cantilever's overhang taken as three Peirce
/// bending lengths (B / W)^(1/3) (its 41.5 degree chord is near two), its convergence study at a
/// quarter of its coarsest spacing.
struct KesSpecimenSizes {
    long long cantilever = 0, bending = 0, shear = 0;
};
KesSpecimenSizes kes_specimen_sizes(const kes::FabricData& fabric, const KesProtocolOptions& options);

/// Estimated peak memory (bytes) of a virtual instrument's static solve on a specimen of
/// `particles` particles, one thread: sim::estimate_solve_memory fitted to kes-test's own peaks
/// (docs/RELIABILITY.md).
sim::MemoryEstimate estimate_tester_memory(long long particles);

}  // namespace woven::testers
