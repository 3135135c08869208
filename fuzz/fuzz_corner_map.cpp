// libFuzzer target: the corner map `woven experiment map --reuse` reads back
// (io::parse_corner_map). Bad input must be a one-line InputError; an accepted map must hold
// positive finite cell coordinates and finite billows on corners 0..3, and its cells' JSON must
// dump (the map writes them again).
#include <cmath>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/corner_map_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    io::CornerMap map;
    try {
        map = io::parse_corner_map(text, "fuzz.json");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(!map.cells.empty(), "corner map (no cells)");
    for (const auto& c : map.cells) {
        woven::fuzz::require(std::isfinite(c.ratio_warp_weft) && c.ratio_warp_weft > 0, "cell ratio");
        woven::fuzz::require(std::isfinite(c.bending_length_cm) && c.bending_length_cm > 0, "cell bending length");
        for (int k = 0; k < 4; ++k)
            for (const auto& b : c.corners[k]) {
                woven::fuzz::require(b.corner == k, "billow corner");
                woven::fuzz::require(std::isfinite(b.angle_deg) && std::abs(b.angle_deg) <= 180, "billow angle");
                woven::fuzz::require(std::isfinite(b.standout_m), "billow standout");
            }
        woven::fuzz::require(!c.has_folds || c.json.contains("folds"), "cell folds");
        (void)c.json.dump(1);
    }
    return 0;
}
