#include "woven/testers/cusick.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <Eigen/Geometry>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/geometry/primitives.hpp"

namespace woven::testers {

namespace {

constexpr const char* kSource = "cusick";
/// Floor below the lowest point the hanging part can reach (m).
constexpr double kFloorClearance = 0.10;
/// Most particles in the grid (a 30 cm specimen at 0.5 mm): beyond, a run would not end.
constexpr double kMaxParticles = 400000;
/// Angular modes of the seeded start's waviness (1 .. this).
constexpr int kPerturbationModes = 12;

/// Uniform in [0, 1) from a mt19937_64 draw, the same on every platform.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

/// Turns each point about the z axis by `deg` degrees (counter-clockwise seen from above).
template <class Points> void turn_about_z(Points& points, double deg)
{
    if (deg == 0) return;
    const Eigen::Rotation2Dd turn(deg * units::kDegToRad);
    for (Vec3& p : points) p.head<2>() = turn * Vec2(p.head<2>());
}

std::string num(double v)
{
    std::ostringstream s;
    s << v;
    return s.str();
}

/// The instrument's obstacles: floor, pedestal, support disc (top at disc_top_z) and, DISCS, the
/// clamp disc (underside at clamp_bottom_z).
void add_instrument(geometry::ObstacleSet& set, const CusickOptions& o, double disc_top_z, double clamp_bottom_z)
{
    const double R = 0.5 * o.specimen_diameter_m, rd = 0.5 * o.disc_diameter_m;
    set.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ(), 4 * R));
    set.add(std::make_unique<geometry::Cylinder>(Vec3::Zero(), o.pedestal_radius_m, disc_top_z - o.disc_thickness_m));
    set.add(std::make_unique<geometry::Cylinder>(Vec3(0, 0, disc_top_z - o.disc_thickness_m), rd, o.disc_thickness_m));
    // The clamp disc: radius r_d, its underside clamp_gap_m above the support's top; the rims of
    // both are true circles (the cylinders' exact distance fields).
    if (o.clamp == CusickClamp::DISCS) set.add(std::make_unique<geometry::Cylinder>(Vec3(0, 0, clamp_bottom_z), rd, o.disc_thickness_m));
}

}  // namespace

const char* clamp_name(CusickClamp clamp) { return name_of(kCusickClampNames, clamp); }

const char* protocol_name(CusickProtocol protocol) { return name_of(kCusickProtocolNames, protocol); }

double lower_step_m(const CusickOptions& o)
{
    if (o.lower_step_m > 0) return o.lower_step_m;
    const double overhang = 0.5 * (o.specimen_diameter_m - o.disc_diameter_m);
    return std::min(std::max(kCusickLowerStep, 2 * o.spacing_m), overhang);
}

