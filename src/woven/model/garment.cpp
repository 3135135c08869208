#include "woven/model/garment.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "woven/common/error.hpp"
#include "woven/common/format.hpp"

namespace woven::model {

namespace {

/// A particle within this many spacings of two segments is on both: at their corner (on both
/// outlines to round-off).
constexpr double kCornerTie = 1e-6;

Vec2 rotate(const Vec2& v, double angle)
{
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// (q1, q2, w) of the point at fraction t on an edge whose particles sit at fractions `ts`
/// (ascending): the two particles around t and t's place between them; beyond either end, the
/// two end particles' line extended (w < 0 or > 1, at most a spacing), so that an edge's end
/// is sewn where it is; a lone particle alone.
struct Bracket {
    int k1 = 0, k2 = 0;
    double w = 0;
};
Bracket bracket(const std::vector<double>& ts, double t)
{
    const int n = static_cast<int>(ts.size());
    if (n == 1) return {0, 0, 0.0};
    int k2 = static_cast<int>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
    k2 = std::clamp(k2, 1, n - 1);
    const int k1 = k2 - 1;
    const double span = ts[k2] - ts[k1];
    return {k1, k2, span > 0 ? std::clamp((t - ts[k1]) / span, -1.0, 2.0) : 0.0};
}

}  // namespace

double OutlineSegment::turn() const
{
    if (!centre) return 0.0;
    const Vec2 u = a - *centre, v = b - *centre;
    double t = std::atan2(cross2(u, v), u.dot(v));
    if (ccw && t <= 0) t += 2 * std::numbers::pi;
    if (!ccw && t >= 0) t -= 2 * std::numbers::pi;
    return t;
}

double OutlineSegment::length() const { return centre ? std::abs(turn()) * radius() : (b - a).norm(); }

Vec2 OutlineSegment::point(double s) const
{
    const double L = length();
    if (!centre) return L > 0 ? Vec2(a + (b - a) * (s / L)) : a;
    const double r = radius();
    return *centre + rotate(a - *centre, (turn() > 0 ? 1.0 : -1.0) * s / r);
}

double OutlineSegment::project(const Vec2& p, double* distance) const
{
    const double L = length();
    double s = 0;
    if (!centre) {
        const Vec2 d = b - a;
        s = L > 0 ? std::clamp((p - a).dot(d) / L, 0.0, L) : 0.0;
    } else {
        const double r = radius(), t = turn();
        const Vec2 u = a - *centre, v = p - *centre;
        double phi = std::atan2(cross2(u, v), u.dot(v));  // from a, counter-clockwise
        if (t < 0) phi = -phi;                            // along the arc's own sense
        if (phi < 0) phi += 2 * std::numbers::pi;
        if (phi <= std::abs(t))
            s = phi * r;
        else  // beyond the arc: the nearer end
            s = (p - a).norm() <= (p - b).norm() ? 0.0 : L;
    }
    if (distance) *distance = (p - point(s)).norm();
    return s;
}

Vec3 place_point(const Placement& pl, const Vec2& p)
{
    const Vec2 down(std::cos(pl.down), std::sin(pl.down));
    const Vec2 right = rotate(down, 0.5 * std::numbers::pi);
    const Vec2 d = p - pl.origin;
    double radius = 0, height = 0, azimuth = 0;
    if (pl.wrap == Placement::Wrap::CONE) {
        const double rho = d.norm();
        const double psi = rho > 0 ? std::atan2(d.dot(right), d.dot(down)) : 0.0;
        const double sa = std::sin(pl.half_angle);
        radius = rho * sa;
        height = pl.height - rho * std::cos(pl.half_angle);
        azimuth = pl.azimuth + psi / sa;
    } else {
        radius = pl.radius;
        height = pl.height - d.dot(down);
        azimuth = pl.azimuth + d.dot(right) / pl.radius;
    }
    return {radius * std::cos(azimuth), radius * std::sin(azimuth), height};
}

Ring piece_ring(const PatternPiece& piece)
{
    Ring ring;
    for (const OutlineSegment& seg : piece.segments) {
        ring.push_back(seg.a);
        if (!seg.centre) continue;
        const double t = seg.turn();
        const int n = std::max(2, static_cast<int>(std::ceil(std::abs(t) / (2 * std::numbers::pi) * kCircleSegments)));
        for (int k = 1; k < n; ++k) ring.push_back(*seg.centre + rotate(seg.a - *seg.centre, t * k / n));
    }
    return ring;
}

GarmentCloth cut_pattern(const Pattern& pattern, double sigma, const std::string& source)
{
    GarmentCloth g;
    const int pieces = static_cast<int>(pattern.pieces.size());
    if (pieces == 0) throw InputError(source, "piece", "missing; expected at least one [[piece]]");
    // 1. Each piece's outline turned by its grain; the pieces side by side along u, 3 sigma apart.
    const double margin = 3 * sigma;
    std::vector<Ring> rings(pieces);
    std::vector<Vec2> offset(pieces);
    double cursor = margin, height = 0;
    for (int k = 0; k < pieces; ++k) {
        const PatternPiece& piece = pattern.pieces[k];
        const std::string field = strf("piece[%d]", k + 1);
        for (std::size_t m = 0; m < piece.segments.size(); ++m) {
            const OutlineSegment& seg = piece.segments[m];
            const OutlineSegment& next = piece.segments[(m + 1) % piece.segments.size()];
            if ((seg.b - next.a).norm() > 1e-9)
                throw InputError(source, field + ".segment", "the outline is not closed: each segment must start where the last ended");
            if (!(seg.length() > 0))
                throw InputError(source, strf("%s.segment[%d]", field.c_str(), static_cast<int>(m) + 1),
                                 "expected a segment of non-zero length");
            if (seg.centre && std::abs((seg.b - *seg.centre).norm() - seg.radius()) > 1e-6 * seg.radius())
                throw InputError(source, strf("%s.segment[%d].centre_cm", field.c_str(), static_cast<int>(m) + 1),
                                 "expected an arc's centre as far from its start as from its end");
        }
        Ring ring = piece_ring(piece);
        for (Vec2& q : ring) q = rotate(q, -piece.grain);
        Vec2 lo = ring[0], hi = ring[0];
        for (const Vec2& q : ring) {
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
        offset[k] = Vec2(cursor - lo.x(), margin - lo.y());
        cursor += (hi.x() - lo.x()) + margin;
        height = std::max(height, hi.y() - lo.y());
        rings[k] = std::move(ring);
    }
    g.grid.sigma = sigma;
    g.grid.nu = static_cast<int>(std::ceil(cursor / sigma)) + 1;
    g.grid.nv = static_cast<int>(std::ceil((height + 2 * margin) / sigma)) + 1;
    const Grid& grid = g.grid;
    const int n = grid.size();
    const Vec2 centre(0.5 * (grid.nu - 1) * sigma, 0.5 * (grid.nv - 1) * sigma);

    // 2. Each piece cut from the grid as the Cusick specimen is.
    g.active.assign(n, 0);
    g.area.assign(n, 0.0);
    g.piece_of.assign(n, -1);
    g.piece_point.assign(n, Vec2::Zero());
    for (int k = 0; k < pieces; ++k) {
        Outline outline;
        outline.kind = Outline::Kind::POLYGON;
        for (const Vec2& q : rings[k]) outline.points.push_back(q + offset[k] - centre);
        g.cuts.push_back(cut_grid(grid, outline, source, strf("piece[%d] (%s)", k + 1, pattern.pieces[k].name.c_str())));
        const ClothCut& cut = g.cuts.back();
        for (int p = 0; p < n; ++p) {
            g.area[p] += cut.area[p];  // slivers of a dropped particle go to its own piece's neighbours
            if (!cut.active[p]) continue;
            g.active[p] = 1;
            g.piece_of[p] = k;
            const Vec2 at(static_cast<double>(p % grid.nu) * sigma, static_cast<double>(p / grid.nu) * sigma);
            g.piece_point[p] = rotate(at - offset[k], pattern.pieces[k].grain);
        }
    }

    // 3. The edge particles of each segment: kept particles with a thread neighbour dropped,
    // each on the segment nearest it (within a spacing); a particle on a corner (within kCornerTie
    // of a spacing of two segments) is on both, so a seam sews its ends too.
    g.edges.resize(pieces);
    for (int k = 0; k < pieces; ++k) g.edges[k].resize(pattern.pieces[k].segments.size());
    for (int p = 0; p < n; ++p) {
        if (!g.active[p]) continue;
        const int i = p % grid.nu, j = p / grid.nu;
        const bool edge = i == 0 || j == 0 || i == grid.nu - 1 || j == grid.nv - 1 || !g.active[p - 1] || !g.active[p + 1]
            || !g.active[p - grid.nu] || !g.active[p + grid.nu];
        if (!edge) continue;
        const PatternPiece& piece = pattern.pieces[g.piece_of[p]];
        std::vector<double> d(piece.segments.size()), s(piece.segments.size());
        for (std::size_t m = 0; m < piece.segments.size(); ++m) s[m] = piece.segments[m].project(g.piece_point[p], &d[m]);
        const double nearest = *std::min_element(d.begin(), d.end());
        if (!(nearest < 1.0001 * sigma)) continue;
        const bool on_outline = nearest < kCornerTie * sigma;  // at a corner: on every segment as near
        for (std::size_t m = 0; m < piece.segments.size(); ++m) {
            if (d[m] > nearest + (on_outline ? kCornerTie * sigma : 0.0)) continue;
            EdgeParticles& e = g.edges[g.piece_of[p]][m];
            e.particles.push_back(p);
            e.s.push_back(s[m]);
            if (!on_outline) break;  // off the outline: the nearest only (the first of equals)
        }
    }
    for (auto& piece_edges : g.edges)
        for (EdgeParticles& e : piece_edges) {
            std::vector<std::size_t> order(e.particles.size());
            for (std::size_t m = 0; m < order.size(); ++m) order[m] = m;
            std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
                return e.s[a] < e.s[b] || (e.s[a] == e.s[b] && e.particles[a] < e.particles[b]);
            });
            EdgeParticles sorted;
            for (std::size_t m : order) {
                sorted.particles.push_back(e.particles[m]);
                sorted.s.push_back(e.s[m]);
            }
            e = std::move(sorted);
        }
    // Each edge particle's point on the outline, extrapolated along the threads from its inward
    // neighbours (seams.hpp): the offset to the outline in the grid's frame, in spacings.
    for (int k = 0; k < pieces; ++k)
        for (std::size_t m = 0; m < g.edges[k].size(); ++m) {
            EdgeParticles& e = g.edges[k][m];
            const OutlineSegment& seg = pattern.pieces[k].segments[m];
            for (std::size_t n = 0; n < e.particles.size(); ++n) {
                const int p = e.particles[n];
                const int i = p % grid.nu, j = p / grid.nu;
                const Vec2 d = rotate(seg.point(e.s[n]) - g.piece_point[p], -pattern.pieces[k].grain) / sigma;
                std::array<int, 3> ids{p, p, p};
                std::array<double, 3> c{1.0, 0.0, 0.0};
                // along the weft (u): inward is against the offset
                const int iu = d.x() > 0 ? i - 1 : i + 1;
                if (iu >= 0 && iu < grid.nu && g.piece_of[grid.index(iu, j)] == k) {
                    ids[1] = grid.index(iu, j);
                    c[0] += std::abs(d.x());
                    c[1] = -std::abs(d.x());
                }
                const int jv = d.y() > 0 ? j - 1 : j + 1;
                if (jv >= 0 && jv < grid.nv && g.piece_of[grid.index(i, jv)] == k) {
                    ids[2] = grid.index(i, jv);
                    c[0] += std::abs(d.y());
                    c[2] = -std::abs(d.y());
                }
                e.ids.push_back(ids);
                e.c.push_back(c);
            }
        }
    for (int k = 0; k < pieces; ++k)
        for (std::size_t m = 0; m < pattern.pieces[k].segments.size(); ++m) {
            const auto role = pattern.pieces[k].segments[m].role;
            if (role == OutlineSegment::Role::EDGE) continue;
            auto& list = role == OutlineSegment::Role::WAIST ? g.waist : g.hem;
            list.insert(list.end(), g.edges[k][m].particles.begin(), g.edges[k][m].particles.end());
        }
    for (auto* list : {&g.waist, &g.hem}) {
        std::sort(list->begin(), list->end());
        list->erase(std::unique(list->begin(), list->end()), list->end());
    }

