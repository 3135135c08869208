// The pieces of `woven report`'s page (render/html_page.hpp): base64 and escaping, a plot with
// its data and axis frame, the sortable table, the page's inlined data and ready flag.
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

TEST(HtmlPage, PlotCarriesItsDataAndFrame)
{
    render::Plot p;
    p.title = "DC </script>";
    p.x_label = "c, cm";
    p.y_label = "DC, %";
    render::Series s;
    s.x = {1.35, 2.66, std::nan("")};
    s.y = {27.2, 63.1, 1.0};
    s.err = {0.5, 1.5, 0.0};
    s.label = "cotton & wool";
    s.style = render::Series::Style::LINE_AND_POINTS;
    p.series.push_back(s);
    const std::string html = render::html_plot(p, "plot-3", 600, 400);
    EXPECT_EQ(html.rfind("<figure class=\"plot\" id=\"plot-3\"><svg", 0), 0u);
    const std::size_t data = html.find("<script type=\"application/json\" class=\"plot-data\" data-for=\"plot-3\">");
    ASSERT_NE(data, std::string::npos);
    const std::string json = html.substr(data);
    // The title's "</script>" cannot end the element early; the numbers are all there, NaN as null.
    EXPECT_EQ(json.find("</script>"), json.size() - 9);
    EXPECT_NE(json.find("\"x\":[1.3500000000000001,2.6600000000000001,null]"), std::string::npos) << json.substr(0, 600);
    EXPECT_NE(json.find("\"err\":[0.5,1.5,0]"), std::string::npos);
    EXPECT_NE(json.find("\"label\":\"cotton & wool\""), std::string::npos);
    EXPECT_NE(json.find("\"color\":[31,119,180]"), std::string::npos);
    // The frame's range covers the data and their error bars (27.2 - 0.5 .. 63.1 + 1.5).
    const render::PlotFrame f = render::plot_frame(p, 600, 400);
    EXPECT_LE(f.y_lo, 26.7);
    EXPECT_GE(f.y_hi, 64.6);
    EXPECT_LE(f.x_lo, 1.35);
    EXPECT_GE(f.x_hi, 2.66);
    // Ids are the plot's own: two plots on a page do not share a glyph or clip id.
    EXPECT_EQ(html.find(" id=\"glyph"), std::string::npos);
    EXPECT_NE(html.find(" id=\"plot-3-"), std::string::npos);
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
    render::ViewModel m;
    m.name = "one";
    m.glb = std::string("glTF\2\0\0\0", 8);
    // A script's "</script>" inside the inlined library must not close the page's script.
    const std::string page = render::html_page("t", table, {m}, {"var s = '</script>';", "", "var loader;"});
    EXPECT_NE(page.find("<body data-ready=\"0\">"), std::string::npos);
    EXPECT_NE(page.find("dataset.ready = '1'"), std::string::npos);
    EXPECT_NE(page.find("var s = '<\\/script>';"), std::string::npos);
    EXPECT_NE(page.find("var loader;"), std::string::npos);
    EXPECT_NE(page.find("\"glb\":\"" + render::base64(m.glb) + "\""), std::string::npos);
    EXPECT_NE(page.find("<select id=\"view3d-field\">"), std::string::npos);
    // No model: no view, no library.
    const std::string plain = render::html_page("t", table, {}, {"var s;", "", ""});
    EXPECT_EQ(plain.find("view3d-field\">"), std::string::npos);
    EXPECT_EQ(plain.find("var s;"), std::string::npos);
}
