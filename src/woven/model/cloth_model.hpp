#pragma once
// The global energy of the cloth (docs/MODEL.md "Each term once"), each term once:
//
//   E = sum_{pairs i<j, r_ij < sigma} R(r_ij)            (Eq. 2, 4; all pairs, spatial hash)
//     + sum_{4-connected edges}        S(r_ij)            (Eq. 3, 5)
//     + sum_{warp bends} B_warp(theta) + sum_{weft bends} B_weft(theta)   (Eq. 7, 12)
//     + sum_{crossings}                T(phi)             (Eq. 8, 15)
//     + sum_k m_k g z_k                                   (Eq. 6)
//
// The grid convention is grid.hpp's; which particles each term touches, stencils.hpp's; the
// terms themselves, terms.hpp's. Height is z; gravity acts along -z.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "woven/common/types.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/kes/fit.hpp"
#include "woven/model/energy_functions.hpp"
#include "woven/model/grid.hpp"
#include "woven/model/seams.hpp"
#include "woven/model/slip.hpp"
#include "woven/model/stencils.hpp"
#include "woven/model/terms.hpp"

namespace woven::model {

/// The terms of Eq. (1), each summed once over the cloth (J).
struct EnergyTerms {
    double repulsion = 0, stretch = 0, bending_warp = 0, bending_weft = 0, trellis = 0, gravity = 0;
    double twist = 0;  ///< beyond the paper: the bias bending (TwistTerm); 0 without it
    double seam = 0;   ///< beyond the paper: a garment's stitches (seams.hpp); 0 without seams
    double total() const { return repulsion + stretch + bending_warp + bending_weft + trellis + gravity + twist + seam; }
    double& operator[](Term t);
    double operator[](Term t) const { return const_cast<EnergyTerms&>(*this)[t]; }
};

/// The shear law of ModelOptions::shear_law.
enum class ShearLaw { DEEMBEDDED, MEASURED };
/// The laws' names: "deembedded", "measured" (scene files, the command line, reports).
inline constexpr std::array<Named<ShearLaw>, 2> kShearLawNames{{{ShearLaw::DEEMBEDDED, "deembedded"}, {ShearLaw::MEASURED, "measured"}}};
/// Its name in kShearLawNames.
inline const char* to_string(ShearLaw law) { return name_of(kShearLawNames, law); }

/// What resists a bend across the threads (ModelOptions::bias_bending).
///   THREADS: the threads' bending alone (the paper's Eq. 7-12): a bend at angle a to the warp
///     costs B_warp cos^4 a + B_weft sin^4 a, at 45 degrees a quarter of their sum.
///   FABRIC: and the cells' twisting (TwistTerm) with the rigidity that gives the fabric's bias
///     bending rigidity B_45 at 45 degrees: its measured KES-FB2 value on a bias specimen
///     (kes::FabricData::bias_B) or, where it has none, bias_rigidity_estimate.
enum class BiasBending { THREADS, FABRIC };

/// The settings' names: "threads", "fabric" (scene files, the command line, reports).
inline constexpr std::array<Named<BiasBending>, 2> kBiasBendingNames{{{BiasBending::THREADS, "threads"}, {BiasBending::FABRIC, "fabric"}}};
/// Its name in kBiasBendingNames.
const char* to_string(BiasBending b);

/// Model settings beyond the fabric (SI).
struct ModelOptions {
    /// WORK: the moment a bent thread carries is the input curve's M(K), as the virtual KES-FB2
    /// test shows (docs/VALIDATION.md); SECANT, the paper's Eq. (12), carries (M + K dM/dK)/2.
    BendingForm bending_form = BendingForm::WORK;
    /// CONVERGENT: consistent masses and weights at edges and corners, a stiff linear thread
    /// (tensile_stiffness), converging to the continuum at second order (docs/VALIDATION.md).
    /// PAPER: the paper's literal convention (stencils.hpp), kept to reproduce its results.
    Discretization discretization = Discretization::CONVERGENT;
    /// CONVERGENT: the thread's tensile stiffness per unit width, N/m: the stretch energy of a
    /// segment is E_t (r - sigma)^2 / 2 in tension and compression. <= 0: from the fabric's KES
    /// EMT (the secant stiffness 500 gf/cm / EMT), or kDefaultEMT where it gives none.
    double tensile_stiffness = 0;
    /// CONVERGENT: the thread's stiffness in compression over tensile_stiffness, in [0, 1]. 1: a
    /// linear spring both ways (the default); 0: the paper's Eq. (3), which resists no shortening
    /// (a yarn buckles; the repulsion alone holds the particles apart).
    double thread_compression = 1;
    units::GramForce gram_force = units::GramForce::PAPER;
    double gravity = units::kStandardGravity;  ///< m/s^2
    /// C0 of Eq. (2, 3) in J; <= 0: chosen by choose_C0 for a hanging length of half the
    /// cloth's longer side and 1 % strain.
    double C0 = 0;
    /// Which shear law the trellis energy (Eq. 14-15) carries. DEEMBEDDED: the material's, the
    /// input curve raised by the KES-FB1 specimen's end effect (its free short edges carry no
    /// shear, so the instrument reads a G below the material's); the factor is found by a
    /// virtual FB1 (testers::shear_deembedding), which testers::make_drape_model (the model of
    /// the woven commands and the Python module) runs and stores in shear_scale. make_cloth_model
    /// applies shear_scale alone: built directly from ModelOptions{} (scale 1) the model carries
    /// the law as measured. MEASURED: the input curve as the instrument read it.
    ShearLaw shear_law = ShearLaw::DEEMBEDDED;
    /// The trellis law is the input shear curve times this factor (the model applies only this).
    double shear_scale = 1.0;
    /// LOADING_BRANCH: each curve's loading branch is the elastic energy (the default). FRICTION:
    /// for the curves given by summary values with a hysteresis width (2HB, 2HG, 2HG5 > 0), the
    /// mean line (slope B, G) is the elastic energy and Jenkins friction elements carry the
    /// hysteresis (slip.hpp); their state changes only through ClothModel::update_slip. The
    /// shear elements are scaled by shear_scale with the elastic law. Curves given as points
    /// keep their loading branch.
    Hysteresis hysteresis = Hysteresis::LOADING_BRANCH;
    /// The bending across the threads; the PAPER discretisation has the threads' alone.
    BiasBending bias_bending = BiasBending::THREADS;
};

/// B_45 (gf.cm^2/cm) of an orthotropic plate with thread rigidities B_warp, B_weft under Huber's
/// approximation of the torsional rigidity, D12 + 2 D66 = sqrt(D11 D22) (M. T. Huber, 1923; the
/// standard estimate for orthotropic plates without a measured one): (B_warp + B_weft) / 4 +
/// sqrt(B_warp B_weft) / 2, which is B for a balanced fabric (isotropic in bending).
double bias_rigidity_estimate(double B_warp, double B_weft);

/// The bias bending rigidity B_45 the model is given (gf.cm^2/cm): the fabric's measured one, or
/// bias_rigidity_estimate of its warp and weft KES slopes.
double bias_rigidity(const kes::FittedFabric& fabric);

/// The KES-FB2 slope over 0.5-1.5 1/cm of a 45-degree specimen bent by the threads alone, the
/// moment 1/2 M_warp(K/2) + 1/2 M_weft(K/2) (each thread curved K/2), gf.cm^2/cm.
double bias_rigidity_of_threads(const kes::FittedFabric& fabric);

/// The twisting rigidity T (N m) that makes a 45-degree bend of the convergent model cost B_45:
/// 4 (B_45 - bias_rigidity_of_threads) converted to SI (it adds T/4 to the bias slope). Throws
/// InputError (the fabric, "bending.bias.B") when B_45 is below the threads' own.
double fabric_twist_rigidity(const kes::FittedFabric& fabric, units::GramForce gf);

/// The extension (%) at 500 gf/cm assumed when a fabric gives no KES tensile values: a typical
/// woven shirting (published EMT of woven fabrics: 3-8 %).
inline constexpr double kDefaultEMT = 5.0;
/// The KES tensile load EMT is measured at, gf/cm.
inline constexpr double kEMTLoad = 500.0;

/// Tensile stiffness per unit width (N/m) from KES EMT (%): 500 gf/cm over EMT / 100.
double tensile_stiffness_from_emt(double emt_percent, units::GramForce gf);

/// Particle masses (kg): W times the area each active particle stands for, 0 for an inactive
/// one. W in kg/m^2. `area_m2` (one per grid particle, e.g. model::ClothCut::area for a cloth
/// of any outline) gives the areas; empty, each stands for a sigma x sigma patch (the paper's m = W sigma^2).
std::vector<double> particle_masses(const Grid& grid, const std::vector<char>& active, double areal_density_kg_m2,
    const std::vector<double>& area_m2 = {});

/// The cloth's energy of Eq. (1) with derivatives, for one fitted fabric on one grid. Sigma is
/// the grid's, held once: every energy function is built from it here.
class ClothModel {
public:
    /// `active`: one entry per grid particle (empty: all active), see stencils.hpp; `area_m2`:
    /// the area each particle stands for (empty: sigma^2), see particle_masses.
    /// `slip`: the friction elements (slip.hpp, KES units), none by default (make_cloth_model
    /// builds them for Hysteresis::FRICTION).
    ClothModel(const kes::FittedFabric& fabric, const Grid& grid, const ModelOptions& options, std::vector<char> active = {},
        const std::vector<double>& area_m2 = {}, const SlipLaws& slip = {});

