#include "woven/render/html_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace woven::render {

std::string html_escape(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&#39;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string base64(std::string_view bytes)
{
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                           static_cast<unsigned char>(bytes[i + 2]);
        out += k[v >> 18];
        out += k[(v >> 12) & 63];
        out += k[(v >> 6) & 63];
        out += k[v & 63];
    }
    if (i < bytes.size()) {
        const bool two = i + 1 < bytes.size();
        const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0);
        out += k[v >> 18];
        out += k[(v >> 12) & 63];
        out += two ? k[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

namespace {

std::string fmt(double v, int digits = 4)
{
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    return b;
}

/// Round tick positions covering [lo, hi]: steps of 1, 2 or 5 times a power of ten.
std::vector<double> ticks(double lo, double hi, int target = 6)
{
    if (!(hi > lo)) {
        const double pad = lo == 0 ? 1.0 : std::abs(lo) * 0.1;
        lo -= pad;
        hi += pad;
    }
    const double raw = (hi - lo) / target;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    double step = p;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (raw <= m * p) {
            step = m * p;
            break;
        }
    // From the last tick at or below lo to the first at or above hi.
    const long long a = static_cast<long long>(std::floor(lo / step + 1e-9)), b = static_cast<long long>(std::ceil(hi / step - 1e-9));
    std::vector<double> t;
    for (long long k = a; k <= b; ++k) t.push_back(static_cast<double>(k) * step);
    return t;
}

const char* const kColours[] = {"#c0392b", "#2471a3", "#229954", "#d68910", "#7d3c98", "#17a589", "#a04000", "#2e4053", "#b7950b", "#cb4335"};

}  // namespace

std::string svg_plot(const PlotSpec& spec, int width, int height)
{
    const double left = 70, right = 190, top = 34, bottom = 48;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    int count = 0;
    for (const auto& s : spec.series)
        for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
            const double e = k < s.err.size() && std::isfinite(s.err[k]) ? s.err[k] : 0.0;
            if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) continue;
            x0 = std::min(x0, s.x[k]);
            x1 = std::max(x1, s.x[k]);
            y0 = std::min(y0, s.y[k] - e);
            y1 = std::max(y1, s.y[k] + e);
            ++count;
        }
    std::ostringstream o;
    o << "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height << "\" viewBox=\"0 0 "
      << width << " " << height << "\" font-family=\"sans-serif\" font-size=\"12\">";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>";
    o << "<text x=\"" << width / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\" font-weight=\"bold\">" << html_escape(spec.title)
      << "</text>";
    if (count == 0) {
        o << "<text x=\"" << width / 2 << "\" y=\"" << height / 2 << "\" text-anchor=\"middle\" fill=\"#888\">no data</text></svg>";
        return o.str();
    }
    const std::vector<double> xt = ticks(x0, x1), yt = ticks(y0, y1);
    const double xa = xt.front(), xb = xt.back(), ya = yt.front(), yb = yt.back();
    const double pw = width - left - right, ph = height - top - bottom;
    const auto X = [&](double x) { return left + (xb > xa ? (x - xa) / (xb - xa) : 0.5) * pw; };
    const auto Y = [&](double y) { return top + ph - (yb > ya ? (y - ya) / (yb - ya) : 0.5) * ph; };
    o << "<g stroke=\"#ddd\">";
    for (double t : xt) o << "<line x1=\"" << fmt(X(t), 6) << "\" y1=\"" << top << "\" x2=\"" << fmt(X(t), 6) << "\" y2=\"" << top + ph << "\"/>";
    for (double t : yt) o << "<line x1=\"" << left << "\" y1=\"" << fmt(Y(t), 6) << "\" x2=\"" << left + pw << "\" y2=\"" << fmt(Y(t), 6) << "\"/>";
    o << "</g><rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph << "\" fill=\"none\" stroke=\"#333\"/>";
    for (double t : xt)
        o << "<text x=\"" << fmt(X(t), 6) << "\" y=\"" << top + ph + 16 << "\" text-anchor=\"middle\">" << fmt(t) << "</text>";
    for (double t : yt)
        o << "<text x=\"" << left - 6 << "\" y=\"" << fmt(Y(t) + 4, 6) << "\" text-anchor=\"end\">" << fmt(t) << "</text>";
    o << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 10 << "\" text-anchor=\"middle\">" << html_escape(spec.x_label) << "</text>";
    o << "<text transform=\"translate(16," << top + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << html_escape(spec.y_label)
      << "</text>";
    for (std::size_t s = 0; s < spec.series.size(); ++s) {
        const PlotSeries& ser = spec.series[s];
        const char* c = kColours[s % std::size(kColours)];
        std::vector<std::size_t> order;
        for (std::size_t k = 0; k < ser.x.size() && k < ser.y.size(); ++k)
            if (std::isfinite(ser.x[k]) && std::isfinite(ser.y[k])) order.push_back(k);
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ser.x[a] < ser.x[b]; });
        if (ser.lines && order.size() > 1) {
            o << "<polyline fill=\"none\" stroke=\"" << c << "\" stroke-width=\"1.5\" points=\"";
            for (std::size_t k : order) o << fmt(X(ser.x[k]), 6) << "," << fmt(Y(ser.y[k]), 6) << " ";
            o << "\"/>";
        }
        for (std::size_t k : order) {
            const double px = X(ser.x[k]), py = Y(ser.y[k]);
            if (k < ser.err.size() && std::isfinite(ser.err[k]) && ser.err[k] > 0) {
                const double a = Y(ser.y[k] - ser.err[k]), b = Y(ser.y[k] + ser.err[k]);
                o << "<path stroke=\"" << c << "\" d=\"M" << fmt(px, 6) << " " << fmt(a, 6) << "V" << fmt(b, 6) << "M" << fmt(px - 4, 6) << " "
                  << fmt(a, 6) << "h8M" << fmt(px - 4, 6) << " " << fmt(b, 6) << "h8\"/>";
            }
            o << "<circle cx=\"" << fmt(px, 6) << "\" cy=\"" << fmt(py, 6) << "\" r=\"3.5\" fill=\"" << c << "\"><title>"
              << html_escape(ser.name) << ": " << fmt(ser.x[k], 6) << ", " << fmt(ser.y[k], 6)
              << (k < ser.err.size() && ser.err[k] > 0 ? " +- " + fmt(ser.err[k], 3) : std::string()) << "</title></circle>";
        }
        // The legend, right of the plot.
        const double ly = top + 8 + 18.0 * static_cast<double>(s);
        o << "<rect x=\"" << left + pw + 12 << "\" y=\"" << ly - 8 << "\" width=\"12\" height=\"10\" fill=\"" << c << "\"/>";
        o << "<text x=\"" << left + pw + 30 << "\" y=\"" << ly + 1 << "\">" << html_escape(ser.name.substr(0, 22)) << "</text>";
    }
    o << "</svg>";
    return o.str();
}

