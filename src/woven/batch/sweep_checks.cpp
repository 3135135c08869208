// The checks made before a sweep's points run (sweep.hpp, sweep_parts.hpp): every point's
// overridden scene and fabric read, the memory of the largest drape.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "woven/app/files.hpp"
#include "woven/sim/resources.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/batch/sweep_parts.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::batch {

using namespace woven::app;

/// Reads every point's overridden scene and fabric with the commands' own readers before
/// anything runs: a bad value or a key the file does not have (a warning when a scene is read)
/// is an error naming the plan and the point.
void validate_sweep_overrides(const batch::SweepPlan& plan)
{
    bool any = false;
    for (const auto& a : plan.axes) any = any || a.key.rfind("scene.", 0) == 0 || a.key.rfind("fabric.", 0) == 0;
    for (const auto& v : plan.fixed) any = any || v.key.rfind("scene.", 0) == 0 || v.key.rfind("fabric.", 0) == 0;
    if (!any) return;
    std::set<std::string> seen;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        const batch::SweepPoint p = plan.point(index);
        if (p.scene_overrides.empty() && p.fabric_overrides.empty()) continue;
        const std::string key = point_signature(p).dump();
        if (!seen.insert(key).second) continue;
        std::vector<std::string> warnings;
        try {
            if (!p.scene_overrides.empty()) {
                const std::string text = batch::apply_toml_overrides(batch::scene_or_fabric_text(p.args[1], "scene"), p.args[1], p.scene_overrides);
                (void)io::parse_scene(text, "scene " + p.args[1], ".", &warnings);
            }
            if (!p.fabric_overrides.empty()) {
                std::string fabric;
                for (std::size_t k = 2; k + 1 < p.args.size(); ++k)
                    if (p.args[k] == "--fabric") fabric = p.args[k + 1];
                if (plan.command != "drape") fabric = p.args[1];
                if (fabric.empty()) fabric = io::find_scene(p.args[1]).fabric;
                const std::string text = batch::apply_toml_overrides(batch::scene_or_fabric_text(fabric, "fabric"), fabric, p.fabric_overrides);
                (void)io::parse_fabric(text, "fabric " + fabric, &warnings);
            }
        } catch (const InputError& e) {
            throw InputError(plan.source, "point " + p.name, e.what());
        }
        for (const auto& w : warnings)
            if (w.find("unknown key") != std::string::npos)
                throw InputError(plan.source, "point " + p.name, w + " (an override names a key the file does not have)");
    }
}

void check_points_memory(const batch::SweepPlan& plan, const std::vector<std::size_t>& todo, int jobs, int threads)
{
    if (plan.command != "drape" || todo.empty()) return;
    long long largest = 0;
    std::string at;
    std::set<std::string> seen;
    for (const std::size_t index : todo) {
        const batch::SweepPoint p = plan.point(index);
        io::SceneOverrides ov;
        for (std::size_t k = 2; k + 1 < p.args.size(); ++k)
            if (p.args[k] == "--grid") ov.grid = std::stoi(p.args[k + 1]);
        std::string key = p.args[1] + "\n" + (ov.grid ? std::to_string(*ov.grid) : "");
        for (const auto& o : p.scene_overrides) key += "\n" + o.key + "=" + o.text;
        if (!seen.insert(key).second) continue;
        if (seen.size() > 1000) break;
        try {
            std::vector<std::string> warnings;
            io::SceneSpec scene = p.scene_overrides.empty()
                                      ? io::find_scene(p.args[1], &warnings)
                                      : io::parse_scene(batch::apply_toml_overrides(batch::scene_or_fabric_text(p.args[1], "scene"), p.args[1],
                                                                                 p.scene_overrides),
                                                        "scene " + p.args[1], ".", &warnings);
            io::apply_overrides(scene, ov, plan.source);
            const long long n = static_cast<long long>(scene.cloth.nu) * scene.cloth.nv;
            if (n > largest) {
                largest = n;
                at = p.name;
            }
        } catch (const InputError&) {
            // The point's own run reports it.
        }
    }
    if (largest == 0) return;
    sim::MemoryEstimate e = sim::estimate_drape_memory(largest, threads);
    const double at_once = static_cast<double>(std::min<std::size_t>(static_cast<std::size_t>(jobs), todo.size()));
    e.resident_bytes *= at_once;  // the address space is each point's own
    check_memory_estimate(e, largest, plan.source, "point " + at,
                          at_once > 1 ? "use a smaller grid or fewer --jobs (" + std::to_string(static_cast<int>(at_once)) + " points at once)" : "use a smaller grid");
}

}  // namespace woven::batch
