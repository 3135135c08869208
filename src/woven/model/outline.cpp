#include "woven/model/outline.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <utility>

#include "woven/common/error.hpp"

namespace woven::model {

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

std::string num(double v)
{
    std::ostringstream s;
    s << v;
    return s.str();
}

/// Orientation of c relative to the line a -> b: +1 left, -1 right, 0 collinear (to eps).
int orient(const Vec2& a, const Vec2& b, const Vec2& c, double eps)
{
    const double v = cross(b - a, c - a);
    return v > eps ? 1 : (v < -eps ? -1 : 0);
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p, double eps)
{
    return p.x() >= std::min(a.x(), b.x()) - eps && p.x() <= std::max(a.x(), b.x()) + eps && p.y() >= std::min(a.y(), b.y()) - eps
        && p.y() <= std::max(a.y(), b.y()) + eps;
}

/// Whether segments ab and cd share a point (crossing, touching or overlapping).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double eps)
{
    const double e2 = eps * eps;
    const int o1 = orient(a, b, c, e2), o2 = orient(a, b, d, e2), o3 = orient(c, d, a, e2), o4 = orient(c, d, b, e2);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && on_segment(a, b, c, eps)) || (o2 == 0 && on_segment(a, b, d, eps)) || (o3 == 0 && on_segment(c, d, a, eps))
        || (o4 == 0 && on_segment(c, d, b, eps));
}

/// A regular n-gon about c with the area of the circle of radius r; counter-clockwise
/// (sign > 0) or clockwise, starting at angle 0.
Ring circle(const Vec2& c, double r, int n, int sign)
{
    const double rp = r * std::sqrt(2.0 * std::numbers::pi / (n * std::sin(2.0 * std::numbers::pi / n)));
    Ring ring(n);
    for (int k = 0; k < n; ++k) {
        const double a = sign * 2.0 * std::numbers::pi * k / n;
        ring[k] = c + rp * Vec2(std::cos(a), std::sin(a));
    }
    return ring;
}

/// Clips a polygon to the half-plane s * (p[axis] - value) >= 0.
Ring clip_half(const Ring& in, int axis, double value, double s)
{
    Ring out;
    const size_t n = in.size();
    if (n == 0) return out;
    out.reserve(n + 4);
    for (size_t k = 0; k < n; ++k) {
        const Vec2& p = in[k];
        const Vec2& q = in[(k + 1) % n];
        const double dp = s * (p[axis] - value), dq = s * (q[axis] - value);
        if (dp >= 0) out.push_back(p);
        if ((dp >= 0) != (dq >= 0)) {
            const double t = dp / (dp - dq);
            Vec2 m = p + t * (q - p);
            m[axis] = value;
            out.push_back(m);
        }
    }
    return out;
}

}  // namespace

void validate_outline(const Outline& o, const std::string& source, const std::string& field)
{
    const auto bad = [&](const std::string& key, const std::string& what) { throw InputError(source, field + "." + key, what); };
    if (!o.centre.allFinite()) bad("centre_m", "expected finite numbers in m");
    switch (o.kind) {
    case Outline::Kind::RECTANGLE: return;
    case Outline::Kind::DISC:
        if (!std::isfinite(o.radius) || !(o.radius > 0)) bad("radius_m", "expected a positive radius in m, got " + num(o.radius));
        return;
    case Outline::Kind::ANNULUS:
        if (!std::isfinite(o.radius) || !(o.radius > 0)) bad("radius_m", "expected a positive radius in m, got " + num(o.radius));
        if (!std::isfinite(o.inner_radius) || !(o.inner_radius > 0) || !(o.inner_radius < o.radius))
            bad("inner_radius_m", "expected a radius in m above 0 and below radius_m (" + num(o.radius) + "), got " + num(o.inner_radius));
        return;
    case Outline::Kind::POLYGON: {
        Ring r = o.points;
        if (r.size() >= 2 && r.front() == r.back()) r.pop_back();  // an explicitly closed polygon
        if (r.size() < 3) bad("points_m", "expected at least 3 points [x, y] in m");
        if (r.size() > kMaxOutlinePoints)
            bad("points_m", "expected at most " + std::to_string(kMaxOutlinePoints) + " points, got " + std::to_string(r.size()));
        for (size_t k = 0; k < r.size(); ++k) {
            if (!r[k].allFinite()) bad("points_m", "expected finite coordinates in m (point " + std::to_string(k) + ")");
            if (r[k] == r[(k + 1) % r.size()]) bad("points_m", "point " + std::to_string(k) + " repeats the next one");
        }
        double extent = 0;
        for (const auto& p : r) extent = std::max(extent, (p - r[0]).norm());
        if (std::abs(signed_area(r)) <= 1e-12 * extent * extent) bad("points_m", "the polygon encloses no area");
        if (const auto x = self_intersection(r))
            bad("points_m", "the polygon intersects itself (edges " + std::to_string(x->first) + " and " + std::to_string(x->second) + ")");
        return;
    }
    }
}

