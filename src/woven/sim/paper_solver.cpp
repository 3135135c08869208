// The paper's three-phase step (Sec. 3, last paragraphs; House, Breen & Getto 1992):
//   1. each particle falls freely under gravity in a viscous medium, with collisions against
//      the obstacles (a particle stopped by a surface slides on, without friction, and loses its
//      inward normal velocity);
//   2. a stochastic energy minimisation enforces the inter-particle energies. Our reading of the
//      paper's per-particle form: Gauss-Seidel sweeps in which each particle in turn moves along
//      its own preconditioned gradient (analytic, where the paper estimated it numerically; the
//      particle's 3x3 block of the projected Hessian as preconditioner) of
//      E_int(x) + sum_i m/(2 dt^2) |x_i - x_i^(1)|^2, with collisions: a step that would reach an
//      obstacle stops at it in the normal direction and keeps its tangential part (for a particle
//      resting on a surface, a step in the tangent plane). A move is kept only if it lowers that
//      energy (halved otherwise); sweeps alternate their order, revisit only particles near one
//      that moved, and stop when none moves any more. The proximity term makes phase 2 a time
//      step (its fixed point at rest is the static equilibrium of E_int + gravity) rather than a
//      projection onto E_int's minimum.
//      The randomness (which escapes local minima and breaks symmetry): in the first sweep a
//      seeded perturbation proportional to the particle's movement over the last step, fading
//      below 1 % of sigma. It has to vanish at rest: phase 3 turns any perturbation into velocity,
//      and one of fixed size (or proportional to the step) keeps the cloth from ever settling;
//   3. velocities are corrected by the motion of phase 2.
// The step is options.time_step capped at sqrt(m / 4k), k the thread stiffness S'' at 1 % strain
// (the strain C0 is chosen for): per-particle sweeps carry a disturbance along a thread about
// as far per pass as the ratio of inertia m/dt^2 to k allows, so with m/dt^2 = 4k a step settles
// in a few sweeps, where a larger step needs of the order of k dt^2 / m of them.
// Equilibrium (Sec. 6): the largest particle movement between successive steps below a
// threshold, for 10 steps and 0.1 s in a row. Not fast: kept for reproduction and comparison.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include <Eigen/Cholesky>

#include "woven/common/error.hpp"
#include "woven/sim/solver_support.hpp"
#include "woven/sim/solvers.hpp"

namespace woven::sim::detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Moves one particle from p by d with collision handling (no friction, as the model has none):
/// a path that meets an obstacle stops at the contact point, lifted to `clearance` along the
/// normal, and goes on with the rest of the move less its inward normal part (sliding); a
/// particle ending closer than `clearance` is lifted to it. Returns whether an obstacle stopped
/// it, and the last contact's normal in `normal`.
bool move_particle(const geometry::ObstacleSet& obstacles, Vec3& p, Vec3 d, double clearance, Vec3* normal)
{
    bool stopped = false;
    for (int contact = 0; contact < 3 && d.squaredNorm() > 0; ++contact) {
        const std::optional<double> t = obstacles.first_contact(p, p + d);
        if (!t) break;
        const geometry::ClosestPoint c = obstacles.closest(p + *t * d);
        p = c.point + clearance * c.normal;
        d *= 1.0 - *t;
        d -= std::min(0.0, d.dot(c.normal)) * c.normal;
        stopped = true;
        if (normal) *normal = c.normal;
    }
    p += d;
    for (size_t o = 0; o < obstacles.size(); ++o) {
        const geometry::ClosestPoint c = obstacles[o].closest(p);
        if (c.distance < clearance) {
            p = c.point + clearance * c.normal;
            stopped = true;
            if (normal) *normal = c.normal;
        }
    }
    return stopped;
}

/// The terms of the inter-particle energy E_int (cloth_model.hpp, all but gravity, which phase 1
/// applies) whose value depends on one particle p, with p's gradient and the p-p block of the
/// projected Hessian, from the model's own terms (model/terms.hpp, ParticleLocal). When p alone
/// moves, this local energy changes as E_int does, which lets phase 2 move particles one at a
/// time. Repulsion is evaluated on a pair list frozen for the step (set_pairs).
class ParticleEnergy {
public:
    explicit ParticleEnergy(const model::ClothModel& model)
        : stencils_(model.stencils()), n_(model.grid().size()), stretch_(model.stretch_term()), repulsion_(model.repulsion_term()),
          warp_(model.bending_term(model::Term::BENDING_WARP)), weft_(model.bending_term(model::Term::BENDING_WEFT)),
          trellis_(model.trellis_term()), warp_of_(model::make_incidence(stencils_.warp_bends, n_)),
          weft_of_(model::make_incidence(stencils_.weft_bends, n_)), crossings_of_(model::make_incidence(stencils_.crossings, n_)),
          twist_(model.twist_term()), cells_of_(model::make_incidence(stencils_.cells, n_))
    {
    }

