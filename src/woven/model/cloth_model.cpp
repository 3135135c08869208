#include "woven/model/cloth_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

#include "woven/common/error.hpp"


namespace woven::model {

double& EnergyTerms::operator[](Term t)
{
    switch (t) {
    case Term::GRAVITY: return gravity;
    case Term::STRETCH: return stretch;
    case Term::REPULSION: return repulsion;
    case Term::BENDING_WARP: return bending_warp;
    case Term::BENDING_WEFT: return bending_weft;
    case Term::TRELLIS: return trellis;
    case Term::TWIST: return twist;
    case Term::SEAM: return seam;
    }
    assert(false);
    return gravity;
}

const char* to_string(BiasBending b) { return name_of(kBiasBendingNames, b); }

double bias_rigidity_estimate(double B_warp, double B_weft)
{
    return 0.25 * (B_warp + B_weft) + 0.5 * std::sqrt(B_warp * B_weft);
}

double bias_rigidity(const kes::FittedFabric& fabric)
{
    if (fabric.bias_B) return *fabric.bias_B;
    namespace ki = kes::instrument;
    return bias_rigidity_estimate(kes::fit_slope(fabric.bending_warp, ki::kBendingSlopeFrom, ki::kBendingSlopeTo),
                                  kes::fit_slope(fabric.bending_weft, ki::kBendingSlopeFrom, ki::kBendingSlopeTo));
}

double bias_rigidity_of_threads(const kes::FittedFabric& fabric)
{
    namespace ki = kes::instrument;
    auto moment = [&](double K) { return 0.5 * (fabric.bending_warp.value(0.5 * K) + fabric.bending_weft.value(0.5 * K)); };
    return (moment(ki::kBendingSlopeTo) - moment(ki::kBendingSlopeFrom)) / (ki::kBendingSlopeTo - ki::kBendingSlopeFrom);
}

double fabric_twist_rigidity(const kes::FittedFabric& fabric, units::GramForce gf)
{
    const double B45 = bias_rigidity(fabric), threads = bias_rigidity_of_threads(fabric);
    if (!(B45 >= threads))
        throw InputError("fabric '" + fabric.name + "'", "bending.bias.B",
                         "the bias rigidity " + std::to_string(B45) + " gf.cm^2/cm is below the threads' own " + std::to_string(threads) +
                             " (1/2 M_warp(K/2) + 1/2 M_weft(K/2) over 0.5-1.5 1/cm); expected at least that");
    // gf.cm^2/cm -> N m: gram-force (N) x cm^2/cm (m).
    return 4.0 * (B45 - threads) * units::newton_per_gram_force(gf) / units::kMToCm;
}

double tensile_stiffness_from_emt(double emt_percent, units::GramForce gf)
{
    return kEMTLoad * units::newton_per_gram_force(gf) * units::kMToCm / (emt_percent / 100.0);
}

std::vector<double> particle_masses(const Grid& grid, const std::vector<char>& active, double areal_density_kg_m2,
    const std::vector<double>& area_m2)
{
    assert(area_m2.empty() || static_cast<int>(area_m2.size()) == grid.size());
    const double patch = areal_density_kg_m2 * grid.sigma * grid.sigma;  // each particle is a sigma x sigma patch
    std::vector<double> m(grid.size(), patch);
    for (int p = 0; p < grid.size(); ++p) {
        if (!area_m2.empty()) m[p] = areal_density_kg_m2 * area_m2[p];
        if (!active.empty() && !active[p]) m[p] = 0;
    }
    return m;
}

ClothModel::ClothModel(const kes::FittedFabric& fabric, const Grid& grid, const ModelOptions& options, std::vector<char> active,
    const std::vector<double>& area_m2, const SlipLaws& slip)
    : grid_(grid),
      stencils_(make_stencils(grid, std::move(active), options.discretization, slip.any(),
                              options.bias_bending == BiasBending::FABRIC && options.discretization == Discretization::CONVERGENT)),
      discretization_(options.discretization),
      shear_scale_(options.shear_scale), hysteresis_(options.hysteresis), slip_(slip)
{
    assert(grid.nu > 0 && grid.nv > 0 && grid.sigma > 0);
    assert(options.shear_scale > 0 && std::isfinite(options.shear_scale));
    const double sigma = grid.sigma;
    const double W = fabric.areal_density_mg_cm2 * units::kMgPerCm2ToKgPerM2;
    // CONVERGENT: each particle's dual cell (stencils.hpp), unless the areas are given.
    std::vector<double> area = area_m2;
    if (area.empty() && options.discretization == Discretization::CONVERGENT)
        for (int p = 0; p < grid.size(); ++p) area.push_back(stencils_.particle_areas[p] * sigma * sigma);
    masses_ = particle_masses(grid, stencils_.active, W, area);
    patch_mass_ = W * sigma * sigma;
    gravity_ = options.gravity;
    const double hang = 0.5 * std::max(grid.nu - 1, grid.nv - 1) * sigma;
    // C0 for the paper's stretch well and the repulsion; without gravity, as under standard
    // gravity (choose_C0 would give no well at all).
    const double g_C0 = options.gravity > 0 ? options.gravity : units::kStandardGravity;
    spacing_ = ThreadSpacing{options.C0 > 0 ? options.C0 : choose_C0(W, g_C0, sigma, hang), sigma};
    if (options.discretization == Discretization::CONVERGENT)
        spacing_.tensile = options.tensile_stiffness > 0 ? options.tensile_stiffness : tensile_stiffness_from_emt(kDefaultEMT, options.gram_force);
    spacing_.compression_ratio = std::clamp(options.thread_compression, 0.0, 1.0);
    warp_ = BendingEnergy(fabric.bending_warp, sigma, options.bending_form, options.gram_force);
    weft_ = BendingEnergy(fabric.bending_weft, sigma, options.bending_form, options.gram_force);
    trellis_ = TrellisEnergy(fabric.shear, sigma, options.gram_force, options.shear_scale);
    if (!stencils_.cells.empty()) twist_rigidity_ = fabric_twist_rigidity(fabric, options.gram_force);
    // The friction elements' energies in J: as the elastic terms' (energy_functions.hpp), the
    // shear ones times the shear law's factor.
    const double sigma_cm = sigma * units::kMToCm;
    const double J = sigma_cm * sigma_cm * units::joule_per_gram_force_cm(options.gram_force);
    slip_.warp.scale = slip_.weft.scale = J;
    slip_.shear.scale = J * options.shear_scale;
    reset_slip();
}

void ClothModel::reset_slip()
{
    warp_state_.assign(slip_.warp.active() ? stencils_.warp_slip_bends.size() : 0, SlipState{});
    weft_state_.assign(slip_.weft.active() ? stencils_.weft_slip_bends.size() : 0, SlipState{});
    shear_state_.assign(slip_.shear.active() ? stencils_.crossings.size() : 0, SlipState{});
}

void ClothModel::update_slip(const Positions& x)
{
    assert(static_cast<int>(x.size()) == grid_.size());
    auto update = [&](const auto& term, const SlipLaw& law, const auto& stencils, std::vector<SlipState>& states) {
        constexpr int N = std::decay_t<decltype(term)>::kParticles;
        for (std::size_t n = 0; n < states.size(); ++n) law.update(term.strain(gather<N>(x, stencils[n])), states[n]);
    };
    if (slip_.warp.active()) update(slip_bend_term(Term::BENDING_WARP), slip_.warp, stencils_.warp_slip_bends, warp_state_);
    if (slip_.weft.active()) update(slip_bend_term(Term::BENDING_WEFT), slip_.weft, stencils_.weft_slip_bends, weft_state_);
    if (slip_.shear.active()) update(slip_trellis_term(), slip_.shear, stencils_.crossings, shear_state_);
}

void ClothModel::set_seams(SeamSet seams, double stiffness)
{
    assert(seams_.empty());
    std::sort(seams.unrepelled.begin(), seams.unrepelled.end());
    seams.unrepelled.erase(std::unique(seams.unrepelled.begin(), seams.unrepelled.end()), seams.unrepelled.end());
    seams_ = std::move(seams);
    seam_stencils_.clear();
    for (const Stitch& s : seams_.stitches) seam_stencils_.push_back(s.ids);
    couple_stitches(stencils_, seams_.stitches);
    set_seam_stiffness(stiffness);
}

EnergyTerms ClothModel::evaluate(const Positions& x) const
{
    detail::NoSink none;
    return evaluate(x, Derivatives::NONE, none);
}

Eigen::VectorXd ClothModel::gradient(const Positions& x) const
{
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * grid_.size());
    GradientSink sink{g};
    evaluate(x, Derivatives::GRADIENT, sink);
    return g;
}