Ring outline_ring(const Outline& o, const Grid& g)
{
    switch (o.kind) {
    case Outline::Kind::RECTANGLE: {
        const Vec2 lo = rest_uv(g, 0, 0), hi = rest_uv(g, g.nu - 1, g.nv - 1);
        return {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
    }
    case Outline::Kind::DISC: return circle(o.centre, o.radius, kCircleSegments, +1);
    case Outline::Kind::ANNULUS: {
        Ring r = circle(o.centre, o.radius, kCircleSegments, +1);
        const Ring inner = circle(o.centre, o.inner_radius, kCircleSegments, -1);
        r.push_back(r.front());  // the cut out to angle 0 ...
        r.insert(r.end(), inner.begin(), inner.end());
        r.push_back(inner.front());  // ... round the hole clockwise, and back
        return r;
    }
    case Outline::Kind::POLYGON: {
        Ring r = o.points;
        if (r.size() >= 2 && r.front() == r.back()) r.pop_back();
        if (signed_area(r) < 0) std::reverse(r.begin(), r.end());
        return r;
    }
    }
    return {};
}

double signed_area(const Ring& ring)
{
    double a = 0;
    const size_t n = ring.size();
    for (size_t k = 0; k < n; ++k) a += cross(ring[k], ring[(k + 1) % n]);
    return 0.5 * a;
}

bool contains(const Ring& ring, const Vec2& p)
{
    bool in = false;
    const size_t n = ring.size();
    for (size_t k = 0, l = n - 1; k < n; l = k++) {
        const Vec2& a = ring[k];
        const Vec2& b = ring[l];
        if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
    }
    return in;
}

std::optional<std::pair<int, int>> self_intersection(const Ring& ring)
{
    const int n = static_cast<int>(ring.size());
    double extent = 0;
    for (const auto& p : ring) extent = std::max(extent, (p - ring[0]).norm());
    const double eps = 1e-12 * std::max(extent, 1e-300);
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            if (b == a + 1 || (a == 0 && b == n - 1)) {
                // Adjacent edges share one point; they meet wrongly only when they fold back
                // onto each other.
                const Vec2& p = ring[a];
                const Vec2& q = ring[(a + 1) % n];
                const Vec2& r = b == a + 1 ? ring[(b + 1) % n] : ring[n - 1];
                const Vec2& shared = b == a + 1 ? q : p;
                const Vec2& other = b == a + 1 ? p : q;
                if (orient(other, shared, r, eps * eps) == 0 && (r - shared).dot(other - shared) > 0) return std::make_pair(a, b);
                continue;
            }
            if (segments_meet(ring[a], ring[(a + 1) % n], ring[b], ring[(b + 1) % n], eps)) return std::make_pair(a, b);
        }
    return std::nullopt;
}

