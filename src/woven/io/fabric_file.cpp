#include "woven/io/fabric_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <toml++/toml.h>

#include "woven/common/error.hpp"
#include "woven/io/embedded_data.hpp"

namespace woven::io {
namespace {

constexpr std::string_view kFabricDir = "fabrics/";
constexpr std::string_view kFabricExt = ".toml";

std::string join(const std::string& prefix, std::string_view key)
{
    return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

/// Reads the keys of one table: typed accessors that name the dotted field in errors, and a
/// record of the keys used so that the others can be reported as unknown.
class TableReader {
public:
    TableReader(const toml::table& t, std::string path, const std::string& source)
        : table_(t), path_(std::move(path)), source_(source)
    {
    }

    bool has(std::string_view key) const { return table_.contains(key); }
    std::string field(std::string_view key) const { return join(path_, key); }

    std::optional<std::string> string(std::string_view key, bool required)
    {
        used_.emplace_back(key);
        const toml::node* n = table_.get(key);
        if (!n) {
            if (required) throw InputError(source_, field(key), "missing; expected a string");
            return std::nullopt;
        }
        if (!n->is_string()) throw InputError(source_, field(key), std::string("expected a string, got ") + type_name(*n));
        return n->value<std::string>();
    }

    /// A finite number (TOML integer or float).
    std::optional<double> number(std::string_view key, bool required, const std::string& unit)
    {
        used_.emplace_back(key);
        const toml::node* n = table_.get(key);
        if (!n) {
            if (required) throw InputError(source_, field(key), "missing; expected a number in " + unit);
            return std::nullopt;
        }
        return to_number(*n, field(key), unit);
    }

    /// A positive finite number.
    std::optional<double> positive(std::string_view key, bool required, const std::string& unit)
    {
        auto v = number(key, required, unit);
        if (v && *v <= 0) throw InputError(source_, field(key), "expected a positive number in " + unit + ", got " + format(*v));
        return v;
    }

    /// A non-negative finite number (hysteresis widths).
    std::optional<double> non_negative(std::string_view key, bool required, const std::string& unit)
    {
        auto v = number(key, required, unit);
        if (v && *v < 0) throw InputError(source_, field(key), "expected a non-negative number in " + unit + ", got " + format(*v));
        return v;
    }

    /// An array of finite numbers.
    std::optional<std::vector<double>> numbers(std::string_view key, const std::string& unit)
    {
        used_.emplace_back(key);
        const toml::node* n = table_.get(key);
        if (!n) return std::nullopt;
        const toml::array* a = n->as_array();
        if (!a) throw InputError(source_, field(key), std::string("expected an array of numbers in ") + unit + ", got " + type_name(*n));
        std::vector<double> out;
        out.reserve(a->size());
        for (size_t k = 0; k < a->size(); ++k)
            out.push_back(to_number((*a)[k], field(key) + "[" + std::to_string(k) + "]", unit));
        return out;
    }

    /// A sub-table, or nullptr when absent.
    const toml::table* table(std::string_view key, bool required)
    {
        used_.emplace_back(key);
        const toml::node* n = table_.get(key);
        if (!n) {
            if (required) throw InputError(source_, field(key), "missing; expected a table [" + field(key) + "]");
            return nullptr;
        }
        const toml::table* t = n->as_table();
        if (!t) throw InputError(source_, field(key), std::string("expected a table [") + field(key) + "], got " + type_name(*n));
        return t;
    }

    /// Appends "<source>: unknown key '<path.key>' ignored" for every key not read.
    void report_unknown(std::vector<std::string>& warnings) const
    {
        for (const auto& [k, v] : table_) {
            const std::string_view key = k.str();
            if (std::find(used_.begin(), used_.end(), key) == used_.end())
                warnings.push_back(source_ + ": unknown key '" + field(key) + "' ignored");
        }
    }

private:
    static const char* type_name(const toml::node& n)
    {
        switch (n.type()) {
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a float";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::array: return "an array";
        case toml::node_type::table: return "a table";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        default: return "nothing";
        }
    }

    static std::string format(double v)
    {
        std::ostringstream s;
        s << v;
        return s.str();
    }

    double to_number(const toml::node& n, const std::string& field, const std::string& unit) const
    {
        double v = 0;
        if (const auto* i = n.as_integer()) v = static_cast<double>(i->get());
        else if (const auto* f = n.as_floating_point()) v = f->get();
        else throw InputError(source_, field, "expected a number in " + unit + ", got " + type_name(n));
        if (!std::isfinite(v)) throw InputError(source_, field, "expected a finite number in " + unit + ", got " + format(v));
        return v;
    }

    const toml::table& table_;
    std::string path_;
    const std::string& source_;
    std::vector<std::string_view> used_;
};

/// Summary values or a point list, exactly one of the two.
enum class Form { summary, points };

Form choose_form(const TableReader& r, const std::string& path, const std::string& source,
                 std::initializer_list<std::string_view> summary_keys, std::string_view x_key, std::string_view y_key)
{
    bool any_summary = false;
    std::string summary_names;
    for (auto k : summary_keys) {
        any_summary |= r.has(k);
        summary_names += (summary_names.empty() ? "" : ", ") + std::string(k);
    }
    const bool any_points = r.has(x_key) || r.has(y_key);
    const std::string both = "summary values (" + summary_names + ") or the first-stage curve as point lists (" +
                             std::string(x_key) + ", " + std::string(y_key) + ")";
    if (any_summary && any_points) throw InputError(source, path, "give either " + both + ", not both");
    if (!any_summary && !any_points) throw InputError(source, path, "expected " + both);
    return any_summary ? Form::summary : Form::points;
}

kes::Curve read_points(TableReader& r, const std::string& path, const std::string& source,
                       std::string_view x_key, const std::string& x_unit, std::string_view y_key, const std::string& y_unit)
{
    auto x = r.numbers(x_key, x_unit);
    auto y = r.numbers(y_key, y_unit);
    if (!x) throw InputError(source, r.field(x_key), "missing; expected an array of numbers in " + x_unit + " beside " + std::string(y_key));
    if (!y) throw InputError(source, r.field(y_key), "missing; expected an array of numbers in " + y_unit + " beside " + std::string(x_key));
    if (x->size() != y->size())
        throw InputError(source, path, std::string(x_key) + " and " + std::string(y_key) + " must have the same length (" +
                                           std::to_string(x->size()) + " vs " + std::to_string(y->size()) + ")");
    if (x->size() < 3) throw InputError(source, path, "expected at least 3 points, got " + std::to_string(x->size()));
    return kes::Curve{std::move(*x), std::move(*y)};
}

kes::Measured<kes::BendingSummary> read_bending(const toml::table& t, const std::string& path, const std::string& source,
                                                std::vector<std::string>& warnings)
{
    TableReader r(t, path, source);
    kes::Measured<kes::BendingSummary> m;
    if (choose_form(r, path, source, {"B", "2HB"}, "curvature_per_cm", "moment_gf_cm_per_cm") == Form::summary) {
        kes::BendingSummary s;
        s.B = *r.positive("B", true, "gf.cm^2/cm");
        s.two_HB = *r.non_negative("2HB", true, "gf.cm/cm");
        m.summary = s;
        m.curve = kes::synthesize_bending_curve(s);
    } else {
        m.curve = read_points(r, path, source, "curvature_per_cm", "1/cm", "moment_gf_cm_per_cm", "gf.cm/cm");
    }
    r.report_unknown(warnings);
    return m;
}

kes::Measured<kes::ShearSummary> read_shear(const toml::table& t, const std::string& source, std::vector<std::string>& warnings)
{
    const std::string path = "shear";
    TableReader r(t, path, source);
    kes::Measured<kes::ShearSummary> m;
    if (choose_form(r, path, source, {"G", "2HG", "2HG5"}, "angle_deg", "force_gf_per_cm") == Form::summary) {
        kes::ShearSummary s;
        s.G = *r.positive("G", true, "gf/(cm.deg)");
        s.two_HG = *r.non_negative("2HG", true, "gf/cm");
        s.two_HG5 = *r.non_negative("2HG5", true, "gf/cm");
        m.summary = s;
        m.curve = kes::synthesize_shear_curve(s);
    } else {
        m.curve = read_points(r, path, source, "angle_deg", "degrees", "force_gf_per_cm", "gf/cm");
    }
    r.report_unknown(warnings);
    return m;
}

kes::TensileSummary read_tensile(const toml::table& t, const std::string& source, std::vector<std::string>& warnings)
{
    TableReader r(t, "tensile", source);
    kes::TensileSummary s;
    s.LT = *r.non_negative("LT", true, "(dimensionless)");
    s.WT = *r.non_negative("WT", true, "gf.cm/cm^2");
    s.RT = *r.non_negative("RT", true, "%");
    s.EMT = *r.non_negative("EMT", true, "%");
    r.report_unknown(warnings);
    return s;
}

bool ends_with(std::string_view s, std::string_view suffix)
{
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

}  // namespace

kes::FabricData parse_fabric(std::string_view toml_text, const std::string& source, std::vector<std::string>* warnings_out)
{
    toml::table root;
#if TOML_EXCEPTIONS
    try {
        root = toml::parse(toml_text, source);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        throw InputError(source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) + ": " + std::string(e.description()));
    }
#else
    toml::parse_result result = toml::parse(toml_text, source);
    if (!result) {
        const auto& e = result.error();
        const auto& b = e.source().begin;
        throw InputError(source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) + ": " + std::string(e.description()));
    }
    root = std::move(result).table();
#endif

