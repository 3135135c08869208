#include "woven/io/corner_map_file.hpp"

#include <cmath>
#include <cstdio>

#include "woven/common/error.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

namespace {

using nlohmann::json;

/// Thrown out of the parser's callback when the nesting is too deep.
struct TooDeep {};

const char* type_name(const json& j)
{
    switch (j.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::binary: return "binary data";
    case json::value_t::discarded: return "nothing";
    default: return "a number";
    }
}

class Reader {
public:
    explicit Reader(const std::string& source) : source_(source) { }

    [[noreturn]] void fail(const std::string& field, const std::string& expected) const
    {
        throw InputError(source_, field, expected);
    }

    std::string got(const json& j) const
    {
        if (j.is_number()) {
            char b[40];
            std::snprintf(b, sizeof b, "%.6g", j.get<double>());
            return b;
        }
        if (j.is_string()) return "'" + printable(j.get<std::string>(), 40) + "'";
        return type_name(j);
    }

    const json& member(const json& obj, const std::string& key, const std::string& field) const
    {
        const auto it = obj.find(key);
        if (it == obj.end()) fail(field, "missing");
        return *it;
    }

    const json& object(const json& j, const std::string& field) const
    {
        if (!j.is_object()) fail(field, std::string("expected an object, got ") + got(j));
        return j;
    }

    const json& array(const json& j, const std::string& field) const
    {
        if (!j.is_array()) fail(field, std::string("expected an array, got ") + got(j));
        return j;
    }

    /// A finite number in [lo, hi].
    double number(const json& j, const std::string& field, double lo, double hi, const char* what) const
    {
        const double v = j.is_number() ? j.get<double>() : NAN;
        if (!(v >= lo && v <= hi)) fail(field, std::string("expected ") + what + ", got " + got(j));
        return v;
    }

private:
    std::string source_;
};

std::string at(const std::string& field, std::size_t k) { return field + "[" + std::to_string(k) + "]"; }

}  // namespace

CornerMap parse_corner_map(std::string_view text, const std::string& source)
{
    const Reader rd(source);
    if (text.size() > kMaxCornerMapBytes)
        rd.fail("file", "expected a corner_map.json of at most " + std::to_string(kMaxCornerMapBytes >> 20) + " MiB, got " +
                            std::to_string(text.size()) + " bytes");
    json root;
    try {
        root = json::parse(
            text.begin(), text.end(),
            [](int depth, json::parse_event_t, json&) {
                if (depth > kMaxCornerMapDepth) throw TooDeep{};
                return true;
            });
    } catch (const TooDeep&) {
        rd.fail("json", "expected JSON nested at most " + std::to_string(kMaxCornerMapDepth) + " deep");
    } catch (const json::parse_error& e) {
        rd.fail("json", "expected the corner_map.json an earlier `woven experiment map` wrote (not JSON: syntax error at byte " +
                            std::to_string(e.byte) + ")");
    } catch (const json::exception& e) {  // out_of_range: a number beyond double's range (1e3085)
        rd.fail("json", std::string("expected the corner_map.json an earlier `woven experiment map` wrote (") + e.what() + ")");
    }
    rd.object(root, "json");
    CornerMap map;
    for (const char* key : {"command", "version"})
        if (const auto it = root.find(key); it != root.end()) {
            if (!it->is_string()) rd.fail(key, std::string("expected a string, got ") + rd.got(*it));
            (std::string(key) == "command" ? map.command : map.version) = it->get<std::string>();
        }
    const json& cells = rd.array(rd.member(root, "cells", "cells"), "cells");
    if (cells.empty() || cells.size() > kMaxCornerMapCells)
        rd.fail("cells", "expected 1 .. " + std::to_string(kMaxCornerMapCells) + " cells, got " + std::to_string(cells.size()));
    for (std::size_t k = 0; k < cells.size(); ++k) {
        const std::string cf = at("cells", k);
        const json& jc = rd.object(cells[k], cf);
        CornerMapCell cell;
        cell.ratio_warp_weft = rd.number(rd.member(jc, "ratio_warp_weft", cf + ".ratio_warp_weft"), cf + ".ratio_warp_weft", 1e-6,
                                         1e6, "a positive number (warp/weft bending ratio)");
        cell.bending_length_cm = rd.number(rd.member(jc, "bending_length_cm", cf + ".bending_length_cm"), cf + ".bending_length_cm",
                                           1e-6, 1e6, "a positive number (cm)");
        if (const auto it = jc.find("converged"); it != jc.end()) {
            if (!it->is_boolean()) rd.fail(cf + ".converged", "expected true or false, got " + rd.got(*it));
            cell.converged = it->get<bool>();
        }
        const std::string ff = cf + ".folds";
        const json& folds = rd.member(jc, "folds", ff);
        if (!folds.is_null()) {
            rd.object(folds, ff);
            cell.has_folds = true;
            const std::string kf = ff + ".corners";
            const json& corners = rd.array(rd.member(folds, "corners", kf), kf);
            if (corners.size() != 4) rd.fail(kf, "expected 4 corners, got " + std::to_string(corners.size()));
            for (std::size_t c = 0; c < 4; ++c) {
                const std::string pf = at(kf, c);
                const json& corner = rd.object(corners[c], pf);
                const json& angles = rd.array(rd.member(corner, "angles_deg", pf + ".angles_deg"), pf + ".angles_deg");
                const json& standout = rd.array(rd.member(corner, "standout_m", pf + ".standout_m"), pf + ".standout_m");
                if (angles.empty()) rd.fail(pf + ".angles_deg", "expected a list per section, got none");
                if (standout.size() != angles.size())
                    rd.fail(pf + ".standout_m", "expected " + std::to_string(angles.size()) + " lists (one per section, as angles_deg), got " +
                                                     std::to_string(standout.size()));
                for (std::size_t s = 0; s < angles.size(); ++s) {
                    const std::string af = at(pf + ".angles_deg", s), sf = at(pf + ".standout_m", s);
                    const json& a = rd.array(angles[s], af);
                    const json& so = rd.array(standout[s], sf);
                    if (so.size() != a.size())
                        rd.fail(sf, "expected " + std::to_string(a.size()) + " numbers (one per billow, as angles_deg), got " +
                                        std::to_string(so.size()));
                    for (std::size_t m = 0; m < a.size(); ++m) {
                        analysis::Billow b;
                        b.corner = static_cast<int>(c);
                        b.angle_deg = rd.number(a[m], at(af, m), -180, 180, "an angle in [-180, 180] degrees");
                        b.standout_m = rd.number(so[m], at(sf, m), -1e6, 1e6, "a finite distance (m)");
                        if (s == 0) cell.corners[c].push_back(b);
                    }
                }
            }
        }
        cell.json = jc;
        map.cells.push_back(std::move(cell));
    }
    return map;
}

CornerMap load_corner_map(const std::string& path)
{
    return parse_corner_map(read_input_file(path, kMaxCornerMapBytes, {"corner map", "a corner_map.json"}), path);
}

}  // namespace woven::io