    /// The discretisation the model was built with.
    Discretization discretization() const { return discretization_; }
    /// The factor on the input shear curve (ModelOptions::shear_scale).
    double shear_scale() const { return shear_scale_; }

    /// Energy terms at x, one position per grid particle; a term is +inf in a singular
    /// configuration (terms.hpp).
    EnergyTerms evaluate(const Positions& x) const;
    /// The same, sending each stencil's local derivatives (as `what` asks) to `sink`
    /// (terms.hpp, LocalSink): not for vanishing or infinite terms.
    template <LocalSink Sink> EnergyTerms evaluate(const Positions& x, Derivatives what, Sink& sink) const
    {
        return evaluate(x, what, sink, close_pairs(x));
    }
    /// The same with the repulsion pairs given: they must be close_pairs(x) (a PairCache's).
    template <LocalSink Sink>
    EnergyTerms evaluate(const Positions& x, Derivatives what, Sink& sink, const std::vector<Stencil<2>>& pairs) const;

    /// Total energy (J).
    double energy(const Positions& x) const { return evaluate(x).total(); }
    /// Gradient dE/dx (J/m), 3n vector.
    Eigen::VectorXd gradient(const Positions& x) const;

    /// Pairs i < j of active particles closer than `radius` (default: sigma, the repulsion's
    /// support), ascending, by a spatial hash: O(n).
    std::vector<Stencil<2>> close_pairs(const Positions& x, double radius = 0) const;

