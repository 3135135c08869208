#include "woven/model/cloth_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "woven/model/stencils.hpp"

namespace woven::model {

ClothModel::ClothModel(Grid grid, double particle_mass, double gravity, ThreadSpacing spacing, BendingEnergy warp, BendingEnergy weft, TrellisEnergy trellis)
    : grid_(grid), mass_(particle_mass), gravity_(gravity), spacing_(spacing), warp_(std::move(warp)), weft_(std::move(weft)), trellis_(std::move(trellis))
{
}

namespace {

/// Local derivatives of a two-particle term f(r), r = |x0 - x1|. In PROJECTED mode the
/// Hessian f'' n n^T + (f'/r)(I - n n^T) is clamped per eigenvalue (exact PSD projection).
void pair_term(const Scalar3& f, const Vec3& x0, const Vec3& x1, const int* ids, Derivatives what, StencilSink* sink)
{
    const Vec3 d = x0 - x1;
    const double r = d.norm();
    const Vec3 n = d / r;
    VecN<6> g;
    g << f.d1 * n, -f.d1 * n;
    if (what == Derivatives::GRADIENT) {
        sink->add(ids, 2, g.data(), nullptr);
        return;
    }
    const bool project = what == Derivatives::PROJECTED;
    const double along = project ? std::max(f.d2, 0.0) : f.d2;
    const double across = project ? std::max(f.d1 / r, 0.0) : f.d1 / r;
    const Mat3 nn = n * n.transpose();
    const Mat3 h = along * nn + across * (Mat3::Identity() - nn);
    MatN<6> H;
    H << h, -h, -h, h;
    sink->add(ids, 2, g.data(), H.data());
}

}  // namespace

EnergyTerms ClothModel::evaluate(const Positions& x, Derivatives what, StencilSink* sink) const
{
    EnergyTerms e;
    const bool want_grad = what != Derivatives::NONE && sink != nullptr;
    const bool want_hess = want_grad && what != Derivatives::GRADIENT;
    const bool project = what == Derivatives::PROJECTED;
    const int nu = grid_.nu, nv = grid_.nv;

    // Gravity (Eq. 6).
    for (int k = 0; k < grid_.size(); ++k) {
        e.gravity += mass_ * gravity_ * x[k].z();
        if (want_grad) {
            const Vec3 g(0, 0, mass_ * gravity_);
            sink->add(&k, 1, g.data(), nullptr);
        }
    }

    // Stretching on the 4-connected edges (Eq. 3, 5).
    auto edge = [&](int p, int q) {
        const double r = (x[p] - x[q]).norm();
        if (r <= spacing_.sigma) return;
        const Scalar3 s = spacing_.stretch(r);
        e.stretch += s.value;
        const int ids[2] = {p, q};
        if (want_grad) pair_term(s, x[p], x[q], ids, what, sink);
    };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            if (i + 1 < nu) edge(grid_.index(i, j), grid_.index(i + 1, j));
            if (j + 1 < nv) edge(grid_.index(i, j), grid_.index(i, j + 1));
        }

    // Repulsion over all pairs closer than sigma (Eq. 2, 4).
    for (const auto& [p, q] : close_pairs(x)) {
        const double r = (x[p] - x[q]).norm();
        const Scalar3 s = spacing_.repulsion(r);
        e.repulsion += s.value;
        const int ids[2] = {p, q};
        if (want_grad && std::isfinite(s.value)) pair_term(s, x[p], x[q], ids, what, sink);
    }

    // Bending (Eq. 7, 12, 13) of one thread angle: f(c), c = cos(theta).
    auto bend = [&](const BendingEnergy& energy, int p0, int p1, int p2, double& sum) {
        const Vec3 a = x[p0] - x[p1], b = x[p2] - x[p1];
        const CosineDerivatives cd = cosine_between(a, b, want_hess && !project);
        const Scalar3 f = energy.of_cosine(cd.c);
        sum += f.value;
        if (!want_grad || !std::isfinite(f.value)) return;
        const int ids[3] = {p0, p1, p2};
        const VecN<9> g = to_particles<3>(kBendingStencil, VecN<6>(f.d1 * cd.gradient));
        if (!want_hess) {
            sink->add(ids, 3, g.data(), nullptr);
            return;
        }
        MatN<6> Hc;
        if (project)  // Gauss-Newton: f'' >= 0 part of grad c grad c^T, and J^T J in place of c's Hessian (f' >= 0)
            Hc = std::max(f.d2, 0.0) * cd.gradient * cd.gradient.transpose() + std::max(f.d1, 0.0) * bending_gauss_newton(a, b);
        else
            Hc = f.d2 * cd.gradient * cd.gradient.transpose() + f.d1 * cd.hessian;
        const MatN<9> H = to_particles<3>(kBendingStencil, Hc);
        sink->add(ids, 3, g.data(), H.data());
    };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            if (j > 0 && j + 1 < nv) bend(warp_, grid_.index(i, j - 1), grid_.index(i, j), grid_.index(i, j + 1), e.bending_warp);
            if (i > 0 && i + 1 < nu) bend(weft_, grid_.index(i - 1, j), grid_.index(i, j), grid_.index(i + 1, j), e.bending_weft);
        }

    // Trellising (Eq. 8, 15) at interior particles: f(c), c = cos(crossing angle) = -sin(phi).
    for (int j = 1; j + 1 < nv; ++j)
        for (int i = 1; i + 1 < nu; ++i) {
            const int ids[4] = {grid_.index(i - 1, j), grid_.index(i + 1, j), grid_.index(i, j - 1), grid_.index(i, j + 1)};
            const Vec3 u = x[ids[1]] - x[ids[0]], v = x[ids[3]] - x[ids[2]];
            const CosineDerivatives cd = cosine_between(u, v, want_hess && !project);
            const Scalar3 f = trellis_.of_cosine(cd.c);
            e.trellis += f.value;
            if (!want_grad || !std::isfinite(f.value)) continue;
            const VecN<12> g = to_particles<4>(kTrellisStencil, VecN<6>(f.d1 * cd.gradient));
            if (!want_hess) {
                sink->add(ids, 4, g.data(), nullptr);
                continue;
            }
            MatN<6> Hc;
            if (project)  // Gauss-Newton: drops f' times c's (indefinite) Hessian; exact at phi = 0 where f' = 0
                Hc = std::max(f.d2, 0.0) * cd.gradient * cd.gradient.transpose();
            else
                Hc = f.d2 * cd.gradient * cd.gradient.transpose() + f.d1 * cd.hessian;
            const MatN<12> H = to_particles<4>(kTrellisStencil, Hc);
            sink->add(ids, 4, g.data(), H.data());
        }
    return e;
}

