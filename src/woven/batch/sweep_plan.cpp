#include "woven/batch/sweep_plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/scene_obstacles.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::batch {

using namespace woven::io;

namespace fs = std::filesystem;

namespace {

enum class Kind { FABRIC, SCENE, INTEGER, NUMBER, CHOICE };

/// A key a plan may set: the commands that take it, its command-line option ("" for the
/// positional argument) and its bounds (those of the command's own parser, cli/cmd_*.cpp).
struct KeySpec {
    const char* key;
    const char* commands;  ///< space-separated
    const char* option;
    Kind kind;
    double lo = 0, hi = 0;
    bool lo_open = false;
    std::vector<const char*> choices = {};
};

const std::vector<KeySpec>& key_specs()
{
    static const std::vector<KeySpec> specs = {
        {"scene", "drape", "", Kind::SCENE},
        {"fabric", "cusick kes-test", "", Kind::FABRIC},
        {"fabric", "drape", "--fabric", Kind::FABRIC},
        {"seed", "drape cusick", "--seed", Kind::INTEGER, 0, 9e15},
        {"seeds", "cusick", "--seeds", Kind::INTEGER, 1, 1000},
        {"grid", "drape", "--grid", Kind::INTEGER, 3, 100000},
        {"spacing_cm", "cusick", "--spacing-cm", Kind::NUMBER, 0, 10, true},
        {"specimen_cm", "cusick", "--specimen-cm", Kind::NUMBER, 0, 200, true},
        {"disc_cm", "cusick", "--disc-cm", Kind::NUMBER, 0, 200, true},
        {"solver", "drape", "--solver", Kind::CHOICE, 0, 0, false, names_of(sim::kSolverKindNames)},
        {"perturb_m", "drape", "--perturb", Kind::NUMBER, 0, 0.1},
        {"max_steps", "drape cusick", "--max-steps", Kind::INTEGER, 0, 1'000'000},
        {"threads", "drape cusick", "--threads", Kind::INTEGER, 0, 4096},
        {"width", "drape", "--width", Kind::INTEGER, 1, 16384},
        {"height", "drape", "--height", Kind::INTEGER, 1, 16384},
        {"shear_law", "cusick kes-test", "--shear-law", Kind::CHOICE, 0, 0, false, names_of(model::kShearLawNames)},
        {"test", "kes-test", "--test", Kind::CHOICE, 0, 0, false, {"cantilever", "bending", "shear", "all"}},
        {"direction", "kes-test", "--direction", Kind::CHOICE, 0, 0, false, {"warp", "weft", "both"}},
        {"sigma_cm", "kes-test", "--sigma-cm", Kind::NUMBER, 0.02, 2},
        {"shear_length_cm", "kes-test", "--shear-length-cm", Kind::NUMBER, 5, 200},
        {"bending_form", "kes-test", "--bending-form", Kind::CHOICE, 0, 0, false, {"work", "secant"}},
        {"discretization", "kes-test", "--discretization", Kind::CHOICE, 0, 0, false, names_of(model::kDiscretizationNames)},
    };
    return specs;
}

bool takes(const KeySpec& s, const std::string& command)
{
    // Called per value and per point (a million of each): no stream.
    for (std::string_view c = s.commands; !c.empty();) {
        const std::size_t space = c.find(' ');
        if (c.substr(0, space) == command) return true;
        if (space == std::string_view::npos) break;
        c.remove_prefix(space + 1);
    }
    return false;
}

const KeySpec* find_spec(const std::string& key, const std::string& command)
{
    for (const auto& s : key_specs())
        if (s.key == key && takes(s, command)) return &s;
    return nullptr;
}

std::string keys_of(const std::string& command)
{
    std::string out;
    for (const auto& s : key_specs())
        if (takes(s, command)) out += (out.empty() ? "" : ", ") + std::string(s.key);
    out += command == "drape" ? ", scene.<key>, fabric.<key>" : ", fabric.<key>";
    return out;
}

/// An override key: "scene.<dotted key>" (drape) or "fabric.<dotted key>".
bool is_override(const std::string& key, const std::string& command)
{
    const bool scene = key.rfind("scene.", 0) == 0 && key.size() > 6 && command == "drape";
    const bool fabric = key.rfind("fabric.", 0) == 0 && key.size() > 7;
    return scene || fabric;
}

std::string stem_label(const std::string& path) { return fs::path(path).stem().string(); }

std::string join_names(const std::vector<std::string>& names)
{
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

/// A value as TOML text: numbers shortest ("0.1"), strings quoted, arrays "[9, 9]".
std::string toml_literal(const toml::node& n)
{
    if (const auto* i = n.as_integer()) return std::to_string(i->get());
    if (const auto* f = n.as_floating_point()) {
        std::string t = num_str(f->get());
        if (t.find_first_of(".eE") == std::string::npos) t += ".0";  // stays a float
        return t;
    }
    if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* a = n.as_array()) {
        std::string out = "[";
        for (std::size_t k = 0; k < a->size(); ++k) out += (k == 0 ? "" : ", ") + toml_literal(*a->get(k));
        return out + "]";
    }
    if (const auto* t = n.as_table()) {  // an inline table (in an array of tables): {key = value, ...}
        std::string out = "{";
        bool first = true;
        for (const auto& [k, v] : *t) {
            out += (first ? "" : ", ") + toml_literal(toml::value<std::string>(std::string(k.str()))) + " = " + toml_literal(v);
            first = false;
        }
        return out + "}";
    }
    if (const auto* s = n.as_string()) {
        std::string out = "\"";
        for (const char c : s->get()) {
            if (c == '"' || c == '\\') out += '\\';
            if (static_cast<unsigned char>(c) < 0x20) {
                char b[8];
                std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(c));
                out += b;
                continue;
            }
            out += c;
        }
        return out + "\"";
    }
    return "\"\"";
}