std::vector<Stencil<2>> ClothModel::close_pairs(const Positions& x, double radius) const
{
    // Spatial hash: cells of size radius; particles sorted by cell key, an open-addressing table
    // from key to the run of particles in that cell; each particle looks in the 27 cells around
    // its own.
    const double h = radius > 0 ? radius : grid_.sigma;
    const std::vector<int>& particles = stencils_.particles;  // active only
    const int n = static_cast<int>(particles.size());
    auto cell_of = [&](const Vec3& p) {
        return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / h)), static_cast<int>(std::floor(p.y() / h)), static_cast<int>(std::floor(p.z() / h)));
    };
    auto key = [](const Eigen::Vector3i& c) {
        constexpr std::int64_t kBias = 1 << 20, kMask = (1 << 21) - 1;
        return ((c.x() + kBias) & kMask) | (((c.y() + kBias) & kMask) << 21) | (((c.z() + kBias) & kMask) << 42);
    };
    std::vector<std::pair<std::int64_t, int>> cells(n);
    for (int k = 0; k < n; ++k) cells[k] = {key(cell_of(x[particles[k]])), particles[k]};
    std::sort(cells.begin(), cells.end());

    struct Slot {
        std::int64_t key = -1;
        int begin = 0, end = 0;
    };
    size_t table_size = 16;
    while (table_size < 2 * static_cast<size_t>(n)) table_size *= 2;
    std::vector<Slot> table(table_size);
    auto slot_of = [&](std::int64_t k) {
        size_t s = static_cast<size_t>((static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull) >> 20) & (table_size - 1);
        while (table[s].key != -1 && table[s].key != k) s = (s + 1) & (table_size - 1);
        return s;
    };
    for (int b = 0; b < n;) {
        int e = b + 1;
        while (e < n && cells[e].first == cells[b].first) ++e;
        table[slot_of(cells[b].first)] = {cells[b].first, b, e};
        b = e;
    }

    std::vector<Stencil<2>> pairs;
    const double h2 = h * h;
    for (int p : particles) {
        const Eigen::Vector3i c = cell_of(x[p]);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::int64_t k = key(c + Eigen::Vector3i(dx, dy, dz));
                    const Slot& slot = table[slot_of(k)];
                    if (slot.key != k) continue;
                    for (int m = slot.begin; m < slot.end; ++m) {
                        const int q = cells[m].second;
                        if (q > p && (x[p] - x[q]).squaredNorm() < h2) pairs.push_back({p, q});
                    }
                }
    }
    std::sort(pairs.begin(), pairs.end());  // deterministic order of summation
    if (!seams_.unrepelled.empty())  // edges sewn together: not pressed apart (seams.hpp)
        std::erase_if(pairs, [&](const Stencil<2>& c) { return std::binary_search(seams_.unrepelled.begin(), seams_.unrepelled.end(), c); });
    return pairs;
}