std::string html_table(const HtmlTable& t, const std::string& id)
{
    std::ostringstream o;
    o << "<table class=\"sortable\" id=\"" << html_escape(id) << "\"><thead><tr>";
    for (std::size_t c = 0; c < t.header.size(); ++c)
        o << "<th data-numeric=\"" << (c < t.numeric.size() && t.numeric[c] ? 1 : 0) << "\" title=\"sort\">" << html_escape(t.header[c]) << "</th>";
    o << "</tr></thead><tbody>";
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
        o << "<tr" << (r < t.row_class.size() && !t.row_class[r].empty() ? " class=\"" + html_escape(t.row_class[r]) + "\"" : "") << ">";
        for (const auto& cell : t.rows[r]) o << "<td>" << html_escape(cell) << "</td>";
        o << "</tr>";
    }
    o << "</tbody></table>";
    return o.str();
}

std::size_t inlined_size(const ViewMesh& m) { return (m.xyz.size() * 4 + m.triangles.size() * 4) * 4 / 3 + 64; }

namespace {

/// A script's text made safe inside <script>...</script>.
std::string script_safe(std::string_view js)
{
    std::string s(js);
    for (std::size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 3) s.replace(at, 2, "<\\/");
    return s;
}

const char* const kStyle = R"(
body{font-family:sans-serif;margin:20px;color:#222;max-width:1400px}
h1{font-size:22px}h2{font-size:18px;margin-top:28px;border-bottom:1px solid #ccc}
table.sortable{border-collapse:collapse;font-size:12px}
table.sortable th,table.sortable td{border:1px solid #ccc;padding:3px 6px;text-align:right}
table.sortable th{background:#eee;cursor:pointer;position:sticky;top:0}
table.sortable th.asc:after{content:" \25B2"}table.sortable th.desc:after{content:" \25BC"}
table.sortable td:first-child{text-align:left}
tr.failed td{background:#fdd}tr.missing td{background:#eee;color:#888}
.plots{display:flex;flex-wrap:wrap;gap:12px}
.gallery{display:flex;flex-wrap:wrap;gap:10px}
.gallery figure{margin:0;border:1px solid #ddd;padding:4px;font-size:11px;max-width:260px}
.gallery img{width:250px;display:block}
#view3d{width:900px;height:560px;border:1px solid #ccc;background:#f4f4f4;display:block}
.note{color:#666;font-size:12px}
)";

const char* const kScript = R"(
(function(){
  function cellValue(td, numeric){
    var t = td.textContent.trim();
    if(!numeric) return t.toLowerCase();
    var v = parseFloat(t);
    return isNaN(v) ? Infinity : v;
  }
  document.querySelectorAll('table.sortable').forEach(function(table){
    table.querySelectorAll('th').forEach(function(th, i){
      th.addEventListener('click', function(){
        var numeric = th.dataset.numeric === '1';
        var dir = th.classList.contains('asc') ? -1 : 1;
        table.querySelectorAll('th').forEach(function(h){ h.classList.remove('asc'); h.classList.remove('desc'); });
        th.classList.add(dir > 0 ? 'asc' : 'desc');
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        rows.sort(function(a, b){
          var x = cellValue(a.cells[i], numeric), y = cellValue(b.cells[i], numeric);
          return x < y ? -dir : x > y ? dir : 0;
        });
        rows.forEach(function(r){ body.appendChild(r); });
      });
    });
  });
  var view = 'none';
  var data = document.getElementById('woven-meshes');
  var meshes = data ? JSON.parse(data.textContent) : [];
  function decode(s, T){
    var bin = atob(s), buf = new Uint8Array(bin.length);
    for(var i = 0; i < bin.length; ++i) buf[i] = bin.charCodeAt(i);
    return new T(buf.buffer);
  }
  var note = document.getElementById('view3d-note');
  if(meshes.length){
    try {
      if(!window.THREE) throw new Error('three.js was not found when the page was made (Debian package libjs-three)');
      var canvas = document.getElementById('view3d');
      var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
      renderer.setPixelRatio(window.devicePixelRatio || 1);
      renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
      var scene = new THREE.Scene();
      scene.background = new THREE.Color(0xf4f4f4);
      scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 0.7));
      var sun = new THREE.DirectionalLight(0xffffff, 0.6);
      sun.position.set(1, -1.5, 2);
      scene.add(sun);
      var camera = new THREE.PerspectiveCamera(35, canvas.clientWidth / canvas.clientHeight, 0.001, 100);
      camera.up.set(0, 0, 1);
      var controls = new THREE.OrbitControls(camera, canvas);
      var current = null;
      var render = function(){ renderer.render(scene, camera); };
      controls.addEventListener('change', render);
      var show = function(k){
        var m = meshes[k];
        if(current){ scene.remove(current); current.geometry.dispose(); }
        var g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(decode(m.xyz, Float32Array), 3));
        g.setIndex(new THREE.BufferAttribute(decode(m.tri, Uint32Array), 1));
        g.computeVertexNormals();
        g.computeBoundingSphere();
        var mat = new THREE.MeshStandardMaterial({color: new THREE.Color(m.colour[0], m.colour[1], m.colour[2]), side: THREE.DoubleSide, roughness: 0.9});
        current = new THREE.Mesh(g, mat);
        scene.add(current);
        var s = g.boundingSphere;
        controls.target.copy(s.center);
        camera.position.set(s.center.x + 1.6 * s.radius, s.center.y - 2.2 * s.radius, s.center.z + 1.6 * s.radius);
        camera.near = s.radius / 100; camera.far = s.radius * 100; camera.updateProjectionMatrix();
        controls.update();
        render();
      };
      var pick = document.getElementById('view3d-pick');
      pick.addEventListener('change', function(){ show(+pick.value); });
      show(0);
      view = 'webgl';
    } catch(e) {
      view = 'failed';
      if(note) note.textContent = '3-D view not available: ' + e.message;
    }
  }
  document.body.dataset.view = view;
  document.body.dataset.ready = '1';
})();
)";

}  // namespace

std::string html_page(const std::string& title, const std::string& body, const std::vector<ViewMesh>& meshes, std::string_view three_js,
                      std::string_view orbit_controls_js)
{
    std::ostringstream o;
    o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << html_escape(title) << "</title><style>" << kStyle
      << "</style></head><body data-ready=\"0\">\n";
    o << body;
    if (!meshes.empty()) {
        o << "<h2>3-D view</h2><p><select id=\"view3d-pick\">";
        for (std::size_t k = 0; k < meshes.size(); ++k) o << "<option value=\"" << k << "\">" << html_escape(meshes[k].name) << "</option>";
        o << "</select> <span class=\"note\" id=\"view3d-note\">drag to turn, wheel to zoom, right-drag to pan; z up</span></p>"
             "<canvas id=\"view3d\"></canvas>\n<script type=\"application/json\" id=\"woven-meshes\">[";
        for (std::size_t k = 0; k < meshes.size(); ++k) {
            const ViewMesh& m = meshes[k];
            std::string xyz(reinterpret_cast<const char*>(m.xyz.data()), m.xyz.size() * sizeof(float));
            std::string tri(reinterpret_cast<const char*>(m.triangles.data()), m.triangles.size() * sizeof(std::uint32_t));
            o << (k ? "," : "") << "{\"colour\":[" << m.colour[0] << "," << m.colour[1] << "," << m.colour[2] << "],\"xyz\":\"" << base64(xyz)
              << "\",\"tri\":\"" << base64(tri) << "\"}";
        }
        o << "]</script>\n";
        if (!three_js.empty()) {
            o << "<script>" << script_safe(three_js) << "\n</script>\n";
            o << "<script>" << script_safe(orbit_controls_js) << "\n</script>\n";
        }
    }
    o << "<script>" << kScript << "</script>\n</body></html>\n";
    return o.str();
}

}  // namespace woven::render