    // 4. The seams: each particle of either edge stitched to the other edge at its fraction of
    // the length; the pairs of the two edges within 1.5 spacings of each other are not repelled.
    std::vector<char> cut_edge(n, 0);
    for (const auto& piece_edges : g.edges)
        for (const EdgeParticles& e : piece_edges)
            for (int p : e.particles) cut_edge[p] = 1;
    // (fraction of the segment's length, particle) of the cut-edge particles within a spacing of it.
    auto near_segment = [&](int k, int m, bool reversed) {
        const OutlineSegment& seg = pattern.pieces[k].segments[m];
        const double L = seg.length();
        std::vector<std::pair<double, int>> out;
        for (int p = 0; p < n; ++p) {
            if (!cut_edge[p] || g.piece_of[p] != k) continue;
            double d = 0;
            const double t = seg.project(g.piece_point[p], &d) / L;
            if (d < 1.0001 * sigma) out.push_back({reversed ? 1.0 - t : t, p});
        }
        return out;
    };
    for (int m = 0; m < static_cast<int>(pattern.seams.size()); ++m) {
        const PatternSeam& seam = pattern.seams[m];
        const std::string field = strf("seam[%d]", m + 1);
        const EdgeParticles& A = g.edges[seam.piece_a][seam.segment_a];
        const EdgeParticles& B = g.edges[seam.piece_b][seam.segment_b];
        if (A.particles.empty() || B.particles.empty())
            throw InputError(source, field,
                             "an edge of the seam holds no particle at this spacing: expected a longer edge or a finer spacing");
        const double La = pattern.pieces[seam.piece_a].segments[seam.segment_a].length();
        const double Lb = pattern.pieces[seam.piece_b].segments[seam.segment_b].length();
        std::vector<double> ta, tb;
        for (double s : A.s) ta.push_back(s / La);
        std::vector<int> b_particles;
        {
            std::vector<std::pair<double, int>> bt;
            for (std::size_t q = 0; q < B.particles.size(); ++q)
                bt.push_back({seam.reversed ? 1.0 - B.s[q] / Lb : B.s[q] / Lb, B.particles[q]});
            std::sort(bt.begin(), bt.end());
            for (const auto& [t, q] : bt) {
                tb.push_back(t);
                b_particles.push_back(q);
            }
        }
        // B's outline points in the order of tb.
        std::vector<std::size_t> b_order;
        {
            std::vector<std::pair<double, std::size_t>> bt;
            for (std::size_t q = 0; q < B.particles.size(); ++q) bt.push_back({seam.reversed ? 1.0 - B.s[q] / Lb : B.s[q] / Lb, q});
            std::sort(bt.begin(), bt.end());
            for (const auto& [t, q] : bt) b_order.push_back(q);
        }
        auto stitch = [&](const EdgeParticles& E, std::size_t at, const EdgeParticles& F, std::size_t at1, std::size_t at2, double w) {
            Stitch st;
            st.p = E.particles[at];
            st.q1 = F.particles[at1];
            st.q2 = F.particles[at2];
            st.w = w;
            st.seam = m;
            for (int r = 0; r < 3; ++r) {
                st.ids[r] = E.ids[at][r];
                st.c[r] = E.c[at][r];
                st.ids[3 + r] = F.ids[at1][r];
                st.c[3 + r] = -(1 - w) * F.c[at1][r];
                st.ids[6 + r] = F.ids[at2][r];
                st.c[6 + r] = -w * F.c[at2][r];
            }
            g.seams.stitches.push_back(st);
        };
        for (std::size_t a = 0; a < ta.size(); ++a) {
            const Bracket br = bracket(tb, ta[a]);
            stitch(A, a, B, b_order[br.k1], b_order[br.k2], br.w);
        }
        for (std::size_t b = 0; b < tb.size(); ++b) {
            const Bracket br = bracket(ta, tb[b]);
            stitch(B, b_order[b], A, br.k1, br.k2, br.w);
        }
        // Not repelled: the cut-edge particles within a spacing of either segment (those nearer
        // another segment at a seam's end too), pairs within 1.5 spacings along the seam.
        const double length = 0.5 * (La + Lb);
        const std::vector<std::pair<double, int>> near_a = near_segment(seam.piece_a, seam.segment_a, false);
        const std::vector<std::pair<double, int>> near_b = near_segment(seam.piece_b, seam.segment_b, seam.reversed);
        for (const auto& [t, a] : near_a)
            for (const auto& [u, b] : near_b)
                if (std::abs(t - u) * length < 1.5 * sigma && a != b) g.seams.unrepelled.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(g.seams.unrepelled.begin(), g.seams.unrepelled.end());
    g.seams.unrepelled.erase(std::unique(g.seams.unrepelled.begin(), g.seams.unrepelled.end()), g.seams.unrepelled.end());

    // 5. Every particle placed; those between the pieces (held by the solver) a metre above.
    g.start.assign(n, Vec3::Zero());
    double top = -1e300;
    for (int p = 0; p < n; ++p)
        if (g.active[p]) {
            g.start[p] = place_point(pattern.pieces[g.piece_of[p]].placement, g.piece_point[p]);
            top = std::max(top, g.start[p].z());
        }
    for (int p = 0; p < n; ++p)
        if (!g.active[p]) g.start[p] = Vec3(0, 0, top + 1.0);
    return g;
}

}  // namespace woven::model