/// Reads one scalar value of `key` into a SweepValue; `field` names it in errors.
SweepValue read_value(const TomlTable& t, const toml::node& n, const std::string& field, const std::string& key,
                      const std::string& command, const std::string& base_dir)
{
    SweepValue v;
    v.key = key;
    if (is_override(key, command)) {
        // Kept as a TOML literal ("0.1", "[9, 9]", "\"wool\"", "true"), set into the point's
        // copy of the scene or fabric file by apply_toml_overrides.
        const bool array = n.is_array();
        if (!(n.is_integer() || n.is_floating_point() || n.is_string() || n.is_boolean() || array))
            t.fail_at(field, "expected a number, a string, a boolean or an array for a " + key.substr(0, key.find('.')) + " key" +
                                 TomlReader::at(n));
        if (n.is_floating_point() && !std::isfinite(n.as_floating_point()->get())) t.fail_at(field, "expected a finite number" + TomlReader::at(n));
        // -0.0 is the value 0.0 (one point, not two).
        v.text = n.is_floating_point() && n.as_floating_point()->get() == 0 ? std::string("0.0") : toml_literal(n);
        v.number = n.is_integer() || n.is_floating_point();
        if (const auto* s = n.as_string()) {
            v.label = s->get();
        } else if (const auto* a = n.as_array()) {
            for (std::size_t k = 0; k < a->size(); ++k) v.label += (k == 0 ? "" : "x") + toml_literal(*a->get(k));
        } else {
            v.label = v.text;
        }
        return v;
    }
    const KeySpec* spec = find_spec(key, command);
    if (!spec) t.fail(key, "unknown key for command " + command + "; expected one of " + keys_of(command));
    switch (spec->kind) {
    case Kind::INTEGER: {
        const long long i = t.to_integer(n, field, static_cast<long long>(spec->lo), static_cast<long long>(spec->hi));
        v.text = v.label = std::to_string(i);
        v.number = true;
        break;
    }
    case Kind::NUMBER: {
        const double x = t.to_number(n, field, Range{spec->lo, spec->hi, spec->lo_open, ""}) + 0.0;  // -0.0 is 0.0
        v.text = v.label = num_str(x);
        v.number = true;
        break;
    }
    case Kind::CHOICE: {
        const auto* s = n.as_string();
        std::string expected;
        for (std::size_t k = 0; k < spec->choices.size(); ++k)
            expected += (k == 0 ? "" : k + 1 == spec->choices.size() ? " or " : ", ") + std::string(spec->choices[k]);
        if (!s || std::find(spec->choices.begin(), spec->choices.end(), s->get()) == spec->choices.end())
            t.fail_at(field, "expected " + expected + (s ? ", got '" + printable(s->get()) + "'" : "") + TomlReader::at(n));
        v.text = v.label = s->get();
        break;
    }
    case Kind::FABRIC:
    case Kind::SCENE: {
        const bool fabric = spec->kind == Kind::FABRIC;
        const auto* s = n.as_string();
        const std::vector<std::string> builtin = fabric ? builtin_fabric_names() : builtin_scene_names();
        const std::string what = fabric ? "a built-in fabric (" + join_names(builtin) + ") or a fabric .toml file"
                                        : "a built-in scene (" + join_names(builtin) + ") or a scene .toml file";
        if (!s || s->get().empty()) t.fail_at(field, "expected " + what + TomlReader::at(n));
        const std::string name = s->get();
        if (std::find(builtin.begin(), builtin.end(), name) != builtin.end()) {
            v.text = v.label = name;
            break;
        }
        fs::path p(name);
        if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec))
            t.fail_at(field, "expected " + what + ", got '" + printable(name) + "' (no such file: " + p.lexically_normal().string() + ")" +
                                 TomlReader::at(n));
        v.text = fs::absolute(p).lexically_normal().string();  // the same command line from any folder
        v.label = stem_label(name);
        // Read now with the commands' own readers (once per file): a file that is not a fabric
        // or a scene is bad input before any point runs, not a point failing later.
        try {
            std::vector<std::string> ignored;
            if (fabric)
                (void)load_fabric_file(v.text, &ignored);
            else
                (void)load_scene(v.text, &ignored);
        } catch (const InputError& e) {
            t.fail_at(field, "expected " + what + ", got '" + printable(name) + "': " + e.what() + TomlReader::at(n));
        }
        break;
    }
    }
    return v;
}