Ring clip_to_box(const Ring& ring, const Vec2& lo, const Vec2& hi)
{
    Ring r = clip_half(ring, 0, lo.x(), +1);
    r = clip_half(r, 0, hi.x(), -1);
    r = clip_half(r, 1, lo.y(), +1);
    return clip_half(r, 1, hi.y(), -1);
}

std::vector<std::array<Vec2, 3>> triangulate(const Ring& poly)
{
    // Vertical slabs between the vertices' x: in each, the edges that span it, sorted by their
    // height at the slab's middle, bound the region pairwise (even-odd, which is the region for
    // a winding of 0 or 1); each pair is a trapezoid, two triangles. Zero-width bridges pair
    // with their twins and give nothing.
    std::vector<std::array<Vec2, 3>> tris;
    const size_t n = poly.size();
    if (n < 3) return tris;
    std::vector<double> xs;
    for (const auto& p : poly) xs.push_back(p.x());
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::vector<std::pair<double, size_t>> spans;
    for (size_t s = 0; s + 1 < xs.size(); ++s) {
        const double x0 = xs[s], x1 = xs[s + 1], xm = 0.5 * (x0 + x1);
        spans.clear();
        for (size_t k = 0; k < n; ++k) {
            const Vec2& a = poly[k];
            const Vec2& b = poly[(k + 1) % n];
            if (std::min(a.x(), b.x()) <= x0 && std::max(a.x(), b.x()) >= x1 && a.x() != b.x())
                spans.emplace_back(a.y() + (xm - a.x()) * (b.y() - a.y()) / (b.x() - a.x()), k);
        }
        std::sort(spans.begin(), spans.end());
        const auto y_at = [&](size_t k, double x) {
            const Vec2& a = poly[k];
            const Vec2& b = poly[(k + 1) % n];
            return a.y() + (x - a.x()) * (b.y() - a.y()) / (b.x() - a.x());
        };
        for (size_t e = 0; e + 1 < spans.size(); e += 2) {
            const size_t lo = spans[e].second, hi = spans[e + 1].second;
            const Vec2 p00(x0, y_at(lo, x0)), p10(x1, y_at(lo, x1)), p11(x1, y_at(hi, x1)), p01(x0, y_at(hi, x0));
            if (p11.y() > p10.y()) tris.push_back({p00, p10, p11});
            if (p01.y() > p00.y()) tris.push_back({p00, p11, p01});
        }
    }
    return tris;
}

Vec2 rest_uv(const Grid& g, int i, int j) { return Vec2((i - 0.5 * (g.nu - 1)) * g.sigma, (j - 0.5 * (g.nv - 1)) * g.sigma); }