CusickSetup make_cusick_setup(const CusickOptions& o)
{
    const double R = 0.5 * o.specimen_diameter_m, rd = 0.5 * o.disc_diameter_m, s = o.spacing_m;
    if (!std::isfinite(R) || !(R > 0)) throw InputError(kSource, "specimen_diameter_m", "expected a positive diameter in m");
    if (!std::isfinite(rd) || !(rd > 0) || !(rd < R))
        throw InputError(kSource, "disc_diameter_m", "expected a positive diameter below the specimen's (" + num(2 * R) + " m)");
    if (!std::isfinite(s) || !(s > 0) || !(R - rd >= 2 * s) || !(2 * R >= 8 * s))
        throw InputError(kSource, "spacing_m",
                         "expected a positive spacing of at most a half of the overhang (" + num(0.5 * (R - rd))
                             + " m) and an eighth of the specimen");
    if (std::pow(2 * R / s, 2) > kMaxParticles)
        throw InputError(kSource, "spacing_m", "expected a spacing above " + num(2 * R / std::sqrt(kMaxParticles)) + " m");
    if (!std::isfinite(o.perturbation_m) || o.perturbation_m < 0 || o.perturbation_m >= 0.25 * (R - rd))
        throw InputError(kSource, "perturbation_m", "expected 0 or more, below a quarter of the overhang");
    if (!(o.disc_thickness_m > 0) || !(o.pedestal_radius_m > 0) || !(o.pedestal_radius_m <= rd))
        throw InputError(kSource, "disc_thickness_m", "expected a positive disc thickness and a pedestal no wider than the disc");
    if (!std::isfinite(o.lower_step_m) || o.lower_step_m < 0 || (o.lower_step_m > 0 && !(o.lower_step_m >= s && o.lower_step_m <= R - rd)))
        throw InputError(kSource, "lower_step_m", "expected 0 (automatic) or a plate step of at least the spacing and at most the overhang (" + num(R - rd) + " m)");
    if (o.shakes < 0 || o.shakes > 100 || !(o.shake_amplitude > 0 && o.shake_amplitude < 1))
        throw InputError(kSource, "shakes", "expected 0 to 100 shakes of an amplitude between 0 and 1 g");
    if (!std::isfinite(o.grid_rotation_deg) || std::abs(o.grid_rotation_deg) > 360)
        throw InputError(kSource, "grid_rotation_deg", "expected an angle between -360 and 360 degrees");
    if (!std::isfinite(o.clamp_margin) || std::abs(o.clamp_margin) > 2)
        throw InputError(kSource, "clamp_margin", "expected a margin between -2 and 2 spacings");
    const bool discs = o.clamp == CusickClamp::DISCS;
    const double d_hat = o.solver.contact_distance, disc_gap = o.clamp_gap_m > 0 ? o.clamp_gap_m : kCusickDiscsGap * d_hat;
    if (!std::isfinite(o.clamp_gap_m) || o.clamp_gap_m < 0 || o.clamp_gap_m > d_hat)
        throw InputError(kSource, "clamp_gap_m", "expected 0 (the default) or a gap up to the contact distance (" + num(d_hat) + " m)");
    if (discs && !(d_hat > 0)) throw InputError(kSource, "contact_distance", "expected a positive contact distance (the discs' gap)");
    if (discs && (o.start_gap_m < 0 || o.start_gap_m >= disc_gap))
        throw InputError(kSource, "start_gap_m", "expected 0 (half the gap) or a height below the discs' gap (" + num(disc_gap) + " m)");
    if (discs && !(rd - kCusickDiscsPinnedInset * s > 0))
        throw InputError(kSource, "spacing_m", "expected a spacing below " + num(rd / kCusickDiscsPinnedInset) + " m (the discs clamp's pinned core)");

    CusickSetup c;
    // An odd number of particles a side (one at the centre), covering the specimen and one
    // particle beyond it all round.
    const int n = 2 * static_cast<int>(std::ceil(R / s)) + 3;
    c.grid.nu = c.grid.nv = n;
    c.grid.sigma = s;
    c.outline.kind = model::Outline::Kind::DISC;
    c.outline.radius = R;
    c.cut = model::cut_grid(c.grid, c.outline, kSource, "specimen");

    c.disc_top_z = (R - rd) + kFloorClearance;
    if (discs) c.clamp_disc_bottom_z = c.disc_top_z + disc_gap;
    add_instrument(c.obstacles, o, c.disc_top_z, c.clamp_disc_bottom_z);
    const double gap = o.start_gap_m > 0 ? o.start_gap_m : discs ? 0.5 * disc_gap : 2 * o.solver.contact_distance;
    c.initial = model::flat_grid(c.grid, Vec3(0, 0, c.disc_top_z + gap));
    // The seeded start: a waviness of the hanging part, a function of the rest position alone
    // (so one seed is one physical start at every spacing): modes k = 1 .. kPerturbationModes
    // around the disc, random amplitudes and phases, growing linearly from the clamp's edge to
    // the specimen's, largest offset perturbation_m.
    std::mt19937_64 rng(o.solver.seed);
    double amplitude[kPerturbationModes], phase[kPerturbationModes], amplitude_sum = 0;
    for (int k = 0; k < kPerturbationModes; ++k) {
        amplitude[k] = uniform01(rng);
        phase[k] = 2 * std::numbers::pi * uniform01(rng);
        amplitude_sum += amplitude[k];
    }
    c.clamp_radius = discs ? rd : rd + o.clamp_margin * s;
    c.pinned_radius = discs ? rd - kCusickDiscsPinnedInset * s : c.clamp_radius;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int p = c.grid.index(i, j);
            if (!c.cut.active[p]) continue;
            const Vec2 uv = model::rest_uv(c.grid, i, j);
            const double r = uv.norm();
            if (r <= c.pinned_radius) {
                c.clamped.push_back(p);
                continue;
            }
            if (r <= c.clamp_radius) {  // DISCS: between the discs, flat at the start
                c.sandwiched.push_back(p);
                continue;
            }
            if (!(o.perturbation_m > 0)) continue;
            const double theta = std::atan2(uv.y(), uv.x());
            double wave = 0;
            for (int k = 0; k < kPerturbationModes; ++k) wave += amplitude[k] * std::cos((k + 1) * theta + phase[k]);
            c.initial[p].z() += o.perturbation_m * std::clamp((r - rd) / (R - rd), 0.0, 1.0) * wave / amplitude_sum;
        }
    turn_about_z(c.initial, o.grid_rotation_deg);
    return c;
}

