#pragma once
// A parametric dress form (a skirt stand): the torso from under the bust to the upper thighs as
// a closed surface of revolution about the vertical axis x = y = 0, with elliptic sections
// (depth = depth_ratio x width), sized by the girths a pattern maker measures. Drawn by woven
// (no third-party mesh): the girth at height z is interpolated smoothly (a cosine blend) between
//
//     waist + 30 cm   0.92 bust          (the stand's top, closed flat)
//     waist + 22 cm   bust
//     waist + 10 cm   waist + 0.4 (bust - waist)
//     waist           waist
//     waist - 10 cm   waist + 0.6 (hip - waist)   (high hip)
//     waist - hip_depth   hip
//     waist - hip_depth - 12 cm   0.97 hip
//     waist - hip_depth - 22 cm   0.90 hip       (the stand's bottom, closed flat)
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::geometry {

/// Sizes (m): girths are circumferences of the elliptic sections.
struct DressFormSizes {
    double bust = 0.88;
    double waist = 0.68;
    double hip = 0.94;
    double waist_height = 1.04;  ///< above the floor (z = 0)
    double hip_depth = 0.20;     ///< from the waist down to the hip line
    double depth_ratio = 0.9;    ///< front-to-back depth over side-to-side width, (0, 1]
};

/// The section's girth at height z (m); 0 above the top and below the bottom.
double dress_form_girth(const DressFormSizes& sizes, double z);
/// The half width a (along x) and half depth b (along y) of the ellipse of girth `girth` (m),
/// b = depth_ratio a (Ramanujan's perimeter).
void ellipse_axes(double girth, double depth_ratio, double& a, double& b);
/// The top and bottom heights of the stand (m).
double dress_form_top(const DressFormSizes& sizes);
double dress_form_bottom(const DressFormSizes& sizes);

/// The closed, outward-facing mesh: `around` vertices per section, one section per `step` m.
TriangleMesh dress_form_mesh(const DressFormSizes& sizes, int around = 96, double step = 0.01);

}  // namespace woven::geometry
