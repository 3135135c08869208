#include "woven/io/start_file.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "woven/common/error.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/sha256.hpp"
#include "woven/model/outline.hpp"

namespace woven::io {

namespace {

/// How far (in spacings) a vertex's vt may lie from a particle's rest position: woven writes 9
/// significant digits.
constexpr double kRestTolerance = 1e-4;

/// The line's whitespace-separated tokens.
std::vector<std::string_view> start_tokens(std::string_view line)
{
    std::vector<std::string_view> out;
    std::size_t k = 0;
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
    while (k < line.size()) {
        while (k < line.size() && space(line[k])) ++k;
        const std::size_t b = k;
        while (k < line.size() && !space(line[k])) ++k;
        if (k > b) out.push_back(line.substr(b, k - b));
    }
    return out;
}

/// `count` finite numbers, tokens 1..count of `t` and no more; false otherwise. Each token is
/// read whole (std::from_chars, decimal or exponent form: no hex, no comma, no trailing junk).
bool start_numbers(const std::vector<std::string_view>& t, std::size_t count, double* out)
{
    if (t.size() != count + 1) return false;
    for (std::size_t k = 0; k < count; ++k) {
        std::string_view s = t[k + 1];
        if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars refuses a leading +, C's strtod does not
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out[k], std::chars_format::general);
        if (ec != std::errc() || ptr != s.data() + s.size() || s.empty() || !std::isfinite(out[k])) return false;
    }
    return true;
}

}  // namespace

StartState parse_start_obj(std::string_view text, const std::string& source, const model::Grid& grid,
                           const std::vector<char>& active, const Positions& fallback)
{
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> v;
    std::vector<std::size_t> v_line;
    std::vector<Vec2> vt;
    std::size_t line_no = 0, begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view line = text.substr(begin, end - begin);
        begin = end + 1;
        ++line_no;
        const std::vector<std::string_view> t = start_tokens(line);
        if (t.empty()) continue;
        if (t[0] == "v") {
            double c[3];
            if (!start_numbers(t, 3, c))
                throw InputError(source, "v",
                                 "line " + std::to_string(line_no) + ": expected three finite coordinates (m) and nothing else");
            v.emplace_back(c[0], c[1], c[2]);
            v_line.push_back(line_no);
        } else if (t[0] == "vt") {
            double c[2];
            if (!start_numbers(t, 2, c))
                throw InputError(source, "vt",
                                 "line " + std::to_string(line_no) + ": expected two finite texture coordinates and nothing else");
            vt.emplace_back(c[0], c[1]);
        }
    }
    const int n = grid.size();
    const auto cloth = [&](int p) { return active.empty() || active[p]; };
    StartState s;
    s.x = fallback;
    s.x.resize(n, Vec3::Zero());
    s.line.assign(static_cast<std::size_t>(n), 0);
    const std::string expected = "expected a drape of the same scene and grid (" + std::to_string(grid.nu) + " x " + std::to_string(grid.nv) +
                                 ", spacing " + std::to_string(grid.sigma) + " m): its " + std::to_string(n) +
                                 " particles in grid order, or a cut cloth's vertices with vt at their rest positions in spacings";
    if (static_cast<int>(v.size()) == n) {  // a whole grid (drape.obj of an uncut cloth): grid order
        for (int p = 0; p < n; ++p)
            if (cloth(p)) {
                s.x[p] = v[p];
                s.line[p] = v_line[p];
            }
    } else {
        if (vt.size() != v.size())
            throw InputError(source, "v", std::to_string(v.size()) + " vertices, " + std::to_string(vt.size()) + " texture coordinates; " + expected);
        // The vertex at each grid point: vt rounded to the grid's rest positions.
        std::map<std::pair<long, long>, int> at;
        const Vec2 origin = model::rest_uv(grid, 0, 0) / grid.sigma;
        for (std::size_t k = 0; k < vt.size(); ++k) {
            const Vec2 g = vt[k] - origin;
            const double i = std::round(g.x()), j = std::round(g.y());
            if (std::abs(g.x() - i) > kRestTolerance || std::abs(g.y() - j) > kRestTolerance) continue;
            // Off the grid (a vt of 9.2e18 overflowed the cast: found by fuzz_start): no particle's.
            if (!(std::abs(i) <= 1e9 && std::abs(j) <= 1e9)) continue;
            at.emplace(std::make_pair(static_cast<long>(i), static_cast<long>(j)), static_cast<int>(k));
        }
        int missing = 0;
        for (int p = 0; p < n; ++p) {
            if (!cloth(p)) continue;
            const auto it = at.find({p % grid.nu, p / grid.nu});
            if (it == at.end()) {
                ++missing;
                continue;
            }
            s.x[p] = v[it->second];
            s.line[p] = v_line[it->second];
        }
        if (missing > 0)
            throw InputError(source, "v",
                             std::to_string(v.size()) + " vertices, " + std::to_string(missing) + " of the cloth's particles without one at its rest position; " + expected);
    }
    s.sha256 = sha256_hex(text);
    return s;
}

StartState load_start(const std::string& path, const model::Grid& grid, const std::vector<char>& active, const Positions& fallback)
{
    if (path.size() < 4 || path.compare(path.size() - 4, 4, ".obj") != 0)
        throw InputError(path, "file", "expected a drape .obj file (drape.obj or cusick.obj, as woven writes them)");
    return parse_start_obj(read_input_file(path, kMaxStartBytes, {"start file", "a drape .obj file"}), path, grid, active, fallback);
}

void check_start_positions(const Positions& x, const std::vector<char>& active, const std::vector<int>& held, const StartBounds& bounds,
                           const std::string& source, const std::string& field, const std::function<std::string(int)>& where)
{
    std::vector<char> skip(x.size(), 0);
    for (int p : held)
        if (p >= 0 && static_cast<std::size_t>(p) < x.size()) skip[static_cast<std::size_t>(p)] = 1;
    const auto num = [](double d) {
        std::ostringstream s;
        s.precision(9);
        s << d;
        return s.str();
    };
    const auto vec = [&](const Vec3& p) { return "(" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ")"; };
    for (std::size_t p = 0; p < x.size(); ++p) {
        if (skip[p] || !(active.empty() || active[p])) continue;
        const Vec3& q = x[p];
        if (!q.allFinite()) throw InputError(source, field, where(static_cast<int>(p)) + ": expected finite positions (m)");
        if (!((q - bounds.centre).cwiseAbs().maxCoeff() <= bounds.reach_m))
            throw InputError(source, field,
                             where(static_cast<int>(p)) + ": the position " + vec(q) + " m lies outside " + bounds.name
                                 + "; expected every coordinate within " + num(bounds.reach_m) + " m of " + vec(bounds.centre)
                                 + " m, as the flat start is");
        if (!bounds.obstacles) continue;
        const geometry::ObstacleSet& obs = *bounds.obstacles;
        const double d = obs.distance(q);
        if (d > 0) continue;
        std::size_t k = 0;
        for (std::size_t i = 0; i < obs.size(); ++i)
            if (obs[i].distance(q) <= d) {
                k = i;
                break;
            }
        throw InputError(source, field,
                         where(static_cast<int>(p)) + ": the position " + vec(q) + " m lies inside or touches obstacle["
                             + std::to_string(k + 1) + "] (" + obs[k].kind() + "): signed distance " + num(d)
                             + " m; expected a start strictly outside every obstacle, as the flat start is");
    }
}

}  // namespace woven::io
