#include "woven/analysis/folds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>

#include "woven/analysis/peaks.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"

namespace woven::analysis {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegPerRad = 180.0 / kPi;
/// Largest raster of projected_area (cells); a coarser cell is used beyond it.
constexpr double kMaxRasterCells = 4e7;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

bool face_ok(const geometry::TriangleMesh& mesh, const Eigen::Vector3i& f)
{
    const int n = static_cast<int>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k)
        if (f[k] < 0 || f[k] >= n || !mesh.vertices[f[k]].allFinite()) return false;
    return true;
}

double polyline_length(const Section& s)
{
    double len = 0;
    for (std::size_t i = 1; i < s.points.size(); ++i) len += (s.points[i] - s.points[i - 1]).norm();
    if (s.closed && s.points.size() > 2) len += (s.points.front() - s.points.back()).norm();
    return len;
}

/// Winding number of a closed section around the xy point c.
int winding(const Section& s, const Vec2& c)
{
    double total = 0;
    const std::size_t n = s.points.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 a = s.points[i].head<2>() - c, b = s.points[(i + 1) % n].head<2>() - c;
        total += std::atan2(cross2(a, b), a.dot(b));
    }
    return static_cast<int>(std::lround(total / (2 * kPi)));
}

}  // namespace

Vec2 BoxFootprint::to_local(const Vec2& p) const
{
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    const Vec2 d = p - centre;
    return Vec2(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
}

Vec2 BoxFootprint::to_world(const Vec2& q) const
{
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return centre + Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y());
}

double BoxFootprint::distance(const Vec2& p) const
{
    const Vec2 q = to_local(p).cwiseAbs() - half;
    const double outside = q.cwiseMax(0.0).norm();
    const double inside = std::min(std::max(q.x(), q.y()), 0.0);
    return outside + inside;
}

Vec2 BoxFootprint::corner(int c) const
{
    static constexpr int sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
    return to_world(Vec2(sx[c & 3] * half.x(), sy[c & 3] * half.y()));
}

Vec2 BoxFootprint::diagonal(int c) const
{
    const Vec2 d = corner(c) - centre;
    return d / d.norm();
}

int BoxFootprint::quadrant(const Vec2& p) const
{
    const Vec2 q = to_local(p);
    if (q.x() >= 0) return q.y() >= 0 ? 0 : 3;
    return q.y() >= 0 ? 1 : 2;
}

std::optional<BoxFootprint> box_footprint(const geometry::ObstacleSet& obstacles)
{
    std::optional<BoxFootprint> best;
    for (std::size_t k = 0; k < obstacles.size(); ++k) {
        const auto* box = dynamic_cast<const geometry::Box*>(&obstacles[k]);
        if (!box) continue;
        BoxFootprint f;
        f.centre = box->centre().head<2>();
        f.half = box->half_extents().head<2>();
        f.yaw_rad = box->yaw();
        f.top_z = box->centre().z() + box->half_extents().z();
        if (!best || f.top_z > best->top_z) best = f;
    }
    return best;
}

std::vector<Section> slice(const geometry::TriangleMesh& mesh, double height)
{
    // Each face the plane crosses gives one segment between two edge crossings; a crossing is
    // named by its edge (sorted vertex pair), so neighbouring faces share it exactly.
    std::unordered_map<std::uint64_t, int> node_of_edge;
    std::vector<Vec3> node_point;
    std::vector<std::array<int, 2>> segments;
    auto node = [&](int a, int b) {
        if (a > b) std::swap(a, b);
        const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
        const auto it = node_of_edge.find(key);
        if (it != node_of_edge.end()) return it->second;
        const Vec3& pa = mesh.vertices[a];
        const Vec3& pb = mesh.vertices[b];
        const double t = (height - pa.z()) / (pb.z() - pa.z());
        node_point.push_back(pa + t * (pb - pa));
        node_point.back().z() = height;
        const int id = static_cast<int>(node_point.size()) - 1;
        node_of_edge.emplace(key, id);
        return id;
    };
    for (const Eigen::Vector3i& f : mesh.faces) {
        if (!face_ok(mesh, f)) continue;
        bool above[3];
        for (int k = 0; k < 3; ++k) above[k] = mesh.vertices[f[k]].z() >= height;
        if (above[0] == above[1] && above[1] == above[2]) continue;
        int ends[2], m = 0;
        for (int k = 0; k < 3; ++k)
            if (above[k] != above[(k + 1) % 3]) ends[m++] = node(f[k], f[(k + 1) % 3]);
        if (ends[0] != ends[1]) segments.push_back({ends[0], ends[1]});
    }

    const int nn = static_cast<int>(node_point.size());
    std::vector<std::vector<int>> incident(nn);
    for (int s = 0; s < static_cast<int>(segments.size()); ++s)
        for (int e : segments[s]) incident[e].push_back(s);
    std::vector<char> used(segments.size(), 0);
    std::vector<Section> out;
    auto walk = [&](int start) {
        Section sec;
        int at = start;
        sec.points.push_back(node_point[at]);
        while (true) {
            int next_seg = -1;
            for (int s : incident[at])
                if (!used[s]) {
                    next_seg = s;
                    break;
                }
            if (next_seg < 0) break;
            used[next_seg] = 1;
            at = segments[next_seg][0] == at ? segments[next_seg][1] : segments[next_seg][0];
            if (at == start) {
                sec.closed = true;
                break;
            }
            sec.points.push_back(node_point[at]);
        }
        if (sec.points.size() >= 2) out.push_back(std::move(sec));
    };
    // Open arcs first (from their ends, degree 1), then the loops.
    for (int n = 0; n < nn; ++n)
        if (incident[n].size() == 1 && !used[incident[n][0]]) walk(n);
    for (int n = 0; n < nn; ++n)
        for (int s : incident[n])
            if (!used[s]) {
                walk(n);
                break;
            }
    return out;
}

