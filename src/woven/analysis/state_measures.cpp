// Geometric measures of a draped state (state_measures.hpp).
#include "woven/analysis/state_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace woven::analysis {

StateMeasures measure_state(const Positions& x, const model::Grid& grid, const geometry::ObstacleSet& obstacles,
                            double contact_distance, const std::vector<char>& active)
{
    StateMeasures m;
    geometry::Aabb box;
    const auto kept = [&](int p) { return active.empty() || active[p]; };
    for (std::size_t q = 0; q < x.size(); ++q) {
        if (!kept(static_cast<int>(q))) continue;
        const Vec3& p = x[q];
        box.extend(p);
        double nearest = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < obstacles.size(); ++k) {
            const double d = obstacles[k].distance(p);
            nearest = std::min(nearest, d);
            m.max_penetration = std::max(m.max_penetration, -d);
        }
        if (nearest < contact_distance) ++m.contact_particles;
    }
    if (!box.empty()) {
        m.bbox_min = box.lo;
        m.bbox_max = box.hi;
    }
    double sum = 0;
    long count = 0;
    m.strain_max = -std::numeric_limits<double>::infinity();
    m.strain_min = std::numeric_limits<double>::infinity();
    auto edge = [&](int a, int b) {
        const double s = (x[a] - x[b]).norm() / grid.sigma - 1.0;
        m.strain_max = std::max(m.strain_max, s);
        m.strain_min = std::min(m.strain_min, s);
        m.strain_max_abs = std::max(m.strain_max_abs, std::abs(s));
        sum += s;
        ++count;
    };
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            if (!kept(grid.index(i, j))) continue;
            if (i + 1 < grid.nu && kept(grid.index(i + 1, j))) edge(grid.index(i, j), grid.index(i + 1, j));
            if (j + 1 < grid.nv && kept(grid.index(i, j + 1))) edge(grid.index(i, j), grid.index(i, j + 1));
        }
    if (count == 0) m.strain_max = m.strain_min = 0;
    m.strain_mean = count ? sum / count : 0;
    return m;
}

}  // namespace woven::analysis