ClothModel make_cloth_model(const kes::FabricData& fabric, const Grid& grid, const ModelOptions& options, std::vector<char> active,
    const std::vector<double>& area_m2)
{
    ModelOptions o = options;
    if (o.discretization == Discretization::CONVERGENT && !(o.tensile_stiffness > 0) && fabric.tensile && fabric.tensile->EMT > 0)
        o.tensile_stiffness = tensile_stiffness_from_emt(fabric.tensile->EMT, o.gram_force);
    if (o.hysteresis != Hysteresis::FRICTION) return ClothModel(kes::fit_fabric(fabric), grid, o, std::move(active), area_m2);
    // FRICTION: the mean lines are the elastic energy, the half widths the friction's.
    const SlipLaws slip = slip_laws(fabric);
    return ClothModel(kes::fit_fabric(kes::without_hysteresis(fabric)), grid, o, std::move(active), area_m2, slip);
}

SlipLaws slip_laws(const kes::FabricData& fabric)
{
    SlipLaws laws;
    constexpr double kAt = 1.0;  // 2HB is read at 1 1/cm
    if (fabric.bending_warp.summary) laws.warp = make_slip_law(kAt, 0.5 * fabric.bending_warp.summary->two_HB, kAt, 0.5 * fabric.bending_warp.summary->two_HB, kes::kBendingRise);
    if (fabric.bending_weft.summary) laws.weft = make_slip_law(kAt, 0.5 * fabric.bending_weft.summary->two_HB, kAt, 0.5 * fabric.bending_weft.summary->two_HB, kes::kBendingRise);
    if (fabric.shear.summary) {
        // q = sin(phi): 2HG at 0.5 degrees, 2HG5 at 5, the rise as the synthesised curve's.
        const auto q = [](double deg) { return std::sin(deg * units::kDegToRad); };
        laws.shear = make_slip_law(q(kes::instrument::kShearSlopeFrom), 0.5 * fabric.shear.summary->two_HG, q(kes::instrument::kShearSlopeTo),
                                   0.5 * fabric.shear.summary->two_HG5, q(kes::kShearRise));
    }
    return laws;
}

Positions flat_grid(const Grid& grid, const Vec3& centre, double yaw)
{
    Positions x(grid.size());
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            const double u = (i - 0.5 * (grid.nu - 1)) * grid.sigma, v = (j - 0.5 * (grid.nv - 1)) * grid.sigma;
            x[grid.index(i, j)] = centre + Vec3(c * u - s * v, s * u + c * v, 0.0);
        }
    return x;
}

}  // namespace woven::model

