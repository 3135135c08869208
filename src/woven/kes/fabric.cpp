#include "woven/kes/fabric.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "woven/common/error.hpp"

namespace woven::kes {

Curve synthesize_bending_curve(const BendingSummary& s)
{
    constexpr double kRise = kBendingRise;  // 1/cm: the initial-resistance region ends here
    constexpr int kPoints = 51;
    Curve c;
    for (int k = 0; k < kPoints; ++k) {
        const double K = instrument::kBendingMaxCurvature * k / (kPoints - 1);
        const double u = std::min(K / kRise, 1.0);
        c.x.push_back(K);
        c.y.push_back(s.B * K + 0.5 * s.two_HB * (1.0 - (1.0 - u) * (1.0 - u)));
    }
    return c;
}

Curve synthesize_shear_curve(const ShearSummary& s)
{
    constexpr double kRise = kShearRise;  // degrees
    constexpr int kPoints = 33;
    const double half_width = 0.25 * (s.two_HG + s.two_HG5);  // mean of 2HG/2 and 2HG5/2
    Curve c;
    for (int k = 0; k < kPoints; ++k) {
        const double phi = instrument::kShearMaxAngle * k / (kPoints - 1);
        const double u = std::min(phi / kRise, 1.0);
        c.x.push_back(phi);
        c.y.push_back(s.G * phi + half_width * (1.0 - (1.0 - u) * (1.0 - u)));
    }
    return c;
}

FabricData without_hysteresis(const FabricData& fabric)
{
    FabricData f = fabric;
    for (Measured<BendingSummary>* b : {&f.bending_warp, &f.bending_weft})
        if (b->summary && b->summary->two_HB > 0) {
            b->summary->two_HB = 0;
            b->curve = synthesize_bending_curve(*b->summary);
        }
    if (f.shear.summary && (f.shear.summary->two_HG > 0 || f.shear.summary->two_HG5 > 0)) {
        f.shear.summary->two_HG = f.shear.summary->two_HG5 = 0;
        f.shear.curve = synthesize_shear_curve(*f.shear.summary);
    }
    return f;
}

FitOptions bending_fit_options()
{
    FitOptions o;
    o.line_from = instrument::kBendingSlopeFrom;
    o.slope_from = instrument::kBendingSlopeFrom;
    o.slope_to = instrument::kBendingSlopeTo;
    return o;
}

FitOptions shear_fit_options()
{
    FitOptions o;
    o.line_from = instrument::kShearSlopeFrom;
    o.slope_from = instrument::kShearSlopeFrom;
    o.slope_to = instrument::kShearSlopeTo;
    return o;
}

void validate_curve(const Curve& c, const std::string& source, const std::string& field, double x_limit)
{
    if (c.x.size() != c.y.size())
        throw InputError(source, field, "abscissa and ordinate lists must have the same length (" + std::to_string(c.x.size()) + " vs " + std::to_string(c.y.size()) + ")");
    if (c.x.size() < 3) throw InputError(source, field, "expected at least 3 points, got " + std::to_string(c.x.size()));
    for (size_t k = 0; k < c.x.size(); ++k) {
        if (!std::isfinite(c.x[k]) || !std::isfinite(c.y[k]))
            throw InputError(source, field, "point " + std::to_string(k) + " is not a finite number");
        if (c.x[k] < 0 || c.y[k] < 0)
            throw InputError(source, field, "point " + std::to_string(k) + " is negative; expected the first-stage loading curve (x >= 0, y >= 0)");
        if (c.x[k] > x_limit) {
            std::ostringstream m;
            m << "point " << k << " has abscissa " << c.x[k] << ", beyond the instrument's range " << x_limit;
            throw InputError(source, field, m.str());
        }
        if (k > 0 && c.x[k] <= c.x[k - 1])
            throw InputError(source, field, "abscissae must be strictly increasing (point " + std::to_string(k) + ")");
        if (k > 0 && c.y[k] < c.y[k - 1])
            throw InputError(source, field, "ordinates must be non-decreasing along a loading curve (point " + std::to_string(k) + " decreases)");
    }
}

namespace {

void check_range(double v, double lo, double hi, const std::string& source, const std::string& field, const std::string& unit)
{
    std::ostringstream m;
    // Worded as the file readers word their ranges (io::Range::str): "[lo, hi] unit".
    if (!std::isfinite(v) || v < lo || v > hi) {
        m << "expected a number in [" << lo << ", " << hi << "] " << unit;
        if (std::isfinite(v)) m << ", got " << v;
        throw InputError(source, field, m.str());
    }
}

void warn_range(double v, double lo, double hi, const std::string& field, const std::string& unit, std::vector<std::string>& warnings)
{
    if (v < lo || v > hi) {
        std::ostringstream m;
        m << field << " = " << v << " " << unit << " is outside the typical woven-fabric range " << lo << "-" << hi;
        warnings.push_back(m.str());
    }
}

}  // namespace

std::vector<std::string> validate(const FabricData& f, const std::string& source)
{
    std::vector<std::string> warnings;
    if (f.name.empty()) throw InputError(source, "name", "expected a non-empty string");
    if (f.source.empty()) throw InputError(source, "source", "expected where the numbers come from");
    check_range(f.areal_density_mg_cm2, 0.5, 500, source, "areal_density_mg_cm2", "mg/cm^2 (W)");
    warn_range(f.areal_density_mg_cm2, 2, 60, "areal_density_mg_cm2", "mg/cm^2", warnings);
    if (f.thickness_mm) check_range(*f.thickness_mm, 0.005, 20, source, "thickness_mm", "mm");

    auto check_bending = [&](const Measured<BendingSummary>& m, const std::string& dir) {
        const std::string field = "bending." + dir;
        if (m.summary) {
            check_range(m.summary->B, 1e-4, 50, source, field + ".B", "gf.cm^2/cm");
            check_range(m.summary->two_HB, 0, 50, source, field + ".2HB", "gf.cm/cm");
            warn_range(m.summary->B, 0.005, 3, field + ".B", "gf.cm^2/cm", warnings);
        }
        validate_curve(m.curve, source, field, 5.0);
        if (m.curve.y.back() <= 0) throw InputError(source, field, "expected a positive moment at the largest curvature");
    };
    check_bending(f.bending_warp, "warp");
    check_bending(f.bending_weft, "weft");
    // B_45 below the threads' own share is refused where the model is built
    // (model::fabric_twist_rigidity), on the fitted curves.
    if (f.bias_B) check_range(*f.bias_B, 1e-4, 50, source, "bending.bias.B", "gf.cm^2/cm");
    if (f.shear.summary) {
        check_range(f.shear.summary->G, 1e-3, 50, source, "shear.G", "gf/(cm.deg)");
        check_range(f.shear.summary->two_HG, 0, 100, source, "shear.2HG", "gf/cm");
        check_range(f.shear.summary->two_HG5, 0, 100, source, "shear.2HG5", "gf/cm");
        warn_range(f.shear.summary->G, 0.1, 10, "shear.G", "gf/(cm.deg)", warnings);
    }
    validate_curve(f.shear.curve, source, "shear", 30.0);
    if (f.shear.curve.y.back() <= 0) throw InputError(source, "shear", "expected a positive force at the largest angle");
    if (f.tensile) {
        check_range(f.tensile->LT, 0, 2, source, "tensile.LT", "(dimensionless)");
        check_range(f.tensile->WT, 0, 1000, source, "tensile.WT", "gf.cm/cm^2");
        check_range(f.tensile->RT, 0, 100, source, "tensile.RT", "%");
        check_range(f.tensile->EMT, 0, 100, source, "tensile.EMT", "%");
    }
    return warnings;
}

}  // namespace woven::kes