/// An axis: an array of values, or {from, to, step} for a number key.
SweepAxis read_axis(const TomlTable& axes, const std::string& key, const std::string& command, const std::string& base_dir)
{
    SweepAxis axis;
    axis.key = key;
    const toml::node* n = axes.node(key);
    const std::string field = axes.field(key);
    if (const auto* a = n->as_array()) {
        if (a->empty()) axes.fail(key, "expected a non-empty array of values" + TomlReader::at(*n));
        for (std::size_t k = 0; k < a->size(); ++k)
            axis.values.push_back(read_value(axes, *a->get(k), field + "[" + std::to_string(k + 1) + "]", key, command, base_dir));
    } else if (n->is_table()) {
        const auto t = axes.table(key);
        const KeySpec* spec = find_spec(key, command);
        const bool integer = spec && spec->kind == Kind::INTEGER;
        if (!(integer || (spec && spec->kind == Kind::NUMBER) || is_override(key, command)))
            axes.fail(key, "expected an array of values ({from, to, step} is for number keys)" + TomlReader::at(*n));
        const Range any{-1e300, 1e300, false, ""};
        const double from = t->number("from", any, std::nullopt);
        const double to = t->number("to", any, std::nullopt);
        const double step = t->number("step", Range{0, 1e300, true, ""}, 1.0);
        if (to < from) t->fail("to", "expected a number >= from (" + num_str(from) + "), got " + num_str(to));
        const double count = std::floor((to - from) / step + 1e-9) + 1;
        if (count > static_cast<double>(kMaxSweepPoints)) t->fail("step", "expected at most " + std::to_string(kMaxSweepPoints) + " values");
        for (long long k = 0; k < static_cast<long long>(count); ++k) {
            const double x = from + static_cast<double>(k) * step;
            if (integer || (is_override(key, command) && x == std::floor(x) && from == std::floor(from) && step == std::floor(step))) {
                toml::value<int64_t> i(static_cast<int64_t>(std::llround(x)));
                axis.values.push_back(read_value(axes, i, field, key, command, base_dir));
            } else {
                toml::value<double> d(x);
                axis.values.push_back(read_value(axes, d, field, key, command, base_dir));
            }
        }
    } else {
        axes.fail(key, "expected an array of values or {from, to, step}" + TomlReader::at(*n));
    }
    std::set<std::string> seen;
    for (const auto& v : axis.values)
        if (!seen.insert(v.text).second) axes.fail(key, "the value '" + printable(v.text) + "' is listed twice");
    return axis;
}

