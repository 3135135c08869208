// libFuzzer target: a start file (io::parse_start_obj, `drape --start`, `cusick --start`) and
// the start's check (io::check_start_positions), on a 5 x 5 grid over a floor and a sphere.
// Bad input must be a one-line InputError; an accepted start must hold finite positions within
// the bounds and outside both obstacles, each from a line of the file.
#include <cstdint>
#include <memory>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/start_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    static const auto setup = [] {
        struct S {
            model::Grid grid;
            Positions flat;
            geometry::ObstacleSet obstacles;
        };
        auto s = std::make_unique<S>();
        s->grid.nu = s->grid.nv = 5;
        s->grid.sigma = 0.01;
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) s->flat.push_back(Vec3(0.01 * (i - 2), 0.01 * (j - 2), 0.2));
        s->obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
        s->obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0, 0, 0.05), 0.05));
        return s;
    }();
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    io::StartState st;
    try {
        st = io::parse_start_obj(text, "fuzz.obj", setup->grid, {}, setup->flat);
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(st.x.size() == 25 && st.line.size() == 25, "start size");
    for (std::size_t p = 0; p < 25; ++p) woven::fuzz::require(st.x[p].allFinite() && st.line[p] >= 1, "start position");
    const io::StartBounds bounds{&setup->obstacles, Vec3::Zero(), 1e3};
    try {
        io::check_start_positions(st.x, {}, {}, bounds, "fuzz.obj", "v", [&](int p) { return "line " + std::to_string(st.line[p]); });
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    for (const Vec3& q : st.x)
        woven::fuzz::require(q.cwiseAbs().maxCoeff() <= 1e3 && setup->obstacles.distance(q) > 0,
                             "start accepted inside or beyond the bounds");
    return 0;
}