    const Grid& grid() const { return grid_; }
    double sigma() const { return grid_.sigma; }
    const Stencils& stencils() const { return stencils_; }
    bool active(int p) const { return stencils_.active[p]; }
    /// Per-particle masses (kg).
    const std::vector<double>& masses() const { return masses_; }
    double mass(int p) const { return masses_[p]; }
    /// W sigma^2 (kg): the mass of a full sigma x sigma patch, an interior particle's.
    double particle_mass() const { return patch_mass_; }
    double gravity() const { return gravity_; }  ///< m/s^2
    /// Sets the gravity of Eq. (6) (m/s^2, >= 0): in the frame of a clamp moved vertically with
    /// acceleration a, the cloth feels g + a (a shaken Cusick disc, testers/cusick.hpp). C0,
    /// chosen at construction, is kept.
    void set_gravity(double g)
    {
        assert(g >= 0 && std::isfinite(g));
        gravity_ = g;
    }
    const ThreadSpacing& spacing() const { return spacing_; }
    const BendingEnergy& bending_warp() const { return warp_; }
    const BendingEnergy& bending_weft() const { return weft_; }
    const TrellisEnergy& trellis() const { return trellis_; }
    /// The twisting rigidity T (N m) of TwistTerm; 0 without bias bending.
    double twist_rigidity() const { return twist_rigidity_; }
    TwistTerm twist_term() const { return TwistTerm(twist_rigidity_, grid_.sigma); }

