// libFuzzer target: the values a Python caller passes for a fabric or a scene (woven.Fabric(...),
// woven.Scene(...)), given here as a JSON document: io::fabric_from_values and
// io::scene_from_values (the conversion to a TOML document, then the files' own readers). Bad
// input must be an InputError with a one-line message; an accepted value must give finite numbers.
#include <cmath>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/values.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    using woven::fuzz::require;
    // Not JSON: nothing a Python caller can pass (nlohmann's parser keeps its own stack, so deep
    // nesting is not a recursion).
    const nlohmann::json values = nlohmann::json::parse(data, data + size, nullptr, false);
    if (values.is_discarded()) return 0;
    try {
        const kes::FabricData f = io::fabric_from_values(values, "Python fabric");
        require(std::isfinite(f.areal_density_mg_cm2) && f.areal_density_mg_cm2 > 0, "areal density");
        for (const kes::Curve* c : {&f.bending_warp.curve, &f.bending_weft.curve, &f.shear.curve})
            for (std::size_t k = 0; k < c->x.size(); ++k) require(std::isfinite(c->x[k]) && std::isfinite(c->y[k]), "curve point");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
    }
    try {
        const io::SceneSpec s = io::scene_from_values(values, "Python scene", "");  // no base: mesh and fabric files are not read
        const io::ClothSpec& c = s.cloth;
        require(std::isfinite(c.sigma()) && c.sigma() > 0, "sigma");
        require(c.centre.allFinite() && std::isfinite(c.yaw_deg), "cloth placement");
        require(std::isfinite(s.solver.residual_tolerance) && std::isfinite(s.solver.time_step) &&
                    std::isfinite(s.solver.contact_distance) && s.solver.contact_distance < c.sigma(),
                "solver option");
        if (static_cast<long long>(c.nu) * c.nv <= 2500) {
            const Positions x = c.initial_positions();
            for (const Vec3& p : x) require(p.allFinite(), "initial position");
        }
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
    }
    return 0;
}
