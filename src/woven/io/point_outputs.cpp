#include "woven/io/point_outputs.hpp"

#include <initializer_list>

namespace woven::io {

nlohmann::json point_outputs(const std::string& command, const nlohmann::json& m)
{
    nlohmann::json o = nlohmann::json::object();
    const auto get = [&](const nlohmann::json& j, std::initializer_list<const char*> path) -> nlohmann::json {
        const nlohmann::json* at = &j;
        for (const char* k : path) {
            if (!at->is_object() || !at->contains(k)) return nullptr;
            at = &(*at)[k];
        }
        return *at;
    };
    if (command == "drape") {
        o["energy_J"] = get(m, {"energy", "total_J"});
        o["max_residual_rel"] = get(m, {"equilibrium", "max_residual_rel"});
        o["converged"] = get(m, {"converged"});
        o["steps"] = get(m, {"steps"});
        o["iterations"] = get(m, {"iterations"});
        o["particles"] = get(m, {"particles"});
        // The fold structure: billows per corner and box face ("2+0 2+1 2+1 2+0"), the
        // corner analysis of the drape (analysis/folds.hpp) when the scene has a box.
        std::string folds;
        const auto corners = get(m, {"folds", "corners"});
        if (corners.is_array())
            for (const auto& c : corners) {
                std::string b;
                if (c.contains("billows") && c["billows"].is_array())
                    for (const auto& n : c["billows"]) b += (b.empty() ? "" : "+") + n.dump();
                folds += (folds.empty() ? "" : " ") + b;
            }
        o["folds"] = folds.empty() ? nlohmann::json(nullptr) : nlohmann::json(folds);
        o["projected_area_m2"] = get(m, {"folds", "projected_area_m2"});
    } else if (command == "cusick") {
        const bool many = m.contains("drape_coefficient_mean");
        o["drape_coefficient_percent"] = many ? m["drape_coefficient_mean"] : get(m, {"drape_coefficient_percent"});
        o["drape_coefficient_std"] = many ? m["drape_coefficient_std"] : nlohmann::json(0.0);
        std::string nodes;
        double energy = 0, residual = 0;
        long steps = 0;
        bool any = false;
        if (m.contains("runs") && m["runs"].is_array())
            for (const auto& r : m["runs"]) {
                nodes += (nodes.empty() ? "" : " ") + r.value("nodes", nlohmann::json(nullptr)).dump();
                energy += r.value("energy_J", 0.0) / static_cast<double>(m["runs"].size());
                residual = std::max(residual, r.value("max_residual_rel", 0.0));
                steps += r.value("steps", 0L);
                any = true;
            }
        o["nodes"] = nodes;
        o["energy_J"] = any ? nlohmann::json(energy) : nlohmann::json(nullptr);
        o["max_residual_rel"] = any ? nlohmann::json(residual) : nlohmann::json(nullptr);
        o["converged"] = get(m, {"converged"});
        o["steps"] = any ? nlohmann::json(steps) : nlohmann::json(nullptr);
        o["particles"] = get(m, {"particles"});
    } else if (command == "garment") {
        o["hem_nodes"] = get(m, {"hem", "nodes"});
        o["flare"] = get(m, {"hem", "flare"});
        o["below_waist_m"] = get(m, {"hem", "below_waist_m"});
        o["length_drop_m"] = get(m, {"hem", "length_drop_m"});
        o["seam_max_gap_over_spacing"] = get(m, {"seam_max_gap_over_spacing"});
        o["energy_J"] = get(m, {"energy", "total_J"});
        o["converged"] = get(m, {"converged"});
        o["steps"] = get(m, {"steps"});
        o["particles"] = get(m, {"particles"});
    } else {
        double worst_summary = 0, worst_curve = 0;
        int tests = 0;
        if (m.contains("tests") && m["tests"].is_array())
            for (const auto& t : m["tests"]) {
                ++tests;
                if (t.contains("summary_rel_error") && t["summary_rel_error"].is_number())
                    worst_summary = std::max(worst_summary, std::abs(t["summary_rel_error"].get<double>()));
                if (t.contains("curve_max_rel_error") && t["curve_max_rel_error"].is_number())
                    worst_curve = std::max(worst_curve, t["curve_max_rel_error"].get<double>());
                const std::string name = t.value("test", std::string("test")) + "_" + t.value("direction", std::string(""));
                o[name + "_simulated"] = t.value("simulated_summary", nlohmann::json(nullptr));
                o[name + "_input"] = t.value("input_summary", nlohmann::json(nullptr));
            }
        o["tests"] = tests;
        o["worst_summary_rel_error"] = worst_summary;
        o["worst_curve_rel_error"] = worst_curve;
    }
    return o;
}

}  // namespace woven::io