    /// The hysteresis mode the model was built with (ModelOptions::hysteresis).
    Hysteresis hysteresis() const { return hysteresis_; }
    /// Whether any friction elements are present (FRICTION with a hysteresis width given).
    bool has_slip() const { return slip_.any(); }
    /// The friction laws (scaled to J).
    const SlipLaws& slip_laws() const { return slip_; }
    /// After a converged step: each friction element's state by the return mapping at x.
    void update_slip(const Positions& x);
    /// Every friction element back to its virgin state (s = 0).
    void reset_slip();
    /// The states, one per stencil of stencils().warp_slip_bends, weft_slip_bends, crossings
    /// (empty for a family without friction).
    const std::vector<SlipState>& warp_slip() const { return warp_state_; }
    const std::vector<SlipState>& weft_slip() const { return weft_state_; }
    const std::vector<SlipState>& shear_slip() const { return shear_state_; }
    SlipBendTerm slip_bend_term(Term warp_or_weft) const
    {
        const bool warp = warp_or_weft == Term::BENDING_WARP;
        return SlipBendTerm(warp ? slip_.warp : slip_.weft, grid_.sigma * units::kMToCm, !warp);
    }
    SlipTrellisTerm slip_trellis_term() const { return SlipTrellisTerm(slip_.shear); }

    /// Sews the cloth (seams.hpp): the stitches join the energy with stiffness k (N/m), their
    /// particles are coupled in stencils(), and the `unrepelled` pairs leave close_pairs. Once.
    void set_seams(SeamSet seams, double stiffness);
    /// The stitches' stiffness k (N/m, >= 0): a drape ramps it up between sim::drape calls.
    void set_seam_stiffness(double stiffness)
    {
        assert(stiffness >= 0 && std::isfinite(stiffness));
        seam_stiffness_ = stiffness;
    }
    double seam_stiffness() const { return seam_stiffness_; }
    const SeamSet& seams() const { return seams_; }