std::vector<Billow> find_billows(const Section& section, const BoxFootprint& box, double prominence_m)
{
    const int n = static_cast<int>(section.points.size());
    std::vector<Billow> billows;
    if (n < 3) return billows;
    std::vector<double> d(n);
    for (int i = 0; i < n; ++i) d[i] = box.distance(section.points[i].head<2>());

    for (const Peak& p : prominent_peaks(d, prominence_m, section.closed ? SequenceEnds::PERIODIC : SequenceEnds::OPEN)) {
        Billow b;
        b.point = section.points[p.sample];
        const Vec2 q = b.point.head<2>();
        b.corner = box.quadrant(q);
        const Vec2 diag = box.diagonal(b.corner), v = q - box.corner(b.corner);
        b.angle_deg = std::atan2(cross2(diag, v), diag.dot(v)) * kDegPerRad;
        b.standout_m = p.value;
        b.prominence_m = p.prominence;
        billows.push_back(b);
    }
    std::sort(billows.begin(), billows.end(),
              [](const Billow& x, const Billow& y) { return x.corner != y.corner ? x.corner < y.corner : x.angle_deg < y.angle_deg; });
    return billows;
}

std::vector<Billow> SectionFolds::at_corner(int c) const
{
    std::vector<Billow> out;
    for (const Billow& b : billows)
        if (b.corner == c) out.push_back(b);
    return out;
}

double projected_area(const geometry::TriangleMesh& mesh, double cell_m)
{
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Eigen::Vector3i& f : mesh.faces)
        if (face_ok(mesh, f))
            for (int k = 0; k < 3; ++k) {
                lo = lo.cwiseMin(mesh.vertices[f[k]].head<2>());
                hi = hi.cwiseMax(mesh.vertices[f[k]].head<2>());
            }
    if (!(hi.array() > lo.array()).all()) return 0;
    const Vec2 span = hi - lo;
    if (span.x() * span.y() / (cell_m * cell_m) > kMaxRasterCells) cell_m = std::sqrt(span.x() * span.y() / kMaxRasterCells);
    const int nx = static_cast<int>(std::ceil(span.x() / cell_m)) + 1, ny = static_cast<int>(std::ceil(span.y() / cell_m)) + 1;
    std::vector<char> covered(static_cast<std::size_t>(nx) * ny, 0);
    for (const Eigen::Vector3i& f : mesh.faces) {
        if (!face_ok(mesh, f)) continue;
        const Vec2 p0 = mesh.vertices[f[0]].head<2>(), p1 = mesh.vertices[f[1]].head<2>(), p2 = mesh.vertices[f[2]].head<2>();
        const double area2 = cross2(p1 - p0, p2 - p0);
        if (area2 == 0) continue;
        const Vec2 flo = p0.cwiseMin(p1).cwiseMin(p2), fhi = p0.cwiseMax(p1).cwiseMax(p2);
        const int x0 = std::max(0, static_cast<int>(std::floor((flo.x() - lo.x()) / cell_m - 0.5)));
        const int x1 = std::min(nx - 1, static_cast<int>(std::ceil((fhi.x() - lo.x()) / cell_m - 0.5)));
        const int y0 = std::max(0, static_cast<int>(std::floor((flo.y() - lo.y()) / cell_m - 0.5)));
        const int y1 = std::min(ny - 1, static_cast<int>(std::ceil((fhi.y() - lo.y()) / cell_m - 0.5)));
        const double s = area2 > 0 ? 1 : -1;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const Vec2 c = lo + cell_m * Vec2(x + 0.5, y + 0.5);
                if (s * cross2(p1 - p0, c - p0) >= 0 && s * cross2(p2 - p1, c - p1) >= 0 && s * cross2(p0 - p2, c - p2) >= 0)
                    covered[static_cast<std::size_t>(y) * nx + x] = 1;
            }
    }
    std::size_t count = 0;
    for (char c : covered) count += c;
    return static_cast<double>(count) * cell_m * cell_m;
}