    std::vector<std::string> warnings;
    TableReader r(root, "", source);
    kes::FabricData f;
    f.name = *r.string("name", true);
    if (f.name.empty()) throw InputError(source, "name", "expected a non-empty string");
    f.description = r.string("description", false).value_or("");
    f.source = *r.string("source", true);
    if (f.source.empty()) throw InputError(source, "source", "expected where the numbers come from (a citation)");
    f.representative = r.string("representative", false).value_or("");
    f.areal_density_mg_cm2 = *r.positive("areal_density_mg_cm2", true, "mg/cm^2");
    f.thickness_mm = r.positive("thickness_mm", false, "mm");

    const toml::table* bending = r.table("bending", true);
    TableReader rb(*bending, "bending", source);
    f.bending_warp = read_bending(*rb.table("warp", true), "bending.warp", source, warnings);
    f.bending_weft = read_bending(*rb.table("weft", true), "bending.weft", source, warnings);
    rb.report_unknown(warnings);

    f.shear = read_shear(*r.table("shear", true), source, warnings);
    if (const toml::table* tensile = r.table("tensile", false)) f.tensile = read_tensile(*tensile, source, warnings);
    r.report_unknown(warnings);

    // Value-level checks (ranges, curve shape): kes::validate throws InputError naming the field.
    for (auto& w : kes::validate(f, source)) warnings.push_back(source + ": " + w);
    if (warnings_out) warnings_out->insert(warnings_out->end(), warnings.begin(), warnings.end());
    return f;
}

kes::FabricData load_fabric_file(const std::string& path, std::vector<std::string>* warnings)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot read file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(path, "", "cannot read file");
    return parse_fabric(text.str(), path, warnings);
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
    throw InputError("", "fabric", "unknown fabric '" + name_or_path + "'; expected a built-in fabric (" + list +
                                       ") or a fabric file path ending in .toml");
}

}  // namespace woven::io
