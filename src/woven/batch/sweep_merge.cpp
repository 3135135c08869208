// The merge of a sweep folder (sweep.hpp): sweep.json and sweep.csv from the point folders that
// verify, and the main outputs of a point's manifest.
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/batch/sweep.hpp"
#include "woven/batch/sweep_parts.hpp"
#include "woven/io/point_outputs.hpp"

namespace woven::batch {

using namespace woven::app;

namespace fs = std::filesystem;

namespace {

/// The merged table's output columns in a reading order (others follow, sorted).
const std::vector<std::string>& preferred_columns()
{
    static const std::vector<std::string> c = {"drape_coefficient_percent", "drape_coefficient_std", "nodes", "energy_J", "folds",
                                               "projected_area_m2", "max_residual_rel", "converged", "steps", "iterations",
                                               "particles", "tests", "worst_summary_rel_error", "worst_curve_rel_error"};
    return c;
}

std::string csv_cell(const nlohmann::json& v)
{
    if (v.is_null()) return "";
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    if (s.find_first_of(",\"\n") != std::string::npos) {
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    }
    return s;
}

}  // namespace

MergeCounts merge_sweep(const batch::SweepPlan& plan, const std::string& sweep_dir)
{
    const fs::path sweep(sweep_dir);
    const SweepFolderLock lock(sweep_dir);
    MergeCounts counts;
    nlohmann::json rows = nlohmann::json::array();
    std::vector<std::string> output_keys;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        const batch::SweepPoint p = plan.point(index);
        nlohmann::json row = point_json(p);
        const PointState st = point_state(sweep, p);
        if (st.done) {
            ++counts.done;
            const auto pj = read_sweep_json(sweep / p.name / "point.json");
            const auto m = read_manifest(sweep / p.name);
            row["status"] = "done";
            row["wall_time_s"] = (*pj)["wall_time_s"];
            row["host"] = pj->value("host", std::string());
            row["outputs"] = io::point_outputs(plan.command, m ? *m : nlohmann::json::object());
            for (auto it = row["outputs"].begin(); it != row["outputs"].end(); ++it)
                if (std::find(output_keys.begin(), output_keys.end(), it.key()) == output_keys.end()) output_keys.push_back(it.key());
        } else if (const auto f = read_sweep_json(sweep / "failed" / (p.name + ".json")); f && f->value("plan", nlohmann::json()) == point_signature(p)) {
            ++counts.failed;
            row["status"] = "failed";
            row["wall_time_s"] = f->value("wall_time_s", nlohmann::json(nullptr));
            row["problem"] = f->value("problem", std::string());
        } else {
            ++counts.missing;
            row["status"] = "missing";
            if (!st.problem.empty()) row["problem"] = st.problem;
        }
        rows.push_back(row);
    }
    nlohmann::json j;
    j["version"] = WOVEN_VERSION;
    j["plan"] = plan.source;
    j["name"] = plan.name;
    j["description"] = plan.description;
    j["command"] = plan.command;
    nlohmann::json axes = nlohmann::json::array();
    for (const auto& a : plan.axes) {
        nlohmann::json vals = nlohmann::json::array();
        for (const auto& v : a.values) vals.push_back(value_json(v));
        axes.push_back({{"key", a.key}, {"values", vals}});
    }
    j["axes"] = axes;
    j["points"] = plan.size();
    j["done"] = counts.done;
    j["failed"] = counts.failed;
    j["missing"] = counts.missing;
    j["rows"] = rows;
    std::vector<std::string> ordered;
    for (const auto& k : preferred_columns())
        if (std::find(output_keys.begin(), output_keys.end(), k) != output_keys.end()) ordered.push_back(k);
    std::sort(output_keys.begin(), output_keys.end());
    for (const auto& k : output_keys)
        if (std::find(ordered.begin(), ordered.end(), k) == ordered.end()) ordered.push_back(k);
    output_keys = ordered;
    j["output_columns"] = output_keys;
    std::ostringstream csv;
    csv << "point";
    for (const auto& a : plan.axes) csv << "," << csv_cell(a.key);
    csv << ",status,wall_time_s";
    for (const auto& k : output_keys) csv << "," << k;
    csv << "\n";
    for (const auto& r : rows) {
        csv << csv_cell(r["point"]);
        for (const auto& a : plan.axes) csv << "," << csv_cell(r["values"][a.key]);
        csv << "," << csv_cell(r["status"]) << "," << csv_cell(r.value("wall_time_s", nlohmann::json(nullptr)));
        for (const auto& k : output_keys) csv << "," << (r.contains("outputs") && r["outputs"].contains(k) ? csv_cell(r["outputs"][k]) : "");
        csv << "\n";
    }
    write_atomic(sweep / "sweep.json", j.dump(2) + "\n");
    write_atomic(sweep / "sweep.csv", csv.str());
    return counts;
}

}  // namespace woven::batch