CusickResult run_cusick(const kes::FabricData& fabric, const CusickOptions& options, const sim::ProgressCallback& progress,
                        const sim::IterationCallback& iteration)
{
    const CusickSetup setup = make_cusick_setup(options);
    model::ClothModel model = model::make_cloth_model(fabric, setup.grid, options.model, setup.cut.active, setup.cut.area);
    sim::Problem problem;
    problem.model = sim::ClothRef::evolving(model);  // friction: the states evolve with the drape
    problem.obstacles = &setup.obstacles;
    problem.initial = setup.initial;
    problem.pinned = setup.clamped;
    // The tester's own seeded start replaces the solver's per-particle one (which differs with
    // the spacing); without it (perturbation_m = 0) the solver's is kept.
    sim::SolverOptions solver = options.solver;
    if (options.perturbation_m > 0) solver.perturbation = 0;

    CusickResult r;
    // One stage: a drape to rest from the state reached, the slip states carried on; r.drape
    // holds the last stage's state with steps, iterations and times summed over the stages.
    Positions x = setup.initial;
    if (!options.start.empty()) {
        if (options.start.size() != setup.initial.size())
            throw InputError(kSource, "start", "expected " + std::to_string(setup.initial.size()) + " positions (the setup's grid)");
        x = options.start;
        for (int p : setup.clamped) x[p] = setup.initial[p];
        for (int p : setup.sandwiched) x[p] = setup.initial[p];
    }
    r.stages = 0;
    const auto stage = [&](const geometry::ObstacleSet& obstacles) {
        problem.obstacles = &obstacles;
        problem.initial = x;
        if (r.stages > 0) solver.perturbation = 0;  // the start's perturbation once
        sim::Result s = sim::drape(problem, solver, progress, iteration);
        if (r.stages > 0) sim::add_counters(s, r.drape);
        x = s.x;
        r.drape = std::move(s);
        ++r.stages;
        return !r.drape.interrupted;
    };
    bool going = true;
    if (options.protocol == CusickProtocol::RELEASE) {
        if (options.guides.guides > 0) {  // first onto the guide rods, then on its own
            geometry::ObstacleSet guided;
            add_instrument(guided, options, setup.disc_top_z, setup.clamp_disc_bottom_z);
            add_guide_rods(guided, options, setup.disc_top_z, options.guides);
            going = stage(guided);
        }
        if (going) going = stage(setup.obstacles);
    } else {
        // LOWERED: the overhang on a plate lowered in stages, each a drape to rest from the last,
        // down to where the hem hangs free (R - r_d below the disc's top); the last stage
        // without the plate: the specimen settles on its own.
        const double overhang = 0.5 * (options.specimen_diameter_m - options.disc_diameter_m);
        const double lower_step = lower_step_m(options);
        const int stages = static_cast<int>(std::ceil(overhang / lower_step - 1e-9));
        for (int k = 1; k <= stages && going; ++k) {
            geometry::ObstacleSet obstacles;
            add_instrument(obstacles, options, setup.disc_top_z, setup.clamp_disc_bottom_z);
            const double plate_z = setup.disc_top_z - k * lower_step;
            if (k < stages) obstacles.add(std::make_unique<geometry::Plane>(Vec3(0, 0, plate_z), Vec3::UnitZ(), options.specimen_diameter_m));
            going = stage(obstacles);
        }
    }
    // The shake, quasi-static: in the clamp's frame the disc's vertical acceleration a adds to
    // gravity, so each half cycle is a drape to rest at g (1 +- amplitude); then at g.
    const double g = model.gravity();
    for (int c = 0; c < options.shakes && going; ++c)
        for (double sign : {1.0, -1.0}) {
            model.set_gravity(g * (1 + sign * options.shake_amplitude));
            if (going) going = stage(setup.obstacles);
        }
    model.set_gravity(g);
    if (options.shakes > 0 && going) stage(setup.obstacles);
    r.surface = model::cut_surface(setup.grid, setup.cut, r.drape.x, &r.surface_uv);
    r.spacing_m = setup.grid.sigma;
    r.specimen_area_m2 = setup.cut.total_area;
    r.particles = setup.cut.count;
    // The shadow read in the threads' frame: the surface turned back by the grid's rotation.
    geometry::TriangleMesh measured = r.surface;
    turn_about_z(measured.vertices, -options.grid_rotation_deg);
    r.shadow = analysis::measure_drape(measured, Vec2::Zero(), 0.5 * options.disc_diameter_m, 0.5 * options.specimen_diameter_m,
                                       setup.cut.total_area, options.shadow);
    return r;
}