/// [A-Za-z0-9._-], everything else '_' (a folder name from the values).
std::string folder_safe(const std::string& text)
{
    std::string s = text;
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    if (!s.empty() && s[0] == '.') s[0] = '_';
    return s;
}

}  // namespace

std::size_t SweepPlan::size() const
{
    std::size_t n = 1;
    for (const auto& a : axes) n *= a.values.size();
    return n;
}

namespace {

/// The value of each axis at point `index` (the last axis varies fastest).
std::vector<std::size_t> picks(const SweepPlan& plan, std::size_t index)
{
    std::vector<std::size_t> pick(plan.axes.size());
    for (std::size_t a = plan.axes.size(); a-- > 0;) {
        pick[a] = index % plan.axes[a].values.size();
        index /= plan.axes[a].values.size();
    }
    return pick;
}

/// The folder name of point `index`.
std::string point_name(const SweepPlan& plan, std::size_t index, const std::vector<std::size_t>& pick)
{
    std::string name;
    for (std::size_t a = 0; a < plan.axes.size(); ++a)
        name += (a == 0 ? "" : "_") + folder_safe(plan.axes[a].key) + "-" + folder_safe(plan.axes[a].values[pick[a]].label);
    if (name.empty()) name = "point";
    if (name.size() > 200) name = name.substr(0, 180) + "-p" + std::to_string(index + 1);
    return name;
}

}  // namespace

SweepPoint SweepPlan::point(std::size_t index) const
{
    SweepPoint p;
    p.index = index;
    const std::vector<std::size_t> pick = picks(*this, index);
    for (std::size_t a = 0; a < axes.size(); ++a) p.values.push_back(axes[a].values[pick[a]]);
    p.name = point_name(*this, index, pick);
    // The command line: the command, its positional argument, then the options in the key
    // table's order (the same line for the same point whatever the plan's key order).
    std::vector<SweepValue> all = fixed;
    for (const auto& v : p.values) {
        std::erase_if(all, [&](const SweepValue& f) { return f.key == v.key; });
        all.push_back(v);
    }
    p.args.push_back(command);
    const std::string positional = command == "drape" ? "scene" : "fabric";
    bool have_positional = false;
    for (const auto& v : all)
        if (v.key == positional) {
            p.args.push_back(v.text);
            have_positional = true;
        }
    if (!have_positional) p.args.push_back("cube");  // drape's default scene (parse checked the others)
    for (const auto& s : key_specs()) {
        if (!takes(s, command) || std::string(s.option).empty()) continue;
        for (const auto& v : all)
            if (v.key == s.key) {
                p.args.push_back(s.option);
                p.args.push_back(v.text);
            }
    }
    if (!render) p.args.push_back("--no-render");
    for (const auto& v : all) {
        if (v.key.rfind("scene.", 0) == 0) p.scene_overrides.push_back(SweepValue{v.key.substr(6), v.text, v.label, v.number});
        if (v.key.rfind("fabric.", 0) == 0) p.fabric_overrides.push_back(SweepValue{v.key.substr(7), v.text, v.label, v.number});
    }
    return p;
}

