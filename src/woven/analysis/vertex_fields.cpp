#include "woven/analysis/vertex_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "woven/common/error.hpp"
#include "woven/model/curvature.hpp"

namespace woven::analysis {

namespace {

/// The particle a crossing {L, R, D, U} is centred on (stencils.hpp): between L and R when both
/// are its neighbours, else the one of L, R it shares with D, U (a one-sided crossing's centre
/// stands in for its missing neighbour).
int crossing_centre(const model::Stencil<4>& s, int nu)
{
    if (s[1] - s[0] == 2) return s[0] + 1;
    if (s[3] - s[2] == 2 * nu) return s[2] + nu;
    return (s[0] == s[2] || s[0] == s[3]) ? s[0] : s[1];
}

/// The angle at the middle particle of a bend, theta = acos(a.b / (|a||b|)) (angle.hpp).
double bend_angle(const Positions& x, const model::Stencil<3>& s)
{
    const Vec3 a = x[s[0]] - x[s[1]], b = x[s[2]] - x[s[1]];
    const double c = a.dot(b) / (a.norm() * b.norm());
    return std::acos(std::clamp(c, -1.0, 1.0));
}

}  // namespace

std::vector<VertexField> VertexFields::list() const
{
    return {{"strain_warp", "1", strain_warp},         {"strain_weft", "1", strain_weft},
            {"trellis_angle", "rad", trellis_angle},   {"curvature_warp", "1/m", curvature_warp},
            {"curvature_weft", "1/m", curvature_weft}, {"contact", "1", contact},
            {"residual_force", "N", residual_force}};
}

VertexFields vertex_fields(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                           double contact_distance, const Positions& residual_forces)
{
    if (!residual_forces.empty() && residual_forces.size() != x.size())
        throw InputError("", "residual_forces", "needs one force per particle, or none");
    const model::Grid& grid = model.grid();
    const model::Stencils& st = model.stencils();
    const std::size_t n = x.size();
    const double sigma = grid.sigma;
    VertexFields f;
    for (auto* v : {&f.strain_warp, &f.strain_weft, &f.trellis_angle, &f.curvature_warp, &f.curvature_weft, &f.contact,
                    &f.residual_force})
        v->assign(n, 0.0);

    // Strain: each segment's strain to both its ends, then the mean at each particle.
    std::vector<int> warp_count(n, 0), weft_count(n, 0);
    for (const auto& e : st.edges) {
        const double s = (x[e[0]] - x[e[1]]).norm() / sigma - 1.0;
        const bool warp = e[1] - e[0] == grid.nu;  // (i, j)-(i, j+1); else (i, j)-(i+1, j)
        auto& field = warp ? f.strain_warp : f.strain_weft;
        auto& count = warp ? warp_count : weft_count;
        for (int p : e) {
            field[p] += s;
            ++count[p];
        }
    }
    for (std::size_t p = 0; p < n; ++p) {
        if (warp_count[p]) f.strain_warp[p] /= warp_count[p];
        if (weft_count[p]) f.strain_weft[p] /= weft_count[p];
    }

    for (const auto& c : st.crossings) {
        const Vec3 u = x[c[1]] - x[c[0]], v = x[c[3]] - x[c[2]];
        const double cosine = u.dot(v) / (u.norm() * v.norm());
        f.trellis_angle[crossing_centre(c, grid.nu)] = -std::asin(std::clamp(cosine, -1.0, 1.0));
    }
    for (const auto& b : st.warp_bends) f.curvature_warp[b[1]] = model::thread_curvature(bend_angle(x, b), sigma).K;
    for (const auto& b : st.weft_bends) f.curvature_weft[b[1]] = model::thread_curvature(bend_angle(x, b), sigma).K;

    for (int p : st.particles) {
        double nearest = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < obstacles.size(); ++k) nearest = std::min(nearest, obstacles[k].distance(x[p]));
        f.contact[p] = nearest < contact_distance ? 1.0 : 0.0;
    }
    if (!residual_forces.empty())
        for (int p : st.particles) f.residual_force[p] = residual_forces[p].norm();
    return f;
}

}  // namespace woven::analysis
