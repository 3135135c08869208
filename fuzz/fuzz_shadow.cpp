// libFuzzer target: the Cusick shadow measures (analysis/drape_shadow.hpp) of a mesh read from
// the input's bytes: up to 64 vertices of three doubles each (any bits: huge, tiny, non-finite),
// faces (k, k+1, k+2). Each must end in bounded memory and time (issue 53: one particle 1 km
// away took 9.3 GB) with a non-negative area, or refuse with a one-line InputError.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "fuzz_support.hpp"
#include "woven/analysis/drape_shadow.hpp"
#include "woven/common/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    geometry::TriangleMesh m;
    const std::size_t n = std::min<std::size_t>(size / 24, 64);
    for (std::size_t k = 0; k < n; ++k) {
        double c[3];
        std::memcpy(c, data + 24 * k, 24);
        m.vertices.emplace_back(c[0], c[1], c[2]);
    }
    for (std::size_t k = 0; k + 2 < n; ++k) m.faces.emplace_back(static_cast<int>(k), static_cast<int>(k + 1), static_cast<int>(k + 2));
    woven::fuzz::require(analysis::shadow_memory_bytes(m) <= 64 * 200, "shadow memory estimate");
    try {
        // Caps far below the defaults (2^20 rows, 2^26 crossings) keep each input quick; the
        // capping is the same code.
        const double a = analysis::shadow_area(m, 1e-4, analysis::ShadowCaps{1 << 6, 1 << 10});
        woven::fuzz::require(!(a < 0), "shadow area");
        const analysis::ShadowRaster r = analysis::rasterize_shadow(m, Vec2(-0.2, -0.2), 5e-3, 80, 80);
        woven::fuzz::require(r.covered.size() == 6400, "shadow raster");
        const std::vector<double> rad = analysis::shadow_radius(m, Vec2::Zero(), 64);
        for (double x : rad) woven::fuzz::require(!(x < 0), "shadow radius");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
    }
    return 0;
}
