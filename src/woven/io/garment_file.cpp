#include "woven/io/garment_file.hpp"

#include <filesystem>
#include <map>
#include <numbers>

#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/common/units.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const Range kAnyCm{-1e4, 1e4, false, "cm"};
const Range kPositiveCm{0, 1e4, true, "cm"};

/// A point given in cm, in m: the one conversion of the garment file's lengths.
Vec2 point_cm(const TomlTable& t, std::string_view key, std::optional<Vec2> def_cm = std::nullopt)
{
    return t.vec<2>(key, kAnyCm, def_cm) * units::kCmToM;
}
double length_cm(const TomlTable& t, std::string_view key, const Range& range, std::optional<double> def_cm)
{
    return t.number(key, range, def_cm) * units::kCmToM;
}

model::PatternPiece parse_piece(const TomlTable& t)
{
    model::PatternPiece piece;
    piece.name = t.string("name", std::nullopt);
    if (piece.name.empty() || piece.name.find('.') != std::string::npos) t.fail("name", "expected a non-empty name without '.'");
    piece.grain = t.number("grain_deg", Range{-360, 360, false, "deg"}, 0.0) * kDeg;
    Vec2 at = point_cm(t, "start_cm");
    const std::vector<TomlTable> segs = t.tables("segment");
    if (segs.size() < 2) t.fail("segment", "expected at least two [[piece.segment]] (an outline of straight and arc segments)");
    for (const TomlTable& s : segs) {
        model::OutlineSegment seg;
        seg.name = s.string("name", "");
        seg.a = at;
        seg.b = point_cm(s, "to_cm");
        if (s.has("centre_cm")) {
            seg.centre = point_cm(s, "centre_cm");
            seg.ccw = s.choice("turn", std::string("ccw"), {"ccw", "cw"}) == "ccw";
            if (!((seg.a - *seg.centre).norm() > 0)) s.fail("centre_cm", "expected an arc's centre away from its start");
            if (std::abs((seg.b - *seg.centre).norm() - seg.radius()) > 1e-4 * seg.radius())
                s.fail("centre_cm",
                       strf("expected the arc's centre as far from its end as from its start (%.4g and %.4g cm)",
                            (seg.b - *seg.centre).norm() * units::kMToCm, seg.radius() * units::kMToCm));
            seg.b = *seg.centre + (seg.b - *seg.centre).normalized() * seg.radius();  // exactly on the circle
        }
        const std::string role = s.choice("role", std::string("edge"), {"edge", "waist", "hem"});
        seg.role = role == "waist" ? model::OutlineSegment::Role::WAIST
            : role == "hem"        ? model::OutlineSegment::Role::HEM
                                   : model::OutlineSegment::Role::EDGE;
        if (!(seg.length() > 0)) s.fail("to_cm", "expected a segment of non-zero length (its end away from its start)");
        at = seg.b;
        piece.segments.push_back(std::move(seg));
    }
    if ((at - piece.segments.front().a).norm() > 1e-6)
        segs.back().fail("to_cm", "expected the last segment to end at the piece's start_cm (a closed outline)");
    piece.segments.back().b = piece.segments.front().a;
    const std::optional<TomlTable> place = t.table("place", true);
    model::Placement& pl = piece.placement;
    const std::string wrap = place->choice("wrap", std::nullopt, {"cone", "cylinder"});
    pl.wrap = wrap == "cone" ? model::Placement::Wrap::CONE : model::Placement::Wrap::CYLINDER;
    pl.origin = point_cm(*place, "origin_cm", Vec2::Zero());
    pl.down = place->number("down_deg", Range{-360, 360, false, "deg"}, -90.0) * kDeg;
    pl.azimuth = place->number("azimuth_deg", Range{-720, 720, false, "deg"}, 0.0) * kDeg;
    pl.height = length_cm(*place, "height_cm", kAnyCm, std::nullopt);
    if (pl.wrap == model::Placement::Wrap::CONE)
        pl.half_angle = place->number("half_angle_deg", Range{0, 90, true, "deg"}, std::nullopt) * kDeg;
    else
        pl.radius = length_cm(*place, "radius_cm", kPositiveCm, std::nullopt);
    return piece;
}

}  // namespace