    StretchTerm stretch_term() const { return StretchTerm(spacing_); }
    RepulsionTerm repulsion_term() const { return RepulsionTerm(spacing_); }
    BendingTerm bending_term(Term warp_or_weft) const { return BendingTerm(warp_or_weft == Term::BENDING_WARP ? warp_ : weft_); }
    TrellisTerm trellis_term() const { return TrellisTerm(trellis_); }
    GravityTerm gravity_term(int p) const { return GravityTerm(masses_[p], gravity_); }

private:
    Grid grid_;
    Stencils stencils_;
    std::vector<double> masses_;
    double patch_mass_, gravity_;
    Discretization discretization_ = Discretization::CONVERGENT;
    double shear_scale_ = 1.0;
    ThreadSpacing spacing_;
    BendingEnergy warp_, weft_;
    TrellisEnergy trellis_;
    double twist_rigidity_ = 0;
    Hysteresis hysteresis_ = Hysteresis::LOADING_BRANCH;
    SlipLaws slip_;
    std::vector<SlipState> warp_state_, weft_state_, shear_state_;
    SeamSet seams_;
    std::vector<Stencil<9>> seam_stencils_;  ///< Stitch::ids of each stitch
    double seam_stiffness_ = 0;
};

/// The friction laws of a fabric (slip.hpp, KES units): for each curve given by summary values,
/// half width 2HB/2 (bending, at 1 1/cm), 2HG/2 at 0.5 and 2HG5/2 at 5 degrees (shear, q =
/// sin(phi)), the virgin rise of the synthesised curves (kes::kBendingRise, kShearRise); curves
/// given as points or without a width have none.
SlipLaws slip_laws(const kes::FabricData& fabric);

/// Fits the fabric's curves (kes::fit_fabric, Sec. 5.1) and builds its model (Sec. 5.2-5.4);
/// with Hysteresis::FRICTION the mean lines (kes::without_hysteresis) and slip_laws.
ClothModel make_cloth_model(const kes::FabricData& fabric, const Grid& grid, const ModelOptions& options, std::vector<char> active = {},
    const std::vector<double>& area_m2 = {});

// ---------------------------------------------------------------------------------------------

namespace detail {

/// Stencils evaluated at once (on oneTBB's threads) before their derivatives go to the sink in
/// order; batches of fewer than kParallelStencils are evaluated on the calling thread.
inline constexpr std::size_t kStencilBatch = 2048;
inline constexpr std::ptrdiff_t kParallelStencils = 128;

/// Sums one term over its stencils, each times its weight (stencils.hpp), and sends the local
/// derivatives to the sink. The local terms of a batch of stencils are evaluated on oneTBB's
/// threads; the sums and the sink see them in the stencils' order (a PartitionedSink in
/// parts at once, each its own values), so the bits do not depend on the thread count.
template <int N, class Eval, class Sink>
double add_stencils(Term id, const Eval& eval, const std::vector<Stencil<N>>& stencils, const std::vector<double>& weights, const Positions& x, Derivatives what, Sink& sink)
{
    double sum = 0;
    std::vector<Local<N>> locals(std::min(kStencilBatch, stencils.size()));
    for (std::size_t begin = 0; begin < stencils.size(); begin += kStencilBatch) {
        const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(std::min(kStencilBatch, stencils.size() - begin));
        const auto evaluate = [&](std::ptrdiff_t from, std::ptrdiff_t to) {
            for (std::ptrdiff_t k = from; k < to; ++k) {
                const std::size_t n = begin + static_cast<std::size_t>(k);
                locals[k] = eval(n, gather<N>(x, stencils[n]), what);
                if (!weights.empty() && weights[n] != 1.0) scale_local(locals[k], weights[n]);
            }
        };
        if (count < kParallelStencils)
            evaluate(0, count);
        else
            tbb::parallel_for(tbb::blocked_range<std::ptrdiff_t>(0, count, (count + 1) / 2),
                              [&](const tbb::blocked_range<std::ptrdiff_t>& r) { evaluate(r.begin(), r.end()); }, tbb::simple_partitioner());
        for (std::ptrdiff_t k = 0; k < count; ++k) sum += locals[k].value;
        if (what == Derivatives::NONE) continue;
        const bool with_hessian = what != Derivatives::GRADIENT;
        const auto scatter = [&](auto... part) {
            for (std::ptrdiff_t k = 0; k < count; ++k) {
                const Local<N>& l = locals[k];
                if (!l.vanishes && std::isfinite(l.value)) sink.template add<N>(id, stencils[begin + static_cast<std::size_t>(k)], l, with_hessian, part...);
            }
        };
        if constexpr (PartitionedSink<Sink>) {
            if (sink.parts() > 1 && count >= kParallelStencils) {
                tbb::parallel_for(0, sink.parts(), [&](int part) { scatter(part); });
                continue;
            }
        }
        scatter();
    }
    return sum;
}

/// Sums one term over its stencils, each times its weight (stencils.hpp), and sends the local
/// derivatives to the sink. The local terms of a batch of stencils are evaluated on oneTBB's
/// threads; the sums and the sink see them in the stencils' order (a PartitionedSink in
/// parts at once, each its own values), so the bits do not depend on the thread count.
template <class T, class Sink>
double add_term(Term id, const T& term, const std::vector<Stencil<T::kParticles>>& stencils, const std::vector<double>& weights, const Positions& x, Derivatives what, Sink& sink)
{
    constexpr int N = T::kParticles;
    return add_stencils<N>(id, [&](std::size_t, const VecN<3 * N>& xl, Derivatives w) { return term.evaluate(xl, w); }, stencils, weights, x, what, sink);
}

/// The same for a friction term, each stencil with its slip state.
template <class T, class Sink>
double add_slip_term(Term id, const T& term, const std::vector<SlipState>& states, const std::vector<Stencil<T::kParticles>>& stencils,
    const std::vector<double>& weights, const Positions& x, Derivatives what, Sink& sink)
{
    constexpr int N = T::kParticles;
    return add_stencils<N>(id, [&](std::size_t n, const VecN<3 * N>& xl, Derivatives w) { return term.evaluate(xl, states[n], w); }, stencils, weights, x, what, sink);
}

struct NoSink {
    template <int N> void add(Term, const Stencil<N>&, const Local<N>&, bool) { }
};

}  // namespace detail

template <LocalSink Sink>
EnergyTerms ClothModel::evaluate(const Positions& x, Derivatives what, Sink& sink, const std::vector<Stencil<2>>& pairs) const
{
    assert(static_cast<int>(x.size()) == grid_.size());
    EnergyTerms e;
    // Gravity (Eq. 6), each particle with its own mass.
    for (int p : stencils_.particles) {
        const Local<1> l = gravity_term(p).evaluate(x[p], what);
        e.gravity += l.value;
        if (what != Derivatives::NONE) sink.template add<1>(Term::GRAVITY, {p}, l, false);  // linear: no Hessian
    }
    e.stretch = detail::add_term(Term::STRETCH, stretch_term(), stencils_.edges, stencils_.edge_weights, x, what, sink);
    e.repulsion = detail::add_term(Term::REPULSION, repulsion_term(), pairs, {}, x, what, sink);
    e.bending_warp = detail::add_term(Term::BENDING_WARP, BendingTerm(warp_), stencils_.warp_bends, stencils_.warp_weights, x, what, sink);
    e.bending_weft = detail::add_term(Term::BENDING_WEFT, BendingTerm(weft_), stencils_.weft_bends, stencils_.weft_weights, x, what, sink);
    e.trellis = detail::add_term(Term::TRELLIS, trellis_term(), stencils_.crossings, stencils_.crossing_weights, x, what, sink);
    if (twist_rigidity_ > 0) e.twist = detail::add_term(Term::TWIST, twist_term(), stencils_.cells, {}, x, what, sink);
    // Friction inside the weave (slip.hpp), part of the bending and trellis terms.
    if (slip_.warp.active())
        e.bending_warp += detail::add_slip_term(Term::BENDING_WARP, slip_bend_term(Term::BENDING_WARP), warp_state_, stencils_.warp_slip_bends,
                                                stencils_.warp_weights, x, what, sink);
    if (slip_.weft.active())
        e.bending_weft += detail::add_slip_term(Term::BENDING_WEFT, slip_bend_term(Term::BENDING_WEFT), weft_state_, stencils_.weft_slip_bends,
                                                stencils_.weft_weights, x, what, sink);
    if (slip_.shear.active())
        e.trellis += detail::add_slip_term(Term::TRELLIS, slip_trellis_term(), shear_state_, stencils_.crossings, stencils_.crossing_weights, x, what, sink);
    // A garment's stitches (seams.hpp), each with its own fraction w.
    if (!seams_.empty() && seam_stiffness_ > 0)
        e.seam = detail::add_stencils<9>(
            Term::SEAM, [&](std::size_t n, const VecN<27>& xl, Derivatives w) { return SeamTerm(seam_stiffness_, seams_.stitches[n].c).evaluate(xl, w); },
            seam_stencils_, {}, x, what, sink);
    return e;
}

}  // namespace woven::model
