// libFuzzer target: the scene parser (io::parse_scene, which also builds the obstacles and
// checks the start), then the cloth's energy at its start for small grids with a built-in
// fabric. Bad input must be an InputError; an accepted scene must give finite numbers.
#include <cmath>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    using woven::fuzz::require;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    io::SceneSpec s;
    try {
        s = io::parse_scene(text, "fuzz.toml", "");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    const io::ClothSpec& c = s.cloth;
    require(std::isfinite(c.sigma()) && c.sigma() > 0, "sigma");
    require(c.centre.allFinite() && std::isfinite(c.yaw_deg), "cloth placement");
    const sim::SolverOptions& o = s.solver;
    require(std::isfinite(o.residual_tolerance) && std::isfinite(o.move_tolerance) && std::isfinite(o.time_step) &&
                std::isfinite(o.contact_distance) && std::isfinite(o.viscosity) && std::isfinite(o.friction) &&
                o.contact_distance < c.sigma(),
            "solver option");
    require(std::isfinite(s.model.gravity) && std::isfinite(s.model.C0), "model option");
    if (static_cast<long long>(c.nu) * c.nv > 2500) return 0;  // keep the run fast
    const Positions x = c.initial_positions();
    for (const Vec3& p : x) require(p.allFinite(), "initial position");
    for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
        const double d = s.obstacles[k].distance(x[x.size() / 2]);
        require(std::isfinite(d) && d > 0, "obstacle distance at the start");
    }
    if (s.fabric.find('/') != std::string::npos || s.fabric.ends_with(".toml")) return 0;  // no file reads
    try {
        const kes::FabricData f = io::find_fabric(s.fabric);
        const model::ClothModel m = model::make_cloth_model(f, c.grid(), s.model);
        require(std::isfinite(m.energy(x)), "energy at the start");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
    }
    return 0;
}
