#include "woven/analysis/drape_shadow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "woven/common/error.hpp"

namespace woven::analysis {

namespace {

constexpr const char* kWhere = "drape shadow";

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The projected faces with finite vertices.
std::vector<std::array<Vec2, 3>> projected_faces(const geometry::TriangleMesh& mesh)
{
    std::vector<std::array<Vec2, 3>> out;
    out.reserve(mesh.faces.size());
    const int nv = static_cast<int>(mesh.vertices.size());
    for (const auto& f : mesh.faces) {
        std::array<Vec2, 3> t;
        bool ok = true;
        for (int k = 0; k < 3; ++k) {
            if (f[k] < 0 || f[k] >= nv || !mesh.vertices[f[k]].allFinite()) {
                ok = false;
                break;
            }
            t[k] = mesh.vertices[f[k]].head<2>();
        }
        if (ok) out.push_back(t);
    }
    return out;
}

/// The x-interval a triangle covers on the line y = const; false if it misses it.
bool interval_at(const std::array<Vec2, 3>& t, double y, double& x0, double& x1)
{
    x0 = INFINITY;
    x1 = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        const Vec2& p = t[k];
        const Vec2& q = t[(k + 1) % 3];
        if ((p.y() - y) * (q.y() - y) > 0) continue;
        if (p.y() == q.y()) {
            x0 = std::min({x0, p.x(), q.x()});
            x1 = std::max({x1, p.x(), q.x()});
        } else {
            // The ratio first (in [0, 1]): (y - p.y) (q.x - p.x) may overflow where the point does not.
            const double x = p.x() + (q.x() - p.x()) * ((y - p.y()) / (q.y() - p.y()));
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
        }
    }
    return x0 <= x1;
}

/// Calls `row_fn(k, intervals)` for each scanline y_k = y0 + (k + 1/2) row, k = 0..rows-1, that
/// some face meets, with the faces' x-intervals on it merged into disjoint sorted intervals. A
/// sweep: the faces sorted by their first row, the faces that meet the current row kept in an
/// active list; memory is O(faces) whatever the rows (each face's row span is clipped to
/// [0, rows)), the time the sum of the faces' row spans.
template <typename RowFn>
void for_each_row(const std::vector<std::array<Vec2, 3>>& faces, double y0, double row, long long rows, RowFn&& row_fn)
{
    struct Span {
        long long k0, k1;
        std::size_t face;
    };
    std::vector<Span> spans;
    spans.reserve(faces.size());
    const double last = static_cast<double>(rows - 1);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const auto& t = faces[f];
        const double lo = std::min({t[0].y(), t[1].y(), t[2].y()});
        const double hi = std::max({t[0].y(), t[1].y(), t[2].y()});
        // In double first: a row index beyond the table (or beyond long long) is clipped.
        const double a = std::max(0.0, std::ceil((lo - y0) / row - 0.5));
        const double b = std::min(last, std::floor((hi - y0) / row - 0.5));
        if (!(a <= b)) continue;
        spans.push_back({static_cast<long long>(a), static_cast<long long>(b), f});
    }
    std::sort(spans.begin(), spans.end(), [](const Span& p, const Span& q) { return p.k0 < q.k0; });
    std::vector<Span> active;
    std::vector<std::pair<double, double>> v, merged;
    std::size_t next = 0;
    long long k = 0;
    while (next < spans.size() || !active.empty()) {
        if (active.empty()) k = std::max(k, spans[next].k0);  // skip the rows no face meets
        while (next < spans.size() && spans[next].k0 <= k) active.push_back(spans[next++]);
        const double y = y0 + (static_cast<double>(k) + 0.5) * row;
        v.clear();
        for (const Span& s : active) {
            double x0, x1;
            if (interval_at(faces[s.face], y, x0, x1)) v.emplace_back(x0, x1);
        }
        std::sort(v.begin(), v.end());
        merged.clear();
        for (const auto& iv : v) {
            if (!merged.empty() && iv.first <= merged.back().second)
                merged.back().second = std::max(merged.back().second, iv.second);
            else
                merged.push_back(iv);
        }
        if (!merged.empty()) row_fn(k, merged);
        std::erase_if(active, [k](const Span& s) { return s.k1 <= k; });
        ++k;
    }
}

}  // namespace

