// woven fabrics: the built-in fabrics with their key KES values.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "woven/app/drape_report.hpp"
#include "woven/cli/commands.hpp"
#include "woven/io/fabric_file.hpp"

namespace woven::cli {

namespace {

std::string fixed(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

/// Prints rows as left-aligned (first and last column) or right-aligned (numbers) columns.
void print_table(const std::vector<std::vector<std::string>>& rows)
{
    if (rows.empty()) return;
    std::vector<std::size_t> width(rows[0].size(), 0);
    for (const auto& r : rows)
        for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size());
    for (const auto& r : rows) {
        std::string line;
        for (std::size_t c = 0; c < r.size(); ++c) {
            const bool last = c + 1 == r.size();
            const bool left = c == 0 || last;
            const std::string pad(width[c] - r[c].size(), ' ');
            line += left ? r[c] + (last ? "" : pad) : pad + r[c];
            if (!last) line += "  ";
        }
        while (!line.empty() && line.back() == ' ') line.pop_back();
        std::cout << line << "\n";
    }
}

}  // namespace

int run_fabrics(const FabricsOptions& options)
{
    nlohmann::json list = nlohmann::json::array();
    std::vector<std::vector<std::string>> rows;
    rows.push_back({"name", "W", "B warp", "B weft", "G", "description"});
    rows.push_back({"", "mg/cm2", "gf.cm2/cm", "gf.cm2/cm", "gf/(cm.deg)", ""});
    for (const auto& name : io::builtin_fabric_names()) {
        const kes::FabricData f = io::find_fabric(name);
        const KesValues v = kes_values(f);
        rows.push_back({name, fixed(v.W, 2), fixed(v.B_warp, 4), fixed(v.B_weft, 4), fixed(v.G, 3), f.description});
        list.push_back({{"name", name},
                        {"description", f.description},
                        {"W_mg_cm2", v.W},
                        {"B_warp_gf_cm2_cm", v.B_warp},
                        {"B_weft_gf_cm2_cm", v.B_weft},
                        {"G_gf_cm_deg", v.G},
                        {"bending_warp_from", f.bending_warp.summary ? "summary" : "curve"},
                        {"bending_weft_from", f.bending_weft.summary ? "summary" : "curve"},
                        {"shear_from", f.shear.summary ? "summary" : "curve"}});
    }
    if (options.json)
        std::cout << list.dump(2) << "\n";
    else
        print_table(rows);
    return kExitOk;
}

void add_fabrics_command(CLI::App& app, int& exit_code)
{
    auto options = std::make_shared<FabricsOptions>();
    CLI::App* sub = app.add_subcommand("fabrics", "List the built-in fabrics with their KES values");
    sub->footer("Columns: W (mg/cm2), B warp and B weft (gf.cm2/cm), G (gf/(cm.deg)). B and G are the fabric's "
                "summary values when it gives them, else the slope of its curve over the KES windows "
                "(0.5-1.5 1/cm, 0.5-5 deg).");
    sub->add_flag("--json", options->json, "Machine-readable output (a JSON array)");
    sub->callback([options, &exit_code] { exit_code = run_fabrics(*options); });
}

}  // namespace woven::cli