    /// Repulsion partners: the edges (which also carry stretching), the particles sharing a
    /// stencil (the diagonal ones come within sigma under large shear) and `close`.
    void set_pairs(const std::vector<model::Stencil<2>>& close)
    {
        links_.clear();
        for (std::size_t k = 0; k < stencils_.edges.size(); ++k) add_link(stencils_.edges[k][0], stencils_.edges[k][1], true, stencils_.edge_weights[k]);
        for (int p = 0; p < n_; ++p)
            for (int q : stencils_.coupled_with(p))
                if (q > p) add_link(p, q, false);
        for (const auto& [p, q] : close) add_link(p, q, false);
        // Sort by particle and partner; a thread link sorts first and so survives unique().
        std::sort(links_.begin(), links_.end(), [](const Link& a, const Link& b) {
            return a.p != b.p ? a.p < b.p : a.q != b.q ? a.q < b.q : a.thread > b.thread;
        });
        links_.erase(std::unique(links_.begin(), links_.end(), [](const Link& a, const Link& b) { return a.p == b.p && a.q == b.q; }),
                     links_.end());
        first_.assign(n_ + 1, 0);
        for (const Link& l : links_) ++first_[l.p + 1];
        for (int p = 0; p < n_; ++p) first_[p + 1] += first_[p];
    }

    /// Calls f(q) for every particle q that shares a term with p (its energy's gradient moves when p does).
    template <class F> void for_each_neighbour(int p, F f) const
    {
        for (int k = first_[p]; k < first_[p + 1]; ++k) f(links_[k].q);
    }

    double value(const Positions& x, int p) const { return terms<false>(x, p, nullptr, nullptr); }
    /// Value; gradient and Hessian block are written to g and H.
    double derivatives(const Positions& x, int p, Vec3& g, Mat3& H) const
    {
        g.setZero();
        H.setZero();
        return terms<true>(x, p, &g, &H);
    }

private:
    struct Link {
        int p, q;
        bool thread;  ///< an edge: stretching as well as repulsion
        double weight = 1.0;  ///< the edge's share of cloth (stencils.hpp)
    };
    void add_link(int p, int q, bool thread, double weight = 1.0)
    {
        links_.push_back({p, q, thread, weight});
        links_.push_back({q, p, thread, weight});
    }

    template <bool kDerivatives> double terms(const Positions& x, int p, Vec3* g, Mat3* H) const
    {
        constexpr model::Derivatives what = kDerivatives ? model::Derivatives::PROJECTED : model::Derivatives::NONE;
        double e = 0;
        auto add = [&](model::ParticleLocal l, double w = 1.0) {
            if (!std::isfinite(l.value)) return false;
            if (w != 1.0) model::scale_local(l, w);  // the stencil's share of cloth (stencils.hpp)
            e += l.value;
            if constexpr (kDerivatives) {
                *g += l.gradient;
                *H += l.hessian;
            }
            return true;
        };
        // Repulsion (Eq. 2, 4) and stretching (Eq. 3, 5), p first in each pair.
        for (int k = first_[p]; k < first_[p + 1]; ++k) {
            const Link& l = links_[k];
            VecN<6> pair;
            pair << x[p], x[l.q];
            if (l.thread && !add(stretch_.particle(pair, 0, what), l.weight)) return kInfinity;
            if (!add(repulsion_.particle(pair, 0, what))) return kInfinity;
        }
        // Bending (Eq. 7, 12, 13) of the angles p belongs to, and trellising (Eq. 8, 15) of the
        // crossings p is a neighbour of; `role` is p's place in the stencil.
        for (const auto& [k, role] : warp_of_.of(p))
            if (!add(warp_.particle(model::gather<3>(x, stencils_.warp_bends[k]), role, what), stencils_.warp_weights[k])) return kInfinity;
        for (const auto& [k, role] : weft_of_.of(p))
            if (!add(weft_.particle(model::gather<3>(x, stencils_.weft_bends[k]), role, what), stencils_.weft_weights[k])) return kInfinity;
        for (const auto& [k, role] : crossings_of_.of(p))
            if (!add(trellis_.particle(model::gather<4>(x, stencils_.crossings[k]), role, what), stencils_.crossing_weights[k])) return kInfinity;
        // Twisting of the cells p is a corner of (beyond the paper; none without bias bending).
        for (const auto& [k, role] : cells_of_.of(p))
            if (!add(twist_.particle(model::gather<4>(x, stencils_.cells[k]), role, what))) return kInfinity;
        return e;
    }