double shadow_row_m(const geometry::TriangleMesh& mesh, double row_m, const ShadowCaps& caps)
{
    if (!(row_m > 0) || !std::isfinite(row_m)) throw InputError(kWhere, "row_m", "expected a positive scanline spacing in m");
    if (caps.rows < 1 || caps.row_spans < 1) throw InputError(kWhere, "caps", "expected at least 1 row and 1 row span");
    double lo = INFINITY, hi = -INFINITY, spans = 0, xlo = INFINITY, xhi = -INFINITY;
    for (const auto& t : projected_faces(mesh)) {
        const double a = std::min({t[0].y(), t[1].y(), t[2].y()}), b = std::max({t[0].y(), t[1].y(), t[2].y()});
        lo = std::min(lo, a);
        hi = std::max(hi, b);
        spans += b - a;
        xlo = std::min({xlo, t[0].x(), t[1].x(), t[2].x()});
        xhi = std::max({xhi, t[0].x(), t[1].x(), t[2].x()});
    }
    if (hi >= lo && (!std::isfinite(hi - lo) || !std::isfinite(spans) || !std::isfinite(xhi - xlo)))
        throw InputError(kWhere, "mesh", "expected vertices within 1e300 m of one another");
    if (!(hi > lo)) return row_m;
    // Both caps in double: an extent of 1e300 m asks for a row of 1e293 m, not an overflow.
    return std::max({row_m, (hi - lo) / static_cast<double>(caps.rows), spans / static_cast<double>(caps.row_spans)});
}

std::size_t shadow_memory_bytes(const geometry::TriangleMesh& mesh)
{
    // The projected faces (48 bytes), their row spans (24), the active list at worst every face
    // (24), a row's intervals at worst one per face (16, twice: gathered and merged).
    return mesh.faces.size() * (48 + 24 + 24 + 2 * 16);
}

double shadow_area(const geometry::TriangleMesh& mesh, double row_m, const ShadowCaps& caps)
{
    row_m = shadow_row_m(mesh, row_m, caps);
    const auto faces = projected_faces(mesh);
    if (faces.empty()) return 0.0;
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& t : faces)
        for (const auto& p : t) {
            lo = std::min(lo, p.y());
            hi = std::max(hi, p.y());
        }
    // Rows on a grid of multiples of row_m; far from the origin (lo / row_m beyond 2^53) the
    // product may round past lo, and then the rows start at lo.
    double y0 = std::floor(lo / row_m) * row_m;
    if (!(y0 <= lo && lo - y0 <= row_m)) y0 = lo;
    const long long rows = static_cast<long long>(std::clamp(std::ceil((hi - y0) / row_m), 0.0, static_cast<double>(caps.rows))) + 1;
    double length = 0;
    for_each_row(faces, y0, row_m, rows, [&](long long, const std::vector<std::pair<double, double>>& v) {
        for (const auto& iv : v) length += iv.second - iv.first;
    });
    return length * row_m;
}

double ShadowRaster::area_m2() const
{
    double n = 0;
    for (unsigned char c : covered) n += c ? 1 : 0;
    return n * pixel_m * pixel_m;
}

ShadowRaster rasterize_shadow(const geometry::TriangleMesh& mesh, const Vec2& origin, double pixel_m, int width, int height)
{
    if (!(pixel_m > 0) || !std::isfinite(pixel_m) || width <= 0 || height <= 0 || !origin.allFinite())
        throw InputError(kWhere, "raster", "expected a positive pixel size and image size");
    if (static_cast<long long>(width) * height > kMaxShadowPixels)
        throw InputError(kWhere, "raster",
                         "expected at most " + std::to_string(kMaxShadowPixels) + " pixels, got " + std::to_string(width) + " x "
                             + std::to_string(height));
    ShadowRaster r;
    r.width = width;
    r.height = height;
    r.pixel_m = pixel_m;
    r.origin = origin;
    r.covered.assign(static_cast<size_t>(width) * height, 0);
    for_each_row(projected_faces(mesh), origin.y(), pixel_m, height, [&](long long k, const std::vector<std::pair<double, double>>& v) {
        for (const auto& iv : v) {
            // Pixel c's centre origin.x + (c + 1/2) p lies in [x0, x1].
            // Clipped in double: an interval far outside the picture is no int overflow.
            const double a = std::max(0.0, std::ceil((iv.first - origin.x()) / pixel_m - 0.5));
            const double b = std::min(static_cast<double>(width - 1), std::floor((iv.second - origin.x()) / pixel_m - 0.5));
            if (!(a <= b)) continue;
            const int c0 = static_cast<int>(a), c1 = static_cast<int>(b);
            for (int c = c0; c <= c1; ++c) r.covered[static_cast<size_t>(c) + static_cast<size_t>(width) * static_cast<size_t>(k)] = 1;
        }
    });
    return r;
}