ClothCut cut_grid(const Grid& g, const Outline& outline, const std::string& source, const std::string& field)
{
    validate_outline(outline, source, field);
    ClothCut cut;
    cut.ring = outline_ring(outline, g);
    const Ring& ring = cut.ring;
    const double s = g.sigma;
    const Vec2 hull_lo = rest_uv(g, 0, 0), hull_hi = rest_uv(g, g.nu - 1, g.nv - 1);
    Vec2 lo = ring[0], hi = ring[0];
    for (const auto& p : ring) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double tol = 1e-9 * s;
    if ((lo.array() < hull_lo.array() - tol).any() || (hi.array() > hull_hi.array() + tol).any())
        throw InputError(source, field,
                         "the outline reaches beyond the grid's particles: expected it within x " + num(hull_lo.x()) + " .. "
                             + num(hull_hi.x()) + " m, y " + num(hull_lo.y()) + " .. " + num(hull_hi.y()) + " m of the cloth's centre");

    const int n = g.size();
    cut.active.assign(n, 0);
    cut.area.assign(n, 0.0);
    std::vector<double> own(n, 0.0);
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            const int p = g.index(i, j);
            const Vec2 c = rest_uv(g, i, j);
            const Vec2 blo = c - Vec2(0.5 * s, 0.5 * s), bhi = c + Vec2(0.5 * s, 0.5 * s);
            if (outline.kind == Outline::Kind::RECTANGLE) {
                cut.active[p] = 1;
            } else {
                cut.active[p] = contains(ring, c) ? 1 : 0;
            }
            if ((bhi.array() < lo.array()).any() || (blo.array() > hi.array()).any()) continue;
            own[p] = signed_area(clip_to_box(ring, blo, bhi));
        }
    for (int p = 0; p < n; ++p) cut.count += cut.active[p];
    if (cut.count == 0)
        throw InputError(source, field,
                         "the outline encloses no particle of the grid (spacing " + num(s) + " m): make it larger or the spacing finer");

    // Each kept particle keeps its own clipped dual cell; a dropped particle's sliver goes to
    // its kept thread neighbours (else diagonal ones, else the nearest within two spacings).
    const double sliver_eps = 1e-12 * s * s;
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            const int p = g.index(i, j);
            if (cut.active[p]) {
                cut.area[p] += own[p];
                continue;
            }
            if (own[p] <= sliver_eps) continue;
            std::vector<int> to;
            for (int radius = 1; radius <= 2 && to.empty(); ++radius) {
                for (int pass = 0; pass < 2 && to.empty(); ++pass)
                    for (int dj = -radius; dj <= radius; ++dj)
                        for (int di = -radius; di <= radius; ++di) {
                            const int a = std::abs(di), b = std::abs(dj);
                            if (std::max(a, b) != radius) continue;
                            if (pass == 0 && a != 0 && b != 0) continue;  // thread neighbours first
                            const int ii = i + di, jj = j + dj;
                            if (ii < 0 || jj < 0 || ii >= g.nu || jj >= g.nv || !cut.active[g.index(ii, jj)]) continue;
                            to.push_back(g.index(ii, jj));
                        }
            }
            if (to.empty()) {
                const Vec2 c = rest_uv(g, i, j);
                throw InputError(source, field,
                                 "the outline is too small for the grid: a part of it near (" + num(c.x()) + ", " + num(c.y())
                                     + ") m lies more than two spacings from any particle inside it; make the spacing finer");
            }
            for (int q : to) cut.area[q] += own[p] / static_cast<double>(to.size());
        }

    bool full_cell = false;
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            if (!cut.active[g.index(i, j)]) continue;
            const bool left = i > 0 && cut.active[g.index(i - 1, j)], right = i + 1 < g.nu && cut.active[g.index(i + 1, j)];
            const bool down = j > 0 && cut.active[g.index(i, j - 1)], up = j + 1 < g.nv && cut.active[g.index(i, j + 1)];
            if (!left && !right && !down && !up) {
                const Vec2 c = rest_uv(g, i, j);
                throw InputError(source, field,
                                 "the outline is too small for the grid: the particle at (" + num(c.x()) + ", " + num(c.y())
                                     + ") m has no thread neighbour inside it; make the spacing finer");
            }
            if (right && up && cut.active[g.index(i + 1, j + 1)]) full_cell = true;
        }
    if (!full_cell)
        throw InputError(source, field,
                         "the outline is too small for the grid: no grid cell (spacing " + num(s)
                             + " m) lies inside it; make the spacing finer");
    cut.total_area = signed_area(ring);
    return cut;
}