std::vector<SweepPoint> SweepPlan::points() const
{
    const std::size_t count = size();
    std::vector<SweepPoint> out;
    out.reserve(count);
    for (std::size_t index = 0; index < count; ++index) out.push_back(point(index));
    return out;
}

namespace {

/// The number of values of an axis, from its array's length or {from, to, step}, before any
/// value is read (a plan of 10^12 points is refused at once). 1 where read_axis will refuse it.
double axis_count(const TomlTable& axes, const std::string& key)
{
    const toml::node* n = axes.node(key);
    if (const auto* a = n->as_array()) return static_cast<double>(a->size());
    if (n->is_table()) {
        const auto t = axes.table(key);
        const Range any{-1e300, 1e300, false, ""};
        const double from = t->number("from", any, std::nullopt);
        const double to = t->number("to", any, std::nullopt);
        const double step = t->number("step", Range{0, 1e300, true, ""}, 1.0);
        if (to < from) return 1;
        return std::floor((to - from) / step + 1e-9) + 1;
    }
    return 1;
}

/// Two points with one folder name (two fabric files with one stem, say) would share a folder:
/// the names' hashes sorted, and the names of equal hashes compared (no name kept: a million
/// points take 16 MB).
void check_unique_names(const SweepPlan& plan, const TomlReader& reader)
{
    const std::size_t count = plan.size();
    std::vector<std::pair<std::size_t, std::size_t>> hashes(count);
    for (std::size_t i = 0; i < count; ++i) hashes[i] = {std::hash<std::string>{}(point_name(plan, i, picks(plan, i))), i};
    std::sort(hashes.begin(), hashes.end());
    for (std::size_t k = 1; k < count; ++k) {
        if (hashes[k].first != hashes[k - 1].first) continue;
        // Equal hashes: compare with every earlier name of this hash.
        for (std::size_t j = k; j-- > 0 && hashes[j].first == hashes[k].first;) {
            const std::size_t a = std::min(hashes[j].second, hashes[k].second), b = std::max(hashes[j].second, hashes[k].second);
            const std::string name = point_name(plan, a, picks(plan, a));
            if (name == point_name(plan, b, picks(plan, b)))
                reader.fail("axes", "points " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " get the same folder name '" +
                                        name + "'; give the files different names");
        }
    }
}

}  // namespace

