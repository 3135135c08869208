// The sections of `woven report`'s page (render/report_sections.hpp) from parsed manifests and
// tables: cells and tables, the plots' data (read back from the page's JSON) and the gallery.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/render/report_sections.hpp"

using namespace woven;
using namespace woven::render;
using nlohmann::json;

namespace {

/// The data of each plot on the page (html_plot's <script class="plot-data">), in order.
std::vector<json> plot_data(const std::string& html)
{
    std::vector<json> out;
    const std::string open = "class=\"plot-data\"";
    for (std::size_t at = html.find(open); at != std::string::npos; at = html.find(open, at + 1)) {
        const std::size_t b = html.find('>', at) + 1, e = html.find("</script>", b);
        out.push_back(json::parse(html.substr(b, e - b)));
    }
    return out;
}

CsvTable table(const std::vector<std::string>& head, const std::vector<std::vector<double>>& cols)
{
    CsvTable t;
    t.head = head;
    t.cols = cols;
    for (const auto& c : cols) {
        t.text.emplace_back();
        for (double v : c) t.text.back().push_back(std::to_string(v));
    }
    return t;
}

ReportPoint point(const std::string& name, json values, json outputs)
{
    ReportPoint p;
    p.name = name;
    p.values = std::move(values);
    p.outputs = std::move(outputs);
    return p;
}

}  // namespace

TEST(ReportSections, CellsAndKeyTable)
{
    EXPECT_EQ(report_cell(json(0.1234567)), "0.123457");
    EXPECT_EQ(report_cell(json(3)), "3");
    EXPECT_EQ(report_cell(json("cotton")), "cotton");
    EXPECT_EQ(report_cell(json()), "");
    const HtmlTable t = key_table(json{{"energy", {{"bending", 2.5e-3}}}, {"fabric", "wool"}, {"list", {1, 2}}});
    ASSERT_EQ(t.rows.size(), 2u);  // arrays are left out
    EXPECT_EQ(t.rows[0], (std::vector<std::string>{"energy.bending", "0.0025"}));
    EXPECT_EQ(t.rows[1], (std::vector<std::string>{"fabric", "wool"}));
    const CsvTable c = table({"a", "b"}, {{1, 2}, {3, 4}});
    EXPECT_EQ(c.col("b"), 1);
    EXPECT_EQ(c.col("z"), -1);
    EXPECT_DOUBLE_EQ(c.get("b")[1], 4);
    EXPECT_TRUE(c.get("z").empty());
}

TEST(ReportSections, PointsTableAndSweepPlots)
{
    std::vector<ReportPoint> points = {point("a", {{"fabric", "cotton"}, {"seed", 1}}, {{"drape_coefficient_percent", 40.0}}),
                                       point("b", {{"fabric", "cotton"}, {"seed", 2}}, {{"drape_coefficient_percent", 44.0}}),
                                       point("c", {{"fabric", "wool"}, {"seed", 1}}, {{"drape_coefficient_percent", 60.0}}),
                                       point("d", {{"fabric", "wool"}, {"seed", 2}}, json::object())};
    points[0].wall = 1.5;
    points[3].status = "failed";
    points[3].problem = "diverged";
    const HtmlTable t = points_table(points, {"fabric", "seed"}, {"drape_coefficient_percent"});
    EXPECT_EQ(t.header, (std::vector<std::string>{"point", "fabric", "seed", "status", "wall_time_s", "drape_coefficient_percent"}));
    EXPECT_EQ(t.numeric, (std::vector<bool>{false, false, true, false, true, true}));
    EXPECT_EQ(t.rows[0], (std::vector<std::string>{"a", "cotton", "1", "done", "1.5", "40"}));
    EXPECT_EQ(t.rows[3][3], "failed: diverged");
    EXPECT_EQ(t.row_class[3], "failed");

    ReportPlots plots;
    const BendingLength length = [](const std::string& f) { return f == "cotton" ? 2.0 : f == "wool" ? 3.0 : std::nan(""); };
    sweep_plots(points, {"fabric", "seed"}, "cusick", length, plots);
    ASSERT_EQ(plots.count, 1);
    const auto data = plot_data(plots.html);
    ASSERT_EQ(data.size(), 1u);
    EXPECT_EQ(data[0]["id"], "plot-1");
    const json& s = data[0]["series"][0];  // one series: seeds are averaged, the failed point left out
    EXPECT_EQ(s["label"], "all points");
    EXPECT_EQ(s["x"], json({2.0, 3.0}));
    EXPECT_DOUBLE_EQ(s["y"][0].get<double>(), 42.0);
    EXPECT_NEAR(s["err"][0].get<double>(), std::sqrt(8.0), 1e-12);  // sample std of 40, 44
    EXPECT_DOUBLE_EQ(s["err"][1].get<double>(), 0.0);
}