void add_guide_rods(geometry::ObstacleSet& obstacles, const CusickOptions& options, double disc_top_z, const CusickStart& start)
{
    const double R = 0.5 * options.specimen_diameter_m, rd = 0.5 * options.disc_diameter_m;
    const double slope = kGuideRodSlopeDeg * std::numbers::pi / 180;
    const double r0 = rd + kGuideRodInset, length = (R - r0) / std::cos(slope);
    for (int k = 0; k < start.guides; ++k) {
        // Angles from the warp (+y) towards the weft (+x), as the shadow's nodes.
        const double a = start.phase_rad + 2 * std::numbers::pi * k / start.guides - options.grid_rotation_deg * units::kDegToRad;
        const Vec2 radial(std::sin(a), std::cos(a));
        const Vec3 base(r0 * radial.x(), r0 * radial.y(), disc_top_z - kGuideRodDrop);
        const Vec3 axis(std::cos(slope) * radial.x(), std::cos(slope) * radial.y(), -std::sin(slope));
        obstacles.add(std::make_unique<geometry::Cylinder>(base, kGuideRodRadius, length, axis, 16));
    }
}

kes::FabricData stiffer_in_bending(const kes::FabricData& fabric, double factor)
{
    kes::FabricData f = fabric;
    for (kes::Measured<kes::BendingSummary>* b : {&f.bending_warp, &f.bending_weft}) {
        for (double& m : b->curve.y) m *= factor;
        if (b->summary) {
            b->summary->B *= factor;
            b->summary->two_HB *= factor;
        }
    }
    if (f.bias_B) *f.bias_B *= factor;
    return f;
}

double guide_phase(std::uint64_t seed, int guides)
{
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(guides));
    return uniform01(rng) * 2 * std::numbers::pi / guides;
}