GarmentSpec parse_garment(std::string_view text, const std::string& source, const std::string& base_dir, std::vector<std::string>* warnings)
{
    const TomlReader reader(text, source);
    const TomlTable r = reader.root();
    GarmentSpec g;
    g.source = source;
    g.name = r.string("name", fs::path(source).stem().string());
    std::string fabric = r.string("fabric", std::nullopt);
    if (fabric.find('/') != std::string::npos || fabric.ends_with(".toml")) {
        fs::path p(fabric);
        if (p.is_relative()) p = fs::path(base_dir) / p;
        fabric = p.string();
    }
    g.fabric = fabric;
    g.spacing_m = r.number("spacing_cm", Range{kGarmentSpacingCm[0], kGarmentSpacingCm[1], false, "cm"}, 2.0) * units::kCmToM;

    if (const auto b = r.table("body")) {
        if (b->has("obj")) {
            fs::path p(b->string("obj", std::nullopt));
            if (p.is_relative()) p = fs::path(base_dir) / p;
            g.body.obj = p.string();
            const std::string unit = b->choice("obj_unit", std::string("m"), {"m", "cm", "mm"});
            g.body.obj_scale = unit == "m" ? 1.0 : unit == "cm" ? 0.01 : 0.001;
        } else {
            b->choice("form", std::string("dress-form"), {"dress-form"});
            geometry::DressFormSizes& f = g.body.form;
            const Range girth{30, 300, false, "cm"};
            f.bust = length_cm(*b, "bust_cm", girth, f.bust * units::kMToCm);
            f.waist = length_cm(*b, "waist_cm", girth, f.waist * units::kMToCm);
            f.hip = length_cm(*b, "hip_cm", girth, f.hip * units::kMToCm);
            f.waist_height = length_cm(*b, "waist_height_cm", Range{50, 300, false, "cm"}, f.waist_height * units::kMToCm);
            f.hip_depth = length_cm(*b, "hip_depth_cm", Range{5, 50, false, "cm"}, f.hip_depth * units::kMToCm);
            f.depth_ratio = b->number("depth_ratio", Range{0.3, 1, false, ""}, f.depth_ratio);
        }
    }

    std::map<std::string, int> piece_index;
    const std::vector<TomlTable> pieces = r.tables("piece");
    if (pieces.empty()) r.fail("piece", "missing; expected at least one [[piece]]");
    for (const TomlTable& t : pieces) {
        model::PatternPiece piece = parse_piece(t);
        if (!piece_index.emplace(piece.name, static_cast<int>(g.pattern.pieces.size())).second)
            t.fail("name", "expected a name no other piece has, got '" + printable(piece.name) + "' twice");
        if (t.has("fabric") && t.string("fabric", std::nullopt) != r.string("fabric", std::nullopt))
            t.fail("fabric", "expected the garment's fabric: the pieces of one garment are draped in one fabric (one thread grid)");
        g.pattern.pieces.push_back(std::move(piece));
    }
    // "piece.segment" -> (piece, segment)
    auto find_edge = [&](const TomlTable& t, std::string_view key, int& piece, int& segment) {
        const std::string ref = t.string(key, std::nullopt);
        const std::size_t dot = ref.find('.');
        const auto it = dot == std::string::npos ? piece_index.end() : piece_index.find(ref.substr(0, dot));
        if (it == piece_index.end()) t.fail(key, "expected '<piece>.<segment>' naming a piece, got '" + printable(ref) + "'");
        piece = it->second;
        const auto& segs = g.pattern.pieces[piece].segments;
        segment = -1;
        for (std::size_t k = 0; k < segs.size(); ++k)
            if (segs[k].name == ref.substr(dot + 1)) segment = static_cast<int>(k);
        if (segment < 0)
            t.fail(key,
                   "expected '<piece>.<segment>' naming a segment of piece '" + printable(it->first) + "', got '" + printable(ref) + "'");
    };
    for (const TomlTable& t : r.tables("seam")) {
        model::PatternSeam seam;
        find_edge(t, "a", seam.piece_a, seam.segment_a);
        find_edge(t, "b", seam.piece_b, seam.segment_b);
        if (seam.piece_a == seam.piece_b && seam.segment_a == seam.segment_b) t.fail("b", "expected another segment than a's");
        seam.reversed = t.choice("direction", std::string("same"), {"same", "reversed"}) == "reversed";
        seam.name = t.string("a", std::nullopt) + " + " + t.string("b", std::nullopt);
        g.pattern.seams.push_back(seam);
    }
    if (const auto s = r.table("solver")) {
        if (const auto k = s->numbers("seam_stiffness_N_m", Range{0, 1e9, true, "N/m"})) {
            if (k->empty()) s->fail("seam_stiffness_N_m", "expected at least one stiffness");
            g.seam_stiffness = *k;
        }
        g.threads = static_cast<int>(s->integer("threads", 0, 1024, 0));
        g.max_steps = static_cast<int>(s->integer("max_steps", 0, 1'000'000'000, 0));
    }
    if (warnings)
        for (auto& w : reader.unknown_keys()) warnings->push_back(std::move(w));
    return g;
}

GarmentSpec load_garment(const std::string& path, std::vector<std::string>* warnings)
{
    const std::string text = read_input_file(path, kMaxTomlBytes, {"garment file", "a garment .toml file"});
    std::string base = fs::path(path).parent_path().string();
    if (base.empty()) base = ".";
    return parse_garment(text, path, base, warnings);
}

}  // namespace woven::io