TEST(ReportSections, KesSectionReadsTheLoopsAndTheCantilever)
{
    const CsvReader csv = [](const ReportPoint&, const std::string& name) -> std::optional<CsvTable> {
        if (name == "shear_warp.csv" || name == "shear_weft.csv")
            return table({"phi_deg", "simulated_F_gf_per_cm", "input_F_gf_per_cm"}, {{0, 4, 8}, {0, name == "shear_warp.csv" ? 1.0 : 0.5, 2}, {0, 1.5, 3}});
        if (name == "cantilever_warp.csv") {
            CsvTable t = table({"source", "x_m", "z_m"}, {{0, 0, 0}, {0, 0.01, 0.02}, {0, -0.001, -0.003}});
            t.text[0] = {"simulated", "simulated", "elastica"};
            return t;
        }
        return std::nullopt;
    };
    ReportPlots plots;
    kes_section(ReportPoint{}, csv, plots, "p1: ");
    ASSERT_EQ(plots.count, 2);
    const auto data = plot_data(plots.html);
    EXPECT_EQ(data[0]["title"], "p1: KES-FB1 shear: force against shear angle");
    ASSERT_EQ(data[0]["series"].size(), 3u);
    EXPECT_EQ(data[0]["series"][0]["label"], "input");
    EXPECT_DOUBLE_EQ(data[0]["series"][2]["y"][1].get<double>(), 0.5);
    EXPECT_EQ(data[0]["series"][2]["color"], json({214, 39, 40}));  // the weft's simulated in red
    EXPECT_EQ(data[1]["series"][0]["label"], "elastica warp");
    EXPECT_DOUBLE_EQ(data[1]["series"][0]["y"][0].get<double>(), -0.003);
    EXPECT_DOUBLE_EQ(data[1]["series"][1]["x"][1].get<double>(), 0.01);
}

TEST(ReportSections, DrapeAndCusickSections)
{
    ReportPoint d;
    d.manifest = json::parse(R"({"energy": {"bending": 1.25e-4, "note": "x"}, "energy_initial_J": 0.5,
        "folds": {"heights_m": [0.1], "corners": [{"corner": 1, "billows": [2], "angles_deg": [[-21.0, 19.0]]}]}})");
    const std::string drape = drape_section(d);
    EXPECT_NE(drape.find("<td>bending</td><td>0.000125</td>"), std::string::npos) << drape;
    EXPECT_NE(drape.find("<td>energy_initial_J</td><td>0.5</td>"), std::string::npos);
    EXPECT_NE(drape.find("<td>1</td><td>0.1</td><td>2</td><td></td><td>-21 19</td>"), std::string::npos) << drape;

    ReportPoint c;
    c.manifest = {{"drape_coefficient_percent", 45.5}, {"disc_diameter_m", 0.18}, {"node_angles_deg", {90.0}}, {"node_radii_m", {0.12}}};
    ReportPlots plots;
    const std::string html = cusick_section(c, std::vector<double>(8, 0.1), plots);
    EXPECT_NE(html.find("<td>drape_coefficient_percent</td><td>45.5</td>"), std::string::npos);
    const auto data = plot_data(plots.html);
    ASSERT_EQ(data.size(), 1u);
    EXPECT_EQ(data[0]["title"], "Shadow seen from above (warp up), DC 45.5 %");
    const json& series = data[0]["series"];
    ASSERT_EQ(series.size(), 3u);  // disc, outline, nodes
    EXPECT_NEAR(series[0]["x"][45].get<double>(), 0.09, 1e-12);  // the disc's radius at 90 deg
    EXPECT_NEAR(series[1]["x"][2].get<double>(), 0.1, 1e-12);     // the outline at 90 deg
    EXPECT_NEAR(series[2]["x"][0].get<double>(), 0.12, 1e-12);    // the node at 90 deg
    EXPECT_NEAR(series[2]["y"][0].get<double>(), 0.0, 1e-12);
}