CusickSearch search_cusick(const kes::FabricData& fabric, const CusickOptions& options, const CusickSearchOptions& search,
                           const sim::ProgressCallback& progress, const sim::IterationCallback& iteration)
{
    std::vector<CusickStart> starts;
    if (search.release) starts.push_back({});
    for (int m : search.modes) starts.push_back({m, guide_phase(options.solver.seed, m), 0});
    for (double f : search.stiffer) starts.push_back({0, 0, f});
    CusickSearch out;
    out.states.resize(starts.size());
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::mutex progress_mutex;
    std::exception_ptr failure;  // the first start's error, rethrown here once every worker has stopped
    const auto run_start = [&](std::size_t k) {
        CusickOptions o = options;
        o.guides = starts[k];
        out.states[k].start = starts[k];
        // The front end's callback, one start at a time; false from it stops every start.
        const auto relayed = [&](const auto& callback) {
            return [&stop, &progress_mutex, &callback](const auto& info) {
                if (stop) return false;
                if (!callback) return true;
                const std::lock_guard<std::mutex> lock(progress_mutex);
                if (!callback(info)) stop = true;
                return !stop.load();
            };
        };
        const sim::ProgressCallback step = relayed(progress);
        const sim::IterationCallback newton = relayed(iteration);
        int stages = 0;
        if (starts[k].stiffer > 0) {  // the stiffer copy first, the fabric from its rest
            const CusickResult stiff = run_cusick(stiffer_in_bending(fabric, starts[k].stiffer), o, step, newton);
            o.start = stiff.drape.x;
            stages = stiff.stages;
            if (stiff.drape.interrupted) stop = true;
        }
        out.states[k].result = run_cusick(fabric, o, step, newton);
        out.states[k].result.stages += stages;
        if (out.states[k].result.drape.interrupted) stop = true;
    };
    const auto worker = [&] {
        for (std::size_t k = next++; k < starts.size() && !stop; k = next++) {
            try {
                run_start(k);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(progress_mutex);
                if (!failure) failure = std::current_exception();
                stop = true;
            }
        }
    };
    const int jobs = std::clamp(search.jobs, 1, static_cast<int>(std::max<std::size_t>(starts.size(), 1)));
    std::vector<std::thread> pool;
    for (int t = 1; t < jobs; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    out.interrupted = stop;
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < out.states.size(); ++k) {
        const double e = out.states[k].result.drape.energy.total();
        if (out.states[k].result.particles > 0 && e < lowest) {
            lowest = e;
            out.prediction = static_cast<int>(k);
        }
    }
    return out;
}

CusickSearch run_cusick_seed(const kes::FabricData& fabric, const CusickOptions& options, const CusickSearchOptions* search,
                             const sim::ProgressCallback& progress, const sim::IterationCallback& iteration)
{
    CusickSearch found;
    if (search) {
        found = search_cusick(fabric, options, *search, progress, iteration);
    } else {
        found.states.push_back({{}, run_cusick(fabric, options, progress, iteration)});
        found.prediction = 0;
        found.interrupted = found.states[0].result.drape.interrupted;
    }
    return found;
}

std::string start_name(const CusickStart& start)
{
    return start.guides > 0    ? std::to_string(start.guides) + " guides"
           : start.stiffer > 0 ? "from " + std::to_string(static_cast<int>(start.stiffer)) + " x B"
                               : std::string("release");
}

CusickStatistics cusick_statistics(const std::vector<double>& drape_coefficients, const std::vector<int>& node_counts)
{
    CusickStatistics st;
    const double n = static_cast<double>(drape_coefficients.size());
    double mean = 0, var = 0;
    for (double d : drape_coefficients) mean += d / n;
    for (double d : drape_coefficients) var += (d - mean) * (d - mean) / std::max(1.0, n - 1);
    st.drape_coefficient_mean = mean;
    st.drape_coefficient_std = std::sqrt(var);
    for (int c : node_counts) ++st.runs_per_node_count[c];
    return st;
}

}  // namespace woven::testers