SweepPlan parse_sweep_plan(std::string_view text, const std::string& source, const std::string& base_dir,
                           std::vector<std::string>* warnings)
{
    const TomlReader reader(text, source);
    if (reader.empty()) reader.fail("file", "the plan is empty; expected at least `command` and an [axes] table");
    const TomlTable r = reader.root();
    SweepPlan plan;
    plan.source = source;
    plan.name = r.string("name", fs::path(source).stem().string());
    if (plan.name.empty() || folder_safe(plan.name) != plan.name)
        r.fail("name", "expected a name of letters, digits, '.', '_' and '-' (not starting with '.'), got '" + printable(plan.name) + "'");
    plan.description = r.string("description", std::string());
    plan.command = r.choice("command", std::nullopt, {"drape", "cusick", "kes-test"});
    if (const auto o = r.table("options")) {
        for (const auto& key : o->keys()) {
            if (key == "render") {
                if (plan.command == "kes-test") o->fail(key, "kes-test draws no render; remove the key");
                const toml::node* n = o->node(key);
                if (!n->is_boolean()) o->fail(key, "expected true or false" + TomlReader::at(*n));
                plan.render = n->as_boolean()->get();
                continue;
            }
            const toml::node* n = o->node(key);
            plan.fixed.push_back(read_value(*o, *n, o->field(key), key, plan.command, base_dir));
        }
    }
    if (const auto a = r.table("axes")) {
        double count = 1;
        for (const auto& key : a->keys()) {
            if (key == "render") a->fail(key, "render is an [options] key, not an axis");
            count *= axis_count(*a, key);
        }
        if (count > static_cast<double>(kMaxSweepPoints))
            reader.fail("axes", "expected at most " + std::to_string(kMaxSweepPoints) + " points, got " + num_str(count));
        for (const auto& key : a->keys()) plan.axes.push_back(read_axis(*a, key, plan.command, base_dir));
    }
    const bool has_fabric = [&] {
        for (const auto& v : plan.fixed)
            if (v.key == "fabric") return true;
        for (const auto& a : plan.axes)
            if (a.key == "fabric") return true;
        return false;
    }();
    if (plan.command != "drape" && !has_fabric)
        reader.fail("axes.fabric", "missing; " + plan.command + " needs a fabric: give it as an axis or in [options]");
    double count = 1;
    for (const auto& a : plan.axes) count *= static_cast<double>(a.values.size());
    if (count > static_cast<double>(kMaxSweepPoints))
        reader.fail("axes", "expected at most " + std::to_string(kMaxSweepPoints) + " points, got " + num_str(count));
    if (warnings)
        for (auto& w : reader.unknown_keys()) warnings->push_back(std::move(w));
    check_unique_names(plan, reader);
    return plan;
}

SweepPlan load_sweep_plan(const std::string& path, std::vector<std::string>* warnings)
{
    // Regular files only, bounded (a FIFO or /dev/zero is refused as such, not "no such file").
    const std::string text = read_input_file(path, kMaxTomlBytes, {"plan file", "a sweep plan .toml file"});
    std::string base = fs::path(path).parent_path().string();
    if (base.empty()) base = ".";
    return parse_sweep_plan(text, path, base, warnings);
}

std::string scene_or_fabric_text(const std::string& name_or_path, const std::string& kind)
{
    std::error_code ec;
    if (fs::exists(name_or_path, ec) && !fs::is_directory(name_or_path, ec))
        return read_input_file(name_or_path, kMaxTomlBytes, {kind + " file", "a " + kind + " .toml file"});
    const std::string folder = kind == "scene" ? "scenes/" : "fabrics/";
    if (auto d = embedded_file(folder + name_or_path + ".toml")) return std::string(*d);
    throw InputError(name_or_path, "file", "expected a built-in " + kind + " or a readable " + kind + " .toml file");
}

std::string apply_toml_overrides(std::string_view text, const std::string& source, const std::vector<SweepValue>& overrides)
{
    toml::table root = parse_toml(text, source);
    for (const auto& o : overrides) {
        toml::table* t = &root;
        std::string part, done;
        std::istringstream in(o.key);
        std::vector<std::string> parts;
        while (std::getline(in, part, '.')) parts.push_back(part);
        for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
            done += (done.empty() ? "" : ".") + parts[k];
            toml::node* n = t->get(parts[k]);
            if (!n) n = &t->insert_or_assign(parts[k], toml::table{}).first->second;
            if (!n->is_table()) throw InputError(source, done, "is not a table, so " + o.key + " cannot be set");
            t = n->as_table();
        }
        if (parts.empty() || parts.back().empty()) throw InputError(source, o.key, "expected a dotted key");
        toml::table lit;
        try {
            lit = toml::parse("v = " + o.text);
        } catch (const toml::parse_error&) {
            throw InputError(source, o.key, "cannot set the value " + printable(o.text));
        }
        t->insert_or_assign(parts.back(), *lit.get("v"));
    }
    std::ostringstream out;
    out << toml::toml_formatter(root) << "\n";
    return out.str();
}

}  // namespace woven::batch
