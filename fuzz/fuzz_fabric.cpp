// libFuzzer target: the fabric file parser (io::parse_fabric), then what `woven fit` and
// `woven drape` do with an accepted fabric (a small cloth model and its energy). Bad input must
// be an InputError; an accepted fabric must give finite numbers, else the target aborts.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/model/cloth_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    kes::FabricData f;
    try {
        f = io::parse_fabric(text, "fuzz.toml");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(std::isfinite(f.areal_density_mg_cm2), "areal density");
    for (const kes::Curve* c : {&f.bending_warp.curve, &f.bending_weft.curve, &f.shear.curve})
        for (std::size_t k = 0; k < c->x.size(); ++k)
            woven::fuzz::require(std::isfinite(c->x[k]) && std::isfinite(c->y[k]), "curve point");
    try {
        const model::Grid grid{4, 4, 0.02};
        const model::ClothModel m = model::make_cloth_model(f, grid, model::ModelOptions{});
        Positions x = model::flat_grid(grid, Vec3(0, 0, 0.5));
        woven::fuzz::require(std::isfinite(m.energy(x)), "energy of the flat cloth");
        // A gently folded cloth: bending and trellis away from their rest state.
        for (std::size_t k = 0; k < x.size(); ++k) x[k].z() += 0.004 * std::sin(1.7 * double(k));
        woven::fuzz::require(std::isfinite(m.energy(x)), "energy of a folded cloth");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());  // a fit-stage rejection is fine, if well formed
    }
    return 0;
}
