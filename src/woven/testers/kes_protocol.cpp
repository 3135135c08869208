// The KES protocol (kes_protocol.hpp).
#include "woven/testers/kes_protocol.hpp"

#include <algorithm>
#include <cmath>

#include "woven/testers/elastica.hpp"

namespace woven::testers {

namespace {

/// Peak RSS of `kes-test cotton --test shear --direction warp` at --sigma-cm 0.25 (1,701
/// particles, 30.8 MB) and 0.1 (10,251 particles, 129.7 MB), /usr/bin/time -v, through
/// base + per_particle_log * n log2(n).
constexpr double kTesterRssBaseBytes = 15.5e6;
constexpr double kTesterRssPerParticleLogBytes = 836;

/// The word on the wait: the share of (test, direction) runs done and the Newton iterations of
/// the one running.
struct Units {
    Units(const KesProgress& progress, int count) : on_progress(progress), units(count) {}
    const KesProgress& on_progress;
    int units = 1, done = 0, iterations = 0;
    std::string running;

    void begin(const std::string& what)
    {
        running = what;
        iterations = 0;
        if (on_progress) on_progress(double(done) / units, running);
    }
    std::function<void()> on_iteration()
    {
        if (!on_progress) return {};
        return [this] { on_progress(double(done) / units, running + ", iteration " + std::to_string(++iterations)); };
    }
};

}  // namespace

double shape_error(const CantileverShape& sim, const ElasticaSolution& el, double clamp_z)
{
    double e = 0;
    for (std::size_t a = 2; a < sim.z.size(); ++a) {
        const double s = (static_cast<double>(a) - 0.5) * sim.sigma;
        const double t = std::min(s, el.s.back()) / el.s.back() * (el.s.size() - 1);
        const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(t), el.s.size() - 2);
        const double f = t - k;
        const double z_el = el.z[k] + f * (el.z[k + 1] - el.z[k]);
        e = std::max(e, std::abs((sim.z[a] - clamp_z) - z_el) / el.tip_drop);
    }
    return e;
}

CantileverConvergence cantilever_convergence(const kes::FabricData& fabric, Direction d, const CantileverOptions& base,
                                             const model::ModelOptions& mo)
{
    const double g = mo.gravity > 0 ? mo.gravity : units::kStandardGravity;
    const double w = weight_per_area(fabric, g);
    const CurvatureOfMoment law = fabric_curvature_law(fabric, d, model::BendingForm::WORK, mo.gram_force);
    const double c = 0.5 * elastica_overhang_for_chord_angle(kPeirceChordAngle, w, law);
    CantileverConvergence study{d, c, {}};
    for (double ratio : {1.0, 1.5, 2.0, 2.5, 3.0}) {
        const double L = ratio * c;
        const ElasticaSolution el = cantilever_elastica(L, w, law);
        const double c_exact = bending_length_from_chord(L, el.chord_angle);
        double prev_err = 0, prev_sigma = 0;
        for (int level = 0; level < 3; ++level) {
            CantileverOptions o = base;
            o.sigma = base.sigma / (1 << level);
            const CantileverShape sh = cantilever_at_overhang(fabric, d, L, o);
            const double c_sim = bending_length_from_chord(L, sh.chord_angle);
            const double err = (c_sim - c_exact) / c_exact;
            double order = NAN;
            if (level > 0 && err != 0 && prev_err != 0) order = std::log(std::abs(prev_err / err)) / std::log(prev_sigma / sh.sigma);
            ConvergencePoint p{ratio, sh.sigma, c_sim, c_exact, err, std::nullopt};
            if (std::isfinite(order)) p.order = order;
            study.points.push_back(p);
            prev_err = err;
            prev_sigma = sh.sigma;
        }
    }
    return study;
}

KesTestRow kes_row(const CantileverResult& r, units::GramForce gram_force)
{
    const double gf_cm2_per_cm = units::newton_per_gram_force(gram_force) * units::kCmToM;  // N m per gf.cm2/cm
    KesTestRow row;
    row.test = "cantilever";
    row.direction = to_string(r.direction);
    row.unit = "gf.cm2/cm";
    row.sigma_m = r.shape.sigma;
    row.input = r.elastica_flexural_rigidity / gf_cm2_per_cm;
    row.simulated = r.flexural_rigidity / gf_cm2_per_cm;
    row.rel = (r.bending_length - r.elastica_bending_length) / r.elastica_bending_length;
    row.curve = shape_error(r.shape, r.elastica, 0.5 * (r.shape.z[0] + r.shape.z[1]));
    row.bending_length_m = r.bending_length;
    row.elastica_bending_length_m = r.elastica_bending_length;
    row.solves_or_iterations = r.solves;
    return row;
}

