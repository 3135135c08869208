#include "woven/io/start_file.hpp"

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

}  // namespace

StartState parse_start_obj(std::string_view text, const std::string& source, const model::Grid& grid,
                           const std::vector<char>& active, const Positions& fallback)
{
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> v;
    std::vector<Vec2> vt;
    std::size_t line_no = 0, begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string_view::npos) end = text.size();
        const std::string line(text.substr(begin, end - begin));
        begin = end + 1;
        ++line_no;
        std::istringstream in(line);
        std::string tag;
        in >> tag;
        if (tag == "v") {
            Vec3 p;
            if (!(in >> p.x() >> p.y() >> p.z()) || !p.allFinite())
                throw InputError(source, "v", "line " + std::to_string(line_no) + ": expected three finite coordinates (m)");
            v.push_back(p);
        } else if (tag == "vt") {
            Vec2 t;
            if (!(in >> t.x() >> t.y()) || !std::isfinite(t.x()) || !std::isfinite(t.y()))
                throw InputError(source, "vt", "line " + std::to_string(line_no) + ": expected two finite texture coordinates");
            vt.push_back(t);
        }
    }
    const int n = grid.size();
    const auto cloth = [&](int p) { return active.empty() || active[p]; };
    StartState s;
    s.x = fallback;
    s.x.resize(n, Vec3::Zero());
    const std::string expected = "expected a drape of the same scene and grid (" + std::to_string(grid.nu) + " x " + std::to_string(grid.nv) +
                                 ", spacing " + std::to_string(grid.sigma) + " m): its " + std::to_string(n) +
                                 " particles in grid order, or a cut cloth's vertices with vt at their rest positions in spacings";
    if (static_cast<int>(v.size()) == n) {  // a whole grid (drape.obj of an uncut cloth): grid order
        for (int p = 0; p < n; ++p)
            if (cloth(p)) s.x[p] = v[p];
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

}  // namespace woven::io