namespace {

class GradientSink : public StencilSink {
public:
    explicit GradientSink(Eigen::VectorXd& g) : g_(g) { }
    void add(const int* particles, int n, const double* gradient, const double*) override
    {
        for (int k = 0; k < n; ++k)
            for (int c = 0; c < 3; ++c) g_[3 * particles[k] + c] += gradient[3 * k + c];
    }

private:
    Eigen::VectorXd& g_;
};

}  // namespace

Eigen::VectorXd ClothModel::gradient(const Positions& x) const
{
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * grid_.size());
    GradientSink sink(g);
    evaluate(x, Derivatives::GRADIENT, &sink);
    return g;
}

std::vector<std::pair<int, int>> ClothModel::close_pairs(const Positions& x, double radius) const
{
    // Spatial hash: cells of size radius; particles sorted by cell key, an open-addressing table
    // from key to the run of particles in that cell; each particle looks in the 27 cells around
    // its own.
    const double h = radius > 0 ? radius : spacing_.sigma;
    const int n = static_cast<int>(x.size());
    auto cell_of = [&](const Vec3& p) {
        return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / h)), static_cast<int>(std::floor(p.y() / h)), static_cast<int>(std::floor(p.z() / h)));
    };
    auto key = [](const Eigen::Vector3i& c) {
        constexpr std::int64_t kBias = 1 << 20, kMask = (1 << 21) - 1;
        return ((c.x() + kBias) & kMask) | (((c.y() + kBias) & kMask) << 21) | (((c.z() + kBias) & kMask) << 42);
    };
    std::vector<std::pair<std::int64_t, int>> cells(n);
    for (int k = 0; k < n; ++k) cells[k] = {key(cell_of(x[k])), k};
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

    std::vector<std::pair<int, int>> pairs;
    const double h2 = h * h;
    for (int p = 0; p < n; ++p) {
        const Eigen::Vector3i c = cell_of(x[p]);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::int64_t k = key(c + Eigen::Vector3i(dx, dy, dz));
                    const Slot& slot = table[slot_of(k)];
                    if (slot.key != k) continue;
                    for (int m = slot.begin; m < slot.end; ++m) {
                        const int q = cells[m].second;
                        if (q > p && (x[p] - x[q]).squaredNorm() < h2) pairs.emplace_back(p, q);
                    }
                }
    }
    std::sort(pairs.begin(), pairs.end());  // deterministic order of summation
    return pairs;
}

ClothModel make_cloth_model(const kes::FabricData& fabric, Grid grid, const ModelOptions& options)
{
    const std::string where = "fabric '" + fabric.name + "'";
    const kes::CurveFit warp = kes::fit_first_stage(fabric.bending_warp.curve, kes::bending_fit_options(), where + ": bending.warp");
    const kes::CurveFit weft = kes::fit_first_stage(fabric.bending_weft.curve, kes::bending_fit_options(), where + ": bending.weft");
    const kes::CurveFit shear = kes::fit_first_stage(fabric.shear.curve, kes::shear_fit_options(), where + ": shear");
    const double W = fabric.areal_density_mg_cm2 * units::kMgPerCm2ToKgPerM2;
    const double mass = W * grid.sigma * grid.sigma;  // each particle is a sigma x sigma patch
    const double hang = 0.5 * std::max(grid.nu - 1, grid.nv - 1) * grid.sigma;
    const double C0 = options.C0 > 0 ? options.C0 : choose_C0(W, options.gravity, grid.sigma, hang);
    return ClothModel(grid, mass, options.gravity, ThreadSpacing{C0, grid.sigma},
                      BendingEnergy(warp, grid.sigma, options.bending_form, options.gram_force),
                      BendingEnergy(weft, grid.sigma, options.bending_form, options.gram_force),
                      TrellisEnergy(shear, grid.sigma, options.gram_force));
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
