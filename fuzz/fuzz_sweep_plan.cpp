// libFuzzer target: sweep plans (batch::parse_sweep_plan), then their points made one at a time as
// `sweep --list` makes them (up to 2,000) and each point's overrides applied to its built-in
// scene or fabric. Bad input must be a one-line InputError; an accepted plan must have 1 ..
// kMaxSweepPoints points, distinct folder names that stay in the folder, command lines that
// start with the command, and values without a duplicate per axis.
#include <cstdint>
#include <set>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/batch/sweep_plan.hpp"
#include "woven/common/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    batch::SweepPlan plan;
    try {
        plan = batch::parse_sweep_plan(text, "fuzz.toml", ".");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(plan.size() >= 1 && plan.size() <= batch::kMaxSweepPoints, "plan size");
    for (const auto& a : plan.axes) {
        std::set<std::string> seen;
        for (const auto& v : a.values) woven::fuzz::require(seen.insert(v.text).second, "axis (a value twice)");
    }
    std::set<std::string> names;
    const std::size_t n = std::min<std::size_t>(plan.size(), 2000);
    for (std::size_t i = 0; i < n; ++i) {
        const batch::SweepPoint p = plan.point(i);
        woven::fuzz::require(p.index == i, "point index");
        woven::fuzz::require(!p.name.empty() && p.name.size() <= 220 && p.name.find('/') == std::string::npos && p.name[0] != '.' &&
                                 names.insert(p.name).second,
                             "point folder name");
        woven::fuzz::require(p.args.size() >= 2 && p.args[0] == plan.command, "point command line");
        if (i < 20 && (!p.scene_overrides.empty() || !p.fabric_overrides.empty())) {
            try {
                if (!p.scene_overrides.empty())
                    (void)batch::apply_toml_overrides(batch::scene_or_fabric_text(p.args[1], "scene"), p.args[1], p.scene_overrides);
                if (!p.fabric_overrides.empty() && plan.command != "drape")
                    (void)batch::apply_toml_overrides(batch::scene_or_fabric_text(p.args[1], "fabric"), p.args[1], p.fabric_overrides);
            } catch (const InputError& e) {
                woven::fuzz::check_one_line(e.what());
            }
        }
    }
    return 0;
}