    const model::Stencils& stencils_;
    int n_;
    model::StretchTerm stretch_;
    model::RepulsionTerm repulsion_;
    model::BendingTerm warp_, weft_;
    model::TrellisTerm trellis_;
    model::Incidence warp_of_, weft_of_, crossings_of_;
    model::TwistTerm twist_;
    model::Incidence cells_of_;
    std::vector<Link> links_;
    std::vector<int> first_;  ///< links_ of particle p: [first_[p], first_[p + 1])
};

/// The paper's solver as a Solver: the state carried from one step to the next.
class PaperStepper final : public Solver {
public:
    PaperStepper(const Problem& problem, const SolverOptions& options);

    bool report_due() const override { return steps_ % options_.paper.progress_every == 0 || calm >= calm_steps; }

private:
    bool advance(const IterationCallback& iteration) override;
    double relax(int p, bool perturb);

    const model::ClothModel& model;
    const int n;
    double dt = 0;
    std::vector<double> inertia;  // m_i / dt^2
    double clearance = 0, sweep_tolerance = 0, noise_fade = 0;
    int calm_steps = 0;
    std::mt19937_64 rng;
    std::normal_distribution<double> normal{0.0, 1.0 / std::sqrt(3.0)};
    Positions v, x1, x_prev;
    std::vector<double> last_move;
    std::vector<char> active, next;
    ParticleEnergy local;
    int calm = 0;
};

PaperStepper::PaperStepper(const Problem& problem, const SolverOptions& options)
    : Solver(problem, options), model(*problem.model), n(model.grid().size()), rng(options.seed), v(n, Vec3::Zero()), x1(n), last_move(n),
      active(n), next(n), local(model)
{
    const PaperSolverOptions& po = options.paper;
    // The paper's per-particle steps have no place for the friction elements' states (their
    // update between converged steps): hysteresis as friction is the fast solver's.
    if (model.hysteresis() == model::Hysteresis::FRICTION)
        throw InputError("paper solver", "hysteresis",
                         "expected loading-branch: the paper solver does not carry the friction elements (use --solver fast)");
    const double sigma = model.grid().sigma;
    const double stiffness = model.spacing().stretch((1.0 + po.stiffness_strain) * sigma).d2;  // S'' at 1 % strain
    // The cap uses an interior particle's mass W sigma^2.
    dt = stiffness > 0 ? std::min(options.time_step, std::sqrt(model.particle_mass() / (po.dt_cap * stiffness))) : options.time_step;
    inertia.resize(n);
    for (int i = 0; i < n; ++i) inertia[i] = model.mass(i) / (dt * dt);
    clearance = po.clearance * options.contact_distance;
    sweep_tolerance = po.sweep_tolerance * options.move_tolerance;  // phase 2 ends when a sweep moves no particle more
    noise_fade = po.noise_fade * sigma;
    // Equilibrium (Sec. 6): movement below the threshold calm_steps steps in a row, and over at
    // least calm_time: with a small step, a cloth released from rest moves less than the
    // threshold per step for its first steps.
    calm_steps = std::max(po.calm_steps, static_cast<int>(std::ceil(po.calm_time / dt)));
    x_ = problem.initial;
}

