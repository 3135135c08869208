#pragma once
// Shared fixtures of the sim tests: a cotton-like fabric from KES summary values, scenes.
#include <memory>

#include "woven/geometry/primitives.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/drape.hpp"

namespace woven::test {

/// Cotton shirting within the ranges of KES-DATA (weft bending stiffer, as the paper's cotton).
inline kes::FabricData cotton_like()
{
    kes::FabricData f;
    f.name = "test-cotton";
    f.source = "test fixture";
    f.areal_density_mg_cm2 = 12.0;
    f.bending_warp.summary = kes::BendingSummary{0.06, 0.04};
    f.bending_weft.summary = kes::BendingSummary{0.15, 0.08};
    f.shear.summary = kes::ShearSummary{1.5, 2.0, 3.0};
    f.bending_warp.curve = kes::synthesize_bending_curve(*f.bending_warp.summary);
    f.bending_weft.curve = kes::synthesize_bending_curve(*f.bending_weft.summary);
    f.shear.curve = kes::synthesize_shear_curve(*f.shear.summary);
    return f;
}

/// The same fabric with equal warp and weft bending (a 4-fold symmetric cloth).
inline kes::FabricData balanced()
{
    kes::FabricData f = cotton_like();
    f.bending_weft = f.bending_warp;
    return f;
}

/// The paper's literal discretisation (model/stencils.hpp): the paper solver reproduces the
/// paper with it; the convergent default's stiff threads cap its time step far below the
/// paper's (sqrt(m / 4 S'')), so the tests comparing it with the fast solver use this.
inline model::ModelOptions paper_model()
{
    model::ModelOptions o;
    o.discretization = model::Discretization::PAPER;
    return o;
}

/// An n x n grid of side `size` (m).
inline model::Grid square_grid(int n, double size) { return model::Grid{n, n, size / (n - 1)}; }

}  // namespace woven::test