TEST(ReportSections, FitSectionAndExperimentSection)
{
    ReportPlots plots;
    const CsvReader csv = [](const ReportPoint&, const std::string& name) -> std::optional<CsvTable> {
        if (name == "trellis_energy.csv") return table({"phi_rad", "T_J"}, {{0.5, 0.96, 1.0}, {1e-3, 2e-3, 5e-3}});
        return std::nullopt;
    };
    fit_section(ReportPoint{}, csv, {CurveFitView{"fit", "K", "M", {0, 1}, {0, 2}, {0, 1}, {0, 2}, {}, {}, kBlue}}, plots);
    ASSERT_EQ(plots.count, 2);  // the curve and T(phi); no bending energy files
    const auto fit = plot_data(plots.html);
    EXPECT_EQ(fit[0]["series"].size(), 2u);
    EXPECT_DOUBLE_EQ(fit[1]["series"][0]["y"][1].get<double>(), 2e-3);
    EXPECT_GE(fit[1]["frame"]["y_hi"].get<double>(), 2e-3);  // clipped at the first T past 0.95 rad
    EXPECT_LT(fit[1]["frame"]["y_hi"].get<double>(), 5e-3);

    ReportPoint e;
    e.manifest = {{"cube_results.json",
                   {{"seeds", 2},
                    {"runs", {{{"fabric", "cotton"}, {"energy_J", 1.0}}, {{"fabric", "cotton"}, {"energy_J", 3.0}}}},
                    {"statistics", {{"cotton", {{"corners", 4}, {"multiple", 1}}}}}}}};
    ReportPlots ex;
    const std::string html = experiment_section(
        e, [](const std::string&) { return 2.5; }, [](const std::string& f) { return f == "cotton" ? std::optional<Vec3>(Vec3(0.8, 0.36, 0.22)) : std::nullopt; },
        ex);
    EXPECT_NE(html.find("<td>seeds</td><td>2</td>"), std::string::npos);
    EXPECT_NE(html.find("<td>cotton</td><td>4</td><td></td><td></td><td>1</td>"), std::string::npos) << html;
    const auto data = plot_data(ex.html);
    ASSERT_EQ(data.size(), 1u);  // energy; no run has a projected area
    const json& s = data[0]["series"][0];
    EXPECT_EQ(s["label"], "cotton (2 seeds)");
    EXPECT_DOUBLE_EQ(s["x"][0].get<double>(), 2.5);
    EXPECT_DOUBLE_EQ(s["y"][0].get<double>(), 2.0);
    EXPECT_NEAR(s["err"][0].get<double>(), std::sqrt(2.0), 1e-12);
    EXPECT_EQ(s["color"], json::array({204, 92, 56}));  // cotton's display colour (0.80, 0.36, 0.22) x 255, as in the figure
}

TEST(ReportSections, GalleryInlinesTheListedPictures)
{
    ReportPoint p = point("a", json::object(), json::object());
    p.manifest = {{"files", {{"shadow.png", {{"size", 3}}}, {"cusick.json", {{"size", 9}}}}}};
    ReportPoint failed = p;
    failed.status = "failed";
    std::vector<std::string> asked;
    const std::string html = gallery({p, failed}, [&asked](const ReportPoint& q, const std::string& n) {
        asked.push_back(q.name + "/" + n);
        return std::string("abc");
    });
    EXPECT_EQ(asked, (std::vector<std::string>{"a/shadow.png"}));
    EXPECT_NE(html.find("src=\"data:image/png;base64,YWJj\""), std::string::npos);
    EXPECT_NE(html.find("<figcaption>a: shadow.png</figcaption>"), std::string::npos);
}