namespace {

/// A clipped cell's triangles with no vertex but the polygon's: the points clipping projected
/// along a side of the cell (between the points where the outline crosses it) dropped, then a
/// fan when what remains is convex (every cell of a convex outline, a disc's); otherwise
/// triangulate's slabs. The slabs add points along the cell's sides where the neighbouring cell
/// has none: T-junctions, open edges in a mesh reader (issue 53).
std::vector<std::array<Vec2, 3>> cell_triangles(const Ring& poly, const Vec2& lo, const Vec2& hi)
{
    const double tol = 1e-12 * (hi - lo).norm();
    const auto sides = [&](const Vec2& p) {
        return (std::abs(p.x() - lo.x()) <= tol ? 1 : 0) | (std::abs(p.x() - hi.x()) <= tol ? 2 : 0)
            | (std::abs(p.y() - lo.y()) <= tol ? 4 : 0) | (std::abs(p.y() - hi.y()) <= tol ? 8 : 0);
    };
    Ring r = poly;
    for (bool changed = true; changed && r.size() >= 3;) {
        changed = false;
        for (std::size_t k = 0; k < r.size() && r.size() >= 3; ++k) {
            const Vec2& a = r[(k + r.size() - 1) % r.size()];
            const Vec2& b = r[k];
            const Vec2& c = r[(k + 1) % r.size()];
            if ((b - a).norm() <= tol || (sides(a) & sides(b) & sides(c)) != 0) {
                r.erase(r.begin() + static_cast<std::ptrdiff_t>(k));
                changed = true;
                --k;
            }
        }
    }
    if (r.size() < 3) return triangulate(poly);
    bool convex = true;
    for (std::size_t k = 0; k < r.size() && convex; ++k) {
        const Vec2 e0 = r[(k + 1) % r.size()] - r[k], e1 = r[(k + 2) % r.size()] - r[(k + 1) % r.size()];
        convex = e0.x() * e1.y() - e0.y() * e1.x() >= -tol * (e0.norm() + e1.norm());
    }
    if (!convex) return triangulate(poly);
    std::vector<std::array<Vec2, 3>> tris;
    for (std::size_t k = 1; k + 1 < r.size(); ++k) tris.push_back({r[0], r[k], r[k + 1]});
    return tris;
}

}  // namespace