KesTestRow kes_row(const KesCurveResult& r, const std::string& unit)
{
    KesTestRow row;
    row.test = r.test;
    row.direction = to_string(r.direction);
    row.unit = unit;
    row.sigma_m = r.sigma;
    row.input = r.input_summary;
    row.simulated = r.simulated_summary;
    row.rel = r.summary_rel_error;
    row.curve = r.curve_max_rel_error;
    row.solves_or_iterations = r.iterations;
    if (!r.y_central.empty()) {
        row.central = r.central_summary;
        row.central_rel = r.central_rel_error;
    }
    if (r.loop)
        row.loop = KesLoopRow{r.hysteresis5_at > 0,      r.input_hysteresis,     r.simulated_hysteresis, r.input_hysteresis5,
                              r.simulated_hysteresis5,   r.hysteresis_rel_error, r.loop_max_rel_error};
    return row;
}

KesProtocolResult run_kes_tests(const kes::FabricData& fabric, const KesProtocolOptions& options, const KesProgress& on_progress)
{
    const int n_dirs = static_cast<int>(options.directions.size());
    Units u(on_progress, (int(options.cantilever) + int(options.bending) + int(options.shear) + int(options.convergence)) * n_dirs);
    KesProtocolResult result;
    if (options.cantilever) {
        CantileverOptions co;
        co.sigma = options.sigma.value_or(kKesCantileverSpacing);
        co.model = options.model;
        co.solve.on_iteration = u.on_iteration();
        for (Direction d : options.directions) {
            u.begin("cantilever " + to_string(d));
            result.cantilever.push_back(cantilever_test(fabric, d, co));
            ++u.done;
            result.rows.push_back(kes_row(result.cantilever.back(), options.model.gram_force));
        }
    }
    if (options.bending) {
        BendingTestOptions bo;
        bo.sigma = options.sigma.value_or(kKesBendingSpacing);
        bo.model = options.model;
        bo.solve.on_iteration = u.on_iteration();
        for (Direction d : options.directions) {
            u.begin("bending " + to_string(d));
            result.bending.push_back(kes_bending_test(fabric, d, bo));
            ++u.done;
        }
        for (const auto& r : result.bending) result.rows.push_back(kes_row(r, "gf.cm2/cm"));
    }
    if (options.shear) {
        ShearTestOptions so;
        so.sigma = options.sigma.value_or(kKesShearSpacing);
        so.length = options.shear_length;
        so.model = options.model;
        so.solve.on_iteration = u.on_iteration();
        for (Direction d : options.directions) {
            u.begin("shear " + to_string(d));
            result.shear.push_back(kes_shear_test(fabric, d, so));
            ++u.done;
        }
        for (const auto& r : result.shear) result.rows.push_back(kes_row(r, "gf/(cm.deg)"));
    }
    if (options.convergence) {
        CantileverOptions co;
        co.sigma = options.sigma.value_or(kKesConvergenceSpacing);
        co.model = options.model;
        co.solve.on_iteration = u.on_iteration();
        for (Direction d : options.directions) {
            u.begin("convergence " + to_string(d));
            result.convergence.push_back(cantilever_convergence(fabric, d, co, options.model));
            ++u.done;
        }
    }
    return result;
}

KesSpecimenSizes kes_specimen_sizes(const kes::FabricData& fabric, const KesProtocolOptions& options)
{
    KesSpecimenSizes n;
    auto rounded = [](double v) { return static_cast<long long>(std::llround(v)); };
    if (options.shear) {
        const double s = options.sigma.value_or(kKesShearSpacing);
        const double gap = ShearTestOptions{}.gap;
        const long long N = std::max(2LL, rounded(gap / s));
        n.shear = (N + 1) * std::max(2LL, rounded(options.shear_length / (gap / N)) + 1);
    }
    if (options.bending) {
        const BendingTestOptions b;
        const double s = options.sigma.value_or(kKesBendingSpacing);
        const long long span = std::max(3LL, rounded(b.gap / s));
        n.bending = (span + 2) * std::max(2LL, rounded(b.width / (b.gap / span)) + 1);
    }
    if (options.cantilever) {
        const double W = fabric.areal_density_mg_cm2;
        const double c_m = std::cbrt(std::max(input_B(fabric, Direction::WARP), input_B(fabric, Direction::WEFT)) / (W * 1e-3)) * units::kCmToM;
        double s = options.sigma.value_or(kKesCantileverSpacing);
        if (options.convergence) s = options.sigma.value_or(kKesConvergenceSpacing) / 4;
        const double w = CantileverOptions{}.width;
        if (std::isfinite(c_m)) n.cantilever = std::max(3LL, rounded(3 * c_m / s)) * std::max(2LL, rounded(w / s) + 1);
    }
    return n;
}

sim::MemoryEstimate estimate_tester_memory(long long particles)
{
    return sim::estimate_solve_memory(particles, kTesterRssBaseBytes, kTesterRssPerParticleLogBytes, 1);
}

}  // namespace woven::testers