// One particle's move in phase 2: a Newton step on its own energy (preconditioned gradient),
// stopped at the nearest obstacle, plus the random perturbation; halved until the phase-2
// energy decreases. Returns how far it moved.
double PaperStepper::relax(int p, bool perturb)
{
    const PaperSolverOptions& po = options_.paper;
    const geometry::ObstacleSet& obstacles = *problem_.obstacles;
    Positions& x = x_;
    Vec3 grad;
    Mat3 H;
    const Vec3 from = x[p];
    const double e0 = local.derivatives(x, p, grad, H) + 0.5 * inertia[p] * (from - x1[p]).squaredNorm();
    grad += inertia[p] * (from - x1[p]);
    H += inertia[p] * Mat3::Identity();
    const Eigen::LDLT<Mat3> solver(H);
    Vec3 d = -solver.solve(grad);
    // A step that would reach the nearest obstacle's surface (planar near the particle) stops
    // there in the normal direction: the minimiser of the local quadratic model on n.d = -gap,
    // which for a particle resting on the obstacle is the step in the tangent plane (the
    // obstacle carries the normal part of its force: no friction).
    const geometry::ClosestPoint c = obstacles.closest(from);
    const double gap = std::max(0.0, c.distance - clearance);
    if (d.dot(c.normal) < -gap) {
        const Vec3 Hn = solver.solve(c.normal);
        d -= (gap + d.dot(c.normal)) / c.normal.dot(Hn) * Hn;
    }
    if (perturb) d += po.noise * last_move[p] * std::min(1.0, last_move[p] / noise_fade) * Vec3(normal(rng), normal(rng), normal(rng));
    for (double alpha = 1.0; alpha > po.min_move_fraction; alpha *= 0.5) {
        Vec3 to = from;
        move_particle(obstacles, to, alpha * d, clearance, nullptr);
        x[p] = to;
        if (local.value(x, p) + 0.5 * inertia[p] * (to - x1[p]).squaredNorm() < e0) return (to - from).norm();
    }
    x[p] = from;
    return 0.0;
}

bool PaperStepper::advance(const IterationCallback& on_iteration)
{
    const PaperSolverOptions& po = options_.paper;
    const geometry::ObstacleSet& obstacles = *problem_.obstacles;
    const std::vector<char>& pinned = held_;
    const double g = model.gravity();
    Positions& x = x_;
    const int step = steps_ + 1;
    x_prev = x;
    // Phase 1 (Sec. 3): free fall in a viscous medium, with collisions.
    const double drag = std::exp(-options_.viscosity * dt);
    x1 = x;
    for (int i = 0; i < n; ++i) {
        last_move[i] = v[i].norm() * dt;  // the step's motion (phase 3 sets v to it)
        v[i] = pinned[i] ? Vec3::Zero() : Vec3(drag * v[i] + Vec3(0, 0, -g * dt));
        Vec3 normal_i;
        if (move_particle(obstacles, x1[i], v[i] * dt, clearance, &normal_i)) v[i] -= std::min(0.0, v[i].dot(normal_i)) * normal_i;
    }

    // Phase 2: stochastic minimisation of the inter-particle energy plus proximity to x1,
    // particle by particle (Gauss-Seidel), sweeps alternating forward and backward; after
    // the first sweep only particles near one that moved are visited again.
    // Repulsion partners: pairs closer than pair_margin sigma, a margin for the moves of phase 2.
    local.set_pairs(model.close_pairs(x1, po.pair_margin * model.grid().sigma));
    x = x1;
    int sweeps = 0;
    for (int i = 0; i < n; ++i) active[i] = !pinned[i];
    for (int sweep = 0; sweep < po.max_sweeps; ++sweep) {
        ++sweeps;
        bool moved = false;
        std::fill(next.begin(), next.end(), 0);
        for (int s = 0; s < n; ++s) {
            const int p = sweep % 2 == 0 ? s : n - 1 - s;
            if (!active[p]) continue;
            if (relax(p, sweep == 0) <= sweep_tolerance) continue;
            moved = true;
            next[p] = 1;
            local.for_each_neighbour(p, [&](int q) { next[q] = active[q] = !pinned[q]; });
        }
        if (!moved) break;
        active.swap(next);
    }
    // Phase 3: velocity correction for the motion of phase 2.
    for (int i = 0; i < n; ++i) v[i] = pinned[i] ? Vec3::Zero() : Vec3(v[i] + (x[i] - x1[i]) / dt);

    steps_ = step;
    iterations_ += sweeps;
    time_ += dt;
    max_move_ = max_displacement(x, x_prev);
    residual_changed();
    calm = max_move_ < options_.move_tolerance ? calm + 1 : 0;
    converged_ = calm >= calm_steps;
    if (on_iteration) {
        constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();
        if (!on_iteration(IterationInfo{step, sweeps, iterations_, dt, kNotComputed, kNotComputed})) return false;
    }
    return true;
}

}  // namespace

std::unique_ptr<Solver> make_paper_solver(const Problem& problem, const SolverOptions& options)
{
    return std::make_unique<PaperStepper>(problem, options);
}

}  // namespace woven::sim::detail