geometry::TriangleMesh cut_surface(const Grid& g, const ClothCut& cut, const Positions& x, std::vector<Vec2>* uv)
{
    if (uv) uv->clear();
    const int n = g.size();
    // Positions of every grid point: kept particles as they are, dropped ones extrapolated.
    Positions at(n, Vec3::Constant(NAN));
    std::vector<char> known(n, 0);
    for (int p = 0; p < n; ++p)
        if (cut.active[p]) {
            at[p] = x[p];
            known[p] = 1;
        }
    // Passes outward from the kept particles: a point is continued linearly along a thread
    // through two known points, else completes a parallelogram of three, else (last resort)
    // is its known neighbour moved by the rest offset; all exact for a plane.
    const int di4[4] = {1, -1, 0, 0}, dj4[4] = {0, 0, 1, -1};
    for (int pass = 0; pass < 3; ++pass) {
        const std::vector<char> was = known;
        const auto ok = [&](int i, int j) { return i >= 0 && j >= 0 && i < g.nu && j < g.nv && was[g.index(i, j)]; };
        for (int j = 0; j < g.nv; ++j)
            for (int i = 0; i < g.nu; ++i) {
                const int p = g.index(i, j);
                if (was[p]) continue;
                Vec3 sum = Vec3::Zero();
                int k = 0;
                for (int d = 0; d < 4; ++d)
                    if (ok(i + di4[d], j + dj4[d]) && ok(i + 2 * di4[d], j + 2 * dj4[d])) {
                        sum += 2 * at[g.index(i + di4[d], j + dj4[d])] - at[g.index(i + 2 * di4[d], j + 2 * dj4[d])];
                        ++k;
                    }
                if (k == 0)
                    for (int a : {-1, 1})
                        for (int b : {-1, 1})
                            if (ok(i + a, j) && ok(i, j + b) && ok(i + a, j + b)) {
                                sum += at[g.index(i + a, j)] + at[g.index(i, j + b)] - at[g.index(i + a, j + b)];
                                ++k;
                            }
                if (k == 0 && pass == 2)
                    for (int d = 0; d < 4 && k == 0; ++d)
                        if (ok(i + di4[d], j + dj4[d])) {
                            const Vec2 off = rest_uv(g, i, j) - rest_uv(g, i + di4[d], j + dj4[d]);
                            sum += at[g.index(i + di4[d], j + dj4[d])] + Vec3(off.x(), off.y(), 0.0);
                            ++k;
                        }
                if (k > 0) {
                    at[p] = sum / k;
                    known[p] = 1;
                }
            }
    }

    geometry::TriangleMesh mesh;
    std::vector<int> vertex_of(n, -1);
    const auto particle_vertex = [&](int p) {
        if (vertex_of[p] < 0) {
            vertex_of[p] = static_cast<int>(mesh.vertices.size());
            mesh.vertices.push_back(at[p]);
            if (uv) uv->push_back(rest_uv(g, p % g.nu, p / g.nu) / g.sigma);
        }
        return vertex_of[p];
    };
    const double s = g.sigma;
    const double full = s * s;
    constexpr long kWeldSteps = 1'000'000'000;  ///< a cut edge's points rounded to 1e-9 spacings
    std::map<std::pair<long long, long long>, int> edge_vertex;
    for (int j = 0; j + 1 < g.nv; ++j)
        for (int i = 0; i + 1 < g.nu; ++i) {
            const int p00 = g.index(i, j), p10 = g.index(i + 1, j), p01 = g.index(i, j + 1), p11 = g.index(i + 1, j + 1);
            const Vec2 lo = rest_uv(g, i, j), hi = rest_uv(g, i + 1, j + 1);
            const bool all = cut.active[p00] && cut.active[p10] && cut.active[p01] && cut.active[p11];
            const Ring poly = clip_to_box(cut.ring, lo, hi);
            const double a = poly.size() >= 3 ? signed_area(poly) : 0.0;
            if (a <= 1e-12 * full) continue;
            if (!known[p00] || !known[p10] || !known[p01] || !known[p11]) continue;  // cannot happen for a cut_grid outline
            if (all && a >= full * (1 - 1e-12)) {
                mesh.faces.emplace_back(particle_vertex(p00), particle_vertex(p10), particle_vertex(p11));
                mesh.faces.emplace_back(particle_vertex(p00), particle_vertex(p11), particle_vertex(p01));
                continue;
            }
            for (const auto& t : cell_triangles(poly, lo, hi)) {
                int f[3];
                for (int k = 0; k < 3; ++k) {
                    const Vec2& q = t[k];
                    const double u = (q.x() - lo.x()) / s, v = (q.y() - lo.y()) / s;
                    // Welded: a cell corner is its particle's vertex; a point of the cut edge
                    // (on a cell's side, shared with the next cell) is one vertex, found by its
                    // rest position rounded to 1e-9 spacings.
                    const long ku = std::lround(u * kWeldSteps), kv = std::lround(v * kWeldSteps);
                    const bool corner_u = ku == 0 || ku == kWeldSteps, corner_v = kv == 0 || kv == kWeldSteps;
                    if (corner_u && corner_v) {
                        f[k] = particle_vertex(g.index(i + (ku != 0), j + (kv != 0)));
                        continue;
                    }
                    const std::pair<long long, long long> key{static_cast<long long>(i) * kWeldSteps + ku,
                                                              static_cast<long long>(j) * kWeldSteps + kv};
                    const auto [it, fresh] = edge_vertex.try_emplace(key, static_cast<int>(mesh.vertices.size()));
                    if (fresh) {
                        mesh.vertices.push_back((1 - u) * (1 - v) * at[p00] + u * (1 - v) * at[p10] + (1 - u) * v * at[p01]
                                                + u * v * at[p11]);
                        if (uv) uv->push_back(q / s);
                    }
                    f[k] = it->second;
                }
                if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) mesh.faces.emplace_back(f[0], f[1], f[2]);
            }
        }
    return mesh;
}

}  // namespace woven::model
