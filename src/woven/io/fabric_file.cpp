#include "woven/io/fabric_file.hpp"
#include "woven/io/values.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <filesystem>

#include "woven/common/error.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {
namespace {

constexpr std::string_view kFabricDir = "fabrics/";
constexpr std::string_view kFabricExt = ".toml";

/// The reader's ranges are loose (kes::validate applies the KES ranges): finite and of the
/// right sign.
Range positive(const std::string& unit) { return Range{0, 1e9, true, unit}; }
Range non_negative(const std::string& unit) { return Range{0, 1e9, false, unit}; }
Range any(const std::string& unit) { return Range{-1e9, 1e9, false, unit}; }

/// kes::validate's ranges of the summary values B and G, applied to a curve's slope as well.
const Range kBendingRigidityRange{1e-4, 50, false, "gf.cm^2/cm"};
const Range kShearRigidityRange{1e-3, 50, false, "gf/(cm.deg)"};

/// Summary values or a point list, exactly one of the two.
enum class Form { summary, points };

Form choose_form(const TomlTable& t, std::initializer_list<std::string_view> summary_keys, std::string_view x_key,
                 std::string_view y_key)
{
    bool any_summary = false;
    std::string summary_names;
    for (auto k : summary_keys) {
        any_summary |= t.has(k);
        summary_names += (summary_names.empty() ? "" : ", ") + std::string(k);
    }
    const bool any_points = t.has(x_key) || t.has(y_key);
    const std::string both = "summary values (" + summary_names + ") or the first-stage curve as point lists (" +
                             std::string(x_key) + ", " + std::string(y_key) + ")";
    if (any_summary && any_points) t.fail_self("give either " + both + ", not both");
    if (!any_summary && !any_points) t.fail_self("expected " + both);
    return any_summary ? Form::summary : Form::points;
}

kes::Curve read_points(const TomlTable& t, std::string_view x_key, const std::string& x_unit, std::string_view y_key,
                       const std::string& y_unit)
{
    auto x = t.numbers(x_key, any(x_unit));
    auto y = t.numbers(y_key, any(y_unit));
    if (!x) t.fail(x_key, "missing; expected an array of numbers in " + x_unit + " beside " + std::string(y_key));
    if (!y) t.fail(y_key, "missing; expected an array of numbers in " + y_unit + " beside " + std::string(x_key));
    return kes::Curve{std::move(*x), std::move(*y)};
}

kes::Measured<kes::BendingSummary> read_bending(const TomlTable& t)
{
    kes::Measured<kes::BendingSummary> m;
    if (choose_form(t, {"B", "2HB"}, "curvature_per_cm", "moment_gf_cm_per_cm") == Form::summary) {
        kes::BendingSummary s;
        s.B = t.number("B", positive("gf.cm^2/cm"), std::nullopt);
        s.two_HB = t.number("2HB", non_negative("gf.cm/cm"), std::nullopt);
        m.summary = s;
        m.curve = kes::synthesize_bending_curve(s);
    } else {
        m.curve = read_points(t, "curvature_per_cm", "1/cm", "moment_gf_cm_per_cm", "gf.cm/cm");
    }
    return m;
}

kes::Measured<kes::ShearSummary> read_shear(const TomlTable& t)
{
    kes::Measured<kes::ShearSummary> m;
    if (choose_form(t, {"G", "2HG", "2HG5"}, "angle_deg", "force_gf_per_cm") == Form::summary) {
        kes::ShearSummary s;
        s.G = t.number("G", positive("gf/(cm.deg)"), std::nullopt);
        s.two_HG = t.number("2HG", non_negative("gf/cm"), std::nullopt);
        s.two_HG5 = t.number("2HG5", non_negative("gf/cm"), std::nullopt);
        m.summary = s;
        m.curve = kes::synthesize_shear_curve(s);
    } else {
        m.curve = read_points(t, "angle_deg", "degrees", "force_gf_per_cm", "gf/cm");
    }
    return m;
}

kes::TensileSummary read_tensile(const TomlTable& t)
{
    kes::TensileSummary s;
    s.LT = t.number("LT", non_negative("(dimensionless)"), std::nullopt);
    s.WT = t.number("WT", non_negative("gf.cm/cm^2"), std::nullopt);
    s.RT = t.number("RT", non_negative("%"), std::nullopt);
    s.EMT = t.number("EMT", non_negative("%"), std::nullopt);
    return s;
}

/// The KES slope of a curve given as points must lie in the range kes::validate gives the
/// summary value (B: 1e-4 .. 50 gf.cm^2/cm, G: 1e-3 .. 50 gf/(cm.deg)).
void check_curve_slope(const kes::Curve& c, double from, double to, const Range& range, const std::string& source,
                       const std::string& field, const std::string& what)
{
    // The slope is a least-squares fit of the curve's points: one at exactly a documented end
    // (1e-4 written as a curve) comes out a rounding off it (9.999999999998899e-05). Within a
    // relative 1e-12 of an end it counts as that end.
    const double slope = kes::data_slope(c, from, to);
    auto near = [slope](double end) { return std::abs(slope - end) <= 1e-12 * std::abs(end); };
    const bool at_end = (!range.lo_open && near(range.lo)) || near(range.hi);
    if (!(std::isfinite(slope) && (range.contains(slope) || at_end)))
        throw InputError(source, field,
                         "the curve's slope " + what + " (" + num_str(from) + " .. " + num_str(to) + ") is " +
                             num_str(slope) + "; expected " + range.str());
}

bool ends_with(std::string_view s, std::string_view suffix)
{
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

}  // namespace

namespace {

kes::FabricData read_fabric(const TomlReader& reader, std::vector<std::string>* warnings_out)
{
    const std::string& source = reader.source();
    const TomlTable r = reader.root();
    kes::FabricData f;
    f.name = r.string("name", std::nullopt);
    if (f.name.empty()) r.fail("name", "expected a non-empty string");
    if (printable(f.name) != f.name) r.fail("name", "expected a name of at most 80 characters without control characters");
    f.description = r.string("description", "");
    f.source = r.string("source", std::nullopt);
    if (f.source.empty()) r.fail("source", "expected where the numbers come from (a citation)");
    f.representative = r.string("representative", "");
    f.areal_density_mg_cm2 = r.number("areal_density_mg_cm2", positive("mg/cm^2"), std::nullopt);
    f.thickness_mm = r.opt_number("thickness_mm", positive("mm"));

    const TomlTable bending = *r.table("bending", true);
    f.bending_warp = read_bending(*bending.table("warp", true));
    f.bending_weft = read_bending(*bending.table("weft", true));
    if (const auto bias = bending.table("bias")) f.bias_B = bias->number("B", positive("gf.cm^2/cm"), std::nullopt);
    f.shear = read_shear(*r.table("shear", true));
    if (const auto tensile = r.table("tensile")) f.tensile = read_tensile(*tensile);
    if (r.has("color")) {  // display colour only (docs/FABRIC-FORMAT.md)
        const Eigen::Vector3d c = r.vec<3>("color", Range{0, 1, false, "(sRGB)"}, std::nullopt);
        f.color = std::array<double, 3>{c[0], c[1], c[2]};
    }
    std::vector<std::string> warnings = reader.unknown_keys();

    // Value-level checks (ranges, curve shape): kes::validate throws InputError naming the field.
    for (auto& w : kes::validate(f, source)) warnings.push_back(source + ": " + w);
    namespace ki = kes::instrument;
    if (!f.bending_warp.summary)
        check_curve_slope(f.bending_warp.curve, ki::kBendingSlopeFrom, ki::kBendingSlopeTo, kBendingRigidityRange,
                          source, "bending.warp", "B");
    if (!f.bending_weft.summary)
        check_curve_slope(f.bending_weft.curve, ki::kBendingSlopeFrom, ki::kBendingSlopeTo, kBendingRigidityRange,
                          source, "bending.weft", "B");
    if (!f.shear.summary)
        check_curve_slope(f.shear.curve, ki::kShearSlopeFrom, ki::kShearSlopeTo, kShearRigidityRange, source, "shear",
                          "G");
    if (warnings_out) warnings_out->insert(warnings_out->end(), warnings.begin(), warnings.end());
    return f;
}

}  // namespace

kes::FabricData parse_fabric(std::string_view toml_text, const std::string& source, std::vector<std::string>* warnings)
{
    return read_fabric(TomlReader(toml_text, source), warnings);
}

kes::FabricData fabric_from_values(const nlohmann::json& values, const std::string& source, std::vector<std::string>* warnings)
{
    return read_fabric(TomlReader(table_from_values(values, source), source), warnings);
}

kes::FabricData load_fabric_file(const std::string& path, std::vector<std::string>* warnings)
{
    return parse_fabric(read_input_file(path, kMaxTomlBytes, {"fabric file", "a fabric .toml file"}), path, warnings);
}

std::vector<std::string> builtin_fabric_names()
{
    std::vector<std::string> names;
    for (const auto& file : data::embedded_files()) {
        const std::string_view p = file.path;
        if (p.substr(0, kFabricDir.size()) != kFabricDir || !ends_with(p, kFabricExt)) continue;
        const std::string_view stem = p.substr(kFabricDir.size(), p.size() - kFabricDir.size() - kFabricExt.size());
        if (stem.find('/') == std::string_view::npos) names.emplace_back(stem);
    }
    std::sort(names.begin(), names.end());
    return names;
}

kes::FabricData find_fabric(const std::string& name_or_path, std::vector<std::string>* warnings)
{
    if (ends_with(name_or_path, kFabricExt) || name_or_path.find('/') != std::string::npos)
        return load_fabric_file(name_or_path, warnings);
    const std::string wanted = std::string(kFabricDir) + name_or_path + std::string(kFabricExt);
    for (const auto& file : data::embedded_files())
        if (file.path == wanted) return parse_fabric(file.data, "built-in fabric '" + name_or_path + "'", warnings);
    std::string list;
    for (const auto& n : builtin_fabric_names()) list += (list.empty() ? "" : ", ") + n;
    throw InputError(printable(name_or_path), "fabric",
                     "no such built-in fabric; expected a built-in fabric (" + list +
                         ") or a fabric file path ending in .toml");
}

}  // namespace woven::io
