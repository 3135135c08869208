// The pieces of `woven report`'s page (render/html_page.hpp): base64 and escaping, the SVG
// plot's axes covering its data, the sortable table, the page's inlined data and ready flag.
#include <string>

#include <gtest/gtest.h>

#include "woven/render/html_page.hpp"

using namespace woven;

TEST(HtmlPage, Base64AndEscaping)
{
    // RFC 4648 section 10's test vectors.
    EXPECT_EQ(render::base64(""), "");
    EXPECT_EQ(render::base64("f"), "Zg==");
    EXPECT_EQ(render::base64("fo"), "Zm8=");
    EXPECT_EQ(render::base64("foo"), "Zm9v");
    EXPECT_EQ(render::base64("foobar"), "Zm9vYmFy");
    EXPECT_EQ(render::base64(std::string("\xff\x00\x80", 3)), "/wCA");
    EXPECT_EQ(render::html_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
}

TEST(HtmlPage, PlotAxesCoverTheDataAndErrorBars)
{
    render::PlotSpec spec;
    spec.title = "DC <test>";
    spec.x_label = "c, cm";
    spec.y_label = "DC, %";
    spec.series.push_back({"cotton & wool", {1.35, 2.66}, {27.2, 63.1}, {0.5, 1.5}, true});
    const std::string svg = render::svg_plot(spec);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_NE(svg.find("DC &lt;test&gt;"), std::string::npos);  // escaped title
    EXPECT_NE(svg.find("cotton &amp; wool"), std::string::npos);
    // Round ticks from 20 to 70 cover 27.2 - 0.5 .. 63.1 + 1.5 (the last tick at or above the top).
    EXPECT_NE(svg.find(">20</text>"), std::string::npos);
    EXPECT_NE(svg.find(">70</text>"), std::string::npos);
    EXPECT_EQ(svg.find(">80</text>"), std::string::npos);
    EXPECT_NE(svg.find("+- 1.5"), std::string::npos);  // the error bar's tooltip
    render::PlotSpec empty;
    EXPECT_NE(render::svg_plot(empty).find("no data"), std::string::npos);
}

TEST(HtmlPage, TableAndPage)
{
    render::HtmlTable t;
    t.header = {"point", "DC"};
    t.numeric = {false, true};
    t.rows = {{"a<1>", "63.1"}, {"b", "27.2"}};
    t.row_class = {"", "failed"};
    const std::string table = render::html_table(t, "points");
    EXPECT_NE(table.find("<th data-numeric=\"1\""), std::string::npos);
    EXPECT_NE(table.find("<td>a&lt;1&gt;</td>"), std::string::npos);
    EXPECT_NE(table.find("<tr class=\"failed\">"), std::string::npos);
    render::ViewMesh m;
    m.name = "one";
    m.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.triangles = {0, 1, 2};
    // A script's "</script>" inside the inlined library must not close the page's script.
    const std::string page = render::html_page("t", table, {m}, "var s = '</script>';", "");
    EXPECT_NE(page.find("<body data-ready=\"0\">"), std::string::npos);
    EXPECT_NE(page.find("dataset.ready = '1'"), std::string::npos);
    EXPECT_NE(page.find("var s = '<\\/script>';"), std::string::npos);
    EXPECT_NE(page.find("\"tri\":\"" + render::base64(std::string("\0\0\0\0\1\0\0\0\2\0\0\0", 12)) + "\""), std::string::npos);
}
