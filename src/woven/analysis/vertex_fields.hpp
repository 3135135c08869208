#pragma once
// Per-particle fields of a draped state, to colour the drape by (drape.ply, drape.glb): each
// computed here once from the model's own stencils (model/stencils.hpp), so that a field shows
// what the energy term it belongs to sees. Units SI; one value per grid particle (index
// i + nu * j), 0 for a particle outside the cloth (a cut cloth's inactive ones).
#include <string>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::analysis {

/// One named field: `name` (lower case, PLY's property name; glTF's attribute is "_" + upper
/// case), its unit and one value per particle.
struct VertexField {
    std::string name;
    std::string unit;
    std::vector<double> values;
};

struct VertexFields {
    /// Thread strain |x_a - x_b| / sigma - 1 of the warp (along j) and weft (along i) segments
    /// at the particle, the mean over its one or two segments (1; stretching, Eq. 3, 5).
    std::vector<double> strain_warp, strain_weft;
    /// The trellis angle phi = -asin(c) of the particle's crossing, c the cosine between the weft
    /// (R - L) and warp (U - D) directions (rad; 0 at right angles; Eq. 8, 15). One-sided at an
    /// edge as the model measures it; 0 where the model has no crossing.
    std::vector<double> trellis_angle;
    /// Thread curvature K(theta) of the warp and weft bends centred on the particle (1/m;
    /// corrected Eq. 13 with sigma in m: (2/sigma) cos(theta/2) for theta > pi/4, 0 for a
    /// straight thread); 0 at a thread's end, where no bend is centred.
    std::vector<double> curvature_warp, curvature_weft;
    /// 1 where the particle is within the contact distance of an obstacle, else 0.
    std::vector<double> contact;
    /// |F|, the residual force on the particle (N), as given (the solver's residual: -dE/dx
    /// less what the obstacles can hold; 0 at equilibrium, up to the solver's tolerance).
    std::vector<double> residual_force;

    /// The fields above with their names and units, in this order: strain_warp, strain_weft,
    /// trellis_angle, curvature_warp, curvature_weft, contact, residual_force.
    std::vector<VertexField> list() const;
};

/// The fields of the state x (one position per grid particle, m) of `model` among `obstacles`;
/// the contact distance (m) as the solver had it, and the residual force on each particle (N,
/// one per grid particle; empty: zero).
VertexFields vertex_fields(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                           double contact_distance, const Positions& residual_forces = {});

}  // namespace woven::analysis