std::vector<double> shadow_radius(const geometry::TriangleMesh& mesh, const Vec2& centre, int n)
{
    if (n < 8) throw InputError(kWhere, "angles", "expected at least 8 angles");
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    const double step = kTwoPi / n;
    std::vector<double> r(n, 0.0);
    // Ray k: centre + t d_k, d_k = (sin theta_k, cos theta_k), theta from +y towards +x.
    std::vector<Vec2> dirs(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) dirs[static_cast<std::size_t>(k)] = Vec2(std::sin(k * step), std::cos(k * step));
    auto exit_distance = [&](const std::array<Vec2, 3>& t, int k) {
        const Vec2& d = dirs[static_cast<std::size_t>(k)];
        double best = -1;
        for (int e = 0; e < 3; ++e) {
            const Vec2 p = t[e], q = t[(e + 1) % 3];
            const Vec2 ed = q - p;
            const double den = cross(d, ed);
            if (std::abs(den) < 1e-300) continue;
            const double tt = cross(p, ed) / den;
            const double s = cross(p, d) / den;
            if (s >= -1e-12 && s <= 1 + 1e-12 && tt >= 0) best = std::max(best, tt);
        }
        return best;
    };
    for (auto t : projected_faces(mesh)) {
        for (auto& p : t) p -= centre;
        // A triangle strictly around the centre (or with the centre on an edge) meets every
        // ray; otherwise only the rays within its angular span (less than pi) as seen from the
        // centre, taken over its vertices away from the centre.
        const double c0 = cross(t[1] - t[0], -t[0]), c1 = cross(t[2] - t[1], -t[1]), c2 = cross(t[0] - t[2], -t[2]);
        const double scale = 1e-12 * (t[0].squaredNorm() + t[1].squaredNorm() + t[2].squaredNorm());
        int at_centre = -1;
        for (int v = 0; v < 3; ++v)
            if (t[v].squaredNorm() <= scale) at_centre = v;
        const bool around = at_centre < 0 && ((c0 >= 0 && c1 >= 0 && c2 >= 0) || (c0 <= 0 && c1 <= 0 && c2 <= 0));
        int k0 = 0, k1 = n - 1;
        if (!around) {
            int ref = at_centre == 0 ? 1 : 0;
            const double a0 = std::atan2(t[ref].x(), t[ref].y());
            double lo = 0, hi = 0;
            for (int v = 0; v < 3; ++v) {
                if (v == ref || v == at_centre) continue;
                double dlt = std::atan2(t[v].x(), t[v].y()) - a0;
                while (dlt > std::numbers::pi) dlt -= kTwoPi;
                while (dlt < -std::numbers::pi) dlt += kTwoPi;
                lo = std::min(lo, dlt);
                hi = std::max(hi, dlt);
            }
            k0 = static_cast<int>(std::ceil((a0 + lo) / step - 1e-9));
            k1 = static_cast<int>(std::floor((a0 + hi) / step + 1e-9));
        }
        for (int k = k0; k <= k1; ++k) {
            const int kk = ((k % n) + n) % n;
            const double t_exit = exit_distance(t, kk);
            if (t_exit > r[kk]) r[kk] = t_exit;
        }
    }
    return r;
}

double drape_coefficient_percent(double shadow_area_m2, double disc_area_m2, double specimen_area_m2)
{
    if (!(disc_area_m2 > 0) || !(specimen_area_m2 > disc_area_m2) || !std::isfinite(specimen_area_m2))
        throw InputError(kWhere, "areas", "expected 0 < disc area < specimen area");
    return (shadow_area_m2 - disc_area_m2) / (specimen_area_m2 - disc_area_m2) * 100.0;
}

Nodes find_nodes(const std::vector<double>& radius_m, double flat_radius_m, double min_prominence_m)
{
    Nodes nodes;
    const double deg_per_sample = 360.0 / static_cast<double>(radius_m.size());
    for (const Peak& p : periodic_peaks(radius_m, min_prominence_m)) {
        nodes.angle_deg.push_back(p.index * deg_per_sample);
        nodes.radius_m.push_back(p.value);
        nodes.depth_m.push_back(flat_radius_m - p.value);
        nodes.amplitude_m.push_back(p.prominence);
    }
    return nodes;
}

DrapeShadow measure_drape(const geometry::TriangleMesh& specimen, const Vec2& centre, double disc_radius_m, double specimen_radius_m,
                          double specimen_area_m2, const DrapeShadowOptions& options)
{
    if (!(disc_radius_m > 0) || !(specimen_radius_m > disc_radius_m))
        throw InputError(kWhere, "radius", "expected 0 < disc radius < specimen radius");
    if (!(options.min_prominence_fraction > 0)) throw InputError(kWhere, "min_prominence_fraction", "expected a positive fraction");
    DrapeShadow d;
    d.shadow_area_m2 = shadow_area(specimen, options.row_m);
    d.disc_area_m2 = std::numbers::pi * disc_radius_m * disc_radius_m;
    d.specimen_area_m2 = specimen_area_m2;
    d.drape_coefficient_percent = drape_coefficient_percent(d.shadow_area_m2, d.disc_area_m2, specimen_area_m2);
    d.radius_m = shadow_radius(specimen, centre, options.angles);
    d.nodes = find_nodes(d.radius_m, specimen_radius_m, options.min_prominence_fraction * (specimen_radius_m - disc_radius_m));
    return d;
}

}  // namespace woven::analysis
