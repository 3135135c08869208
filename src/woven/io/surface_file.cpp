#include "woven/io/surface_file.hpp"

#include <iomanip>
#include <sstream>

#include "woven/common/error.hpp"

namespace woven::io {

std::string surface_obj(const geometry::TriangleMesh& m, const std::vector<Vec2>& uv, const std::string& comment)
{
    if (!uv.empty() && uv.size() != m.vertices.size()) throw InputError("surface", "uv", "expected one texture coordinate per vertex");
    std::ostringstream o;
    o << std::setprecision(9);
    o << "# woven: " << comment << "; units m";
    if (!uv.empty()) o << "; vt = rest position in particle spacings (u weft, v warp)";
    o << "\n";
    for (const Vec3& v : m.vertices) o << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const Vec2& t : uv) o << "vt " << t.x() << " " << t.y() << "\n";
    for (const auto& f : m.faces) {
        o << "f";
        for (int k = 0; k < 3; ++k) {
            o << " " << f[k] + 1;
            if (!uv.empty()) o << "/" << f[k] + 1;
        }
        o << "\n";
    }
    return o.str();
}

}  // namespace woven::io