FoldAnalysis analyse_folds(const geometry::TriangleMesh& cloth, const BoxFootprint& box, const FoldOptions& options)
{
    const std::string src = "fold analysis";
    if (!(box.half.x() > 0 && box.half.y() > 0) || !box.centre.allFinite() || !std::isfinite(box.yaw_rad) || !std::isfinite(box.top_z))
        throw InputError(src, "box", "finite centre, yaw and top, half extents > 0");
    if (!(options.prominence_m > 0)) throw InputError(src, "prominence_m", "a prominence > 0 m");
    for (double depth : options.depths_m)
        if (!(depth > 0) || !std::isfinite(depth)) throw InputError(src, "depths_m", "depths > 0 m below the top face");
    if (cloth.vertices.empty() || cloth.faces.empty()) throw InputError(src, "cloth", "a non-empty mesh");

    FoldAnalysis fa;
    for (double depth : options.depths_m) {
        SectionFolds sf;
        sf.depth_m = depth;
        sf.height_m = box.top_z - depth;
        const std::vector<Section> sections = slice(cloth, sf.height_m);
        const Section* best = nullptr;
        double best_len = -1;
        for (const Section& s : sections)  // the longest loop around the box
            if (s.closed && winding(s, box.centre) != 0 && polyline_length(s) > best_len) {
                best = &s;
                best_len = polyline_length(s);
            }
        if (!best)
            for (const Section& s : sections)  // else the longest arc
                if (polyline_length(s) > best_len) {
                    best = &s;
                    best_len = polyline_length(s);
                }
        if (best) {
            sf.found = true;
            sf.closed = best->closed;
            sf.length_m = best_len;
            sf.billows = find_billows(*best, box, options.prominence_m);
        }
        fa.sections.push_back(std::move(sf));
    }

    double lowest = std::numeric_limits<double>::infinity();
    std::array<double, 4> side_low;
    side_low.fill(std::numeric_limits<double>::infinity());
    for (const Vec3& p : cloth.vertices) {
        if (!p.allFinite()) continue;
        if (p.z() < lowest) {
            lowest = p.z();
            fa.lowest_point = p;
        }
        const Vec2 q = box.to_local(p.head<2>());
        int side = -1;
        if (q.x() > box.half.x() && std::abs(q.y()) <= box.half.y())
            side = 0;
        else if (q.y() > box.half.y() && std::abs(q.x()) <= box.half.x())
            side = 1;
        else if (q.x() < -box.half.x() && std::abs(q.y()) <= box.half.y())
            side = 2;
        else if (q.y() < -box.half.y() && std::abs(q.x()) <= box.half.x())
            side = 3;
        if (side >= 0) side_low[side] = std::min(side_low[side], p.z());
    }
    for (int s = 0; s < 4; ++s) fa.hanging_m[s] = std::isfinite(side_low[s]) ? box.top_z - side_low[s] : 0.0;
    fa.projected_area_m2 = projected_area(cloth);
    return fa;
}

const char* to_string(CornerStructure s)
{
    switch (s) {
    case CornerStructure::NONE: return "none";
    case CornerStructure::SINGLE_BILLOW: return "single billow";
    case CornerStructure::PUSHED_BILLOW: return "pushed billow";
    case CornerStructure::TWO_FOLDS: return "two folds";
    case CornerStructure::SEVERAL_FOLDS: return "several folds";
    }
    return "?";
}

CornerBillows split_corner_billows(const std::vector<Billow>& billows)
{
    CornerBillows out;
    double largest = 0;
    for (const Billow& b : billows)
        if (std::abs(b.angle_deg) <= kCornerConeDeg) largest = std::max(largest, b.standout_m);
    for (const Billow& b : billows) {
        if (std::abs(b.angle_deg) > kCornerConeDeg) out.side_waves.push_back(b);
        else if (b.standout_m >= kFoldStandoutFraction * largest) out.folds.push_back(b);
        else out.ripples.push_back(b);
    }
    return out;
}

CornerStructure corner_structure(const std::vector<Billow>& billows)
{
    const std::vector<Billow> folds = split_corner_billows(billows).folds;
    switch (folds.size()) {
    case 0: return CornerStructure::NONE;
    case 1: return std::abs(folds[0].angle_deg) <= kDiagonalToleranceDeg ? CornerStructure::SINGLE_BILLOW : CornerStructure::PUSHED_BILLOW;
    case 2: return CornerStructure::TWO_FOLDS;
    default: return CornerStructure::SEVERAL_FOLDS;
    }
}

double corner_asymmetry_deg(const std::vector<Billow>& billows)
{
    double sum = 0, weight = 0;
    for (const Billow& b : billows) {
        sum += b.standout_m * b.angle_deg;
        weight += b.standout_m;
    }
    return weight > 0 ? sum / weight : 0.0;
}

}  // namespace woven::analysis
