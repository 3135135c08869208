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

/// A number for JSON: shortest round trip, non-finite as null.
std::string json_number(double v)
{
    if (!std::isfinite(v)) return "null";
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

std::string json_string(std::string_view s)
{
    std::string o = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            o += b;
        } else if (c == '<') {
            o += "\\u003c";  // never "</script>" inside the element
        } else {
            o += c;
        }
    }
    return o + "\"";
}

std::string json_array(const std::vector<double>& v, std::size_t n)
{
    std::string o = "[";
    for (std::size_t k = 0; k < n && k < v.size(); ++k) {
        if (k) o += ',';
        o += json_number(v[k]);
    }
    return o + "]";
}

}  // namespace

std::string html_plot(const Plot& plot, const std::string& id, int width, int height)
{
    const PlotFrame f = plot_frame(plot, width, height);
    std::ostringstream o;
    o << "<figure class=\"plot\" id=\"" << html_escape(id) << "\">" << plot_svg(plot, width, height, id) << "</figure>";
    o << "<script type=\"application/json\" class=\"plot-data\" data-for=\"" << html_escape(id) << "\">{\"id\":" << json_string(id)
      << ",\"title\":" << json_string(plot.title) << ",\"x_label\":" << json_string(plot.x_label) << ",\"y_label\":" << json_string(plot.y_label)
      << ",\"frame\":{\"x_lo\":" << json_number(f.x_lo) << ",\"x_hi\":" << json_number(f.x_hi) << ",\"y_lo\":" << json_number(f.y_lo)
      << ",\"y_hi\":" << json_number(f.y_hi) << ",\"left\":" << json_number(f.left) << ",\"top\":" << json_number(f.top)
      << ",\"right\":" << json_number(f.right) << ",\"bottom\":" << json_number(f.bottom) << ",\"legend\":[" << json_number(f.legend_x) << ","
      << json_number(f.legend_y) << "," << json_number(f.legend_w) << "," << json_number(f.legend_h) << "],\"legend_whole\":" << (f.legend_whole ? "true" : "false") << ",\"width\":" << width
      << ",\"height\":" << height << "},\"series\":[";
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
        const Series& s = plot.series[k];
        const std::size_t n = std::min(s.x.size(), s.y.size());
        const Vec3& c = f.colors[k];
        o << (k ? "," : "") << "{\"label\":" << json_string(s.label) << ",\"color\":[" << std::lround(255 * c[0]) << "," << std::lround(255 * c[1])
          << "," << std::lround(255 * c[2]) << "],\"style\":\""
          << (s.style == Series::Style::LINE ? "line" : s.style == Series::Style::POINTS ? "points" : "line_and_points") << "\",\"x\":"
          << json_array(s.x, n) << ",\"y\":" << json_array(s.y, n) << ",\"err\":" << json_array(s.err, s.err.empty() ? 0 : n) << "}";
    }
    o << "]}</script>";
    return o.str();
}

std::string html_table(const HtmlTable& t, const std::string& id)
{
    std::ostringstream o;
    o << "<div class=\"table-box\"><table class=\"sortable\" id=\"" << html_escape(id) << "\"><thead><tr>";
    for (std::size_t c = 0; c < t.header.size(); ++c)
        o << "<th data-numeric=\"" << (c < t.numeric.size() && t.numeric[c] ? 1 : 0) << "\" title=\"sort\">" << html_escape(t.header[c]) << "</th>";
    o << "</tr></thead><tbody>";
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
        o << "<tr" << (r < t.row_class.size() && !t.row_class[r].empty() ? " class=\"" + html_escape(t.row_class[r]) + "\"" : "") << ">";
        for (const auto& cell : t.rows[r]) o << "<td>" << html_escape(cell) << "</td>";
        o << "</tr>";
    }
    o << "</tbody></table></div>";
    return o.str();
}

std::size_t inlined_size(const ViewModel& m) { return m.glb.size() * 4 / 3 + 256; }

namespace {

/// A script's text made safe inside <script>...</script>.
std::string script_safe(std::string_view js)
{
    std::string s(js);
    for (std::size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 3) s.replace(at, 2, "<\\/");
    return s;
}

const char* const kStyle = R"(
body{font-family:sans-serif;margin:20px;color:#222;max-width:1400px;overflow-wrap:break-word}
@media (max-width:600px){body{margin:10px}}
h1{font-size:22px}h2{font-size:18px;margin-top:28px;border-bottom:1px solid #ccc}
h1,figcaption,.note{overflow-wrap:anywhere}
img,figure{max-width:100%}
select{max-width:100%}
.table-box{max-width:100%;max-height:80vh;overflow:auto;margin:4px 0}
table.sortable{border-collapse:collapse;font-size:12px;overflow-wrap:normal}
table.sortable th,table.sortable td{border:1px solid #ccc;padding:3px 6px;text-align:right}
table.sortable th{background:#eee;cursor:pointer;position:sticky;top:0}
table.sortable th.asc:after{content:" \25B2"}table.sortable th.desc:after{content:" \25BC"}
table.sortable td:first-child{text-align:left}
tr.failed td{background:#fdd}tr.missing td{background:#eee;color:#888}
.plots{display:flex;flex-wrap:wrap;gap:12px}
figure.plot{margin:0;min-width:0}figure.plot svg{display:block;max-width:100%;height:auto}
.gallery{display:flex;flex-wrap:wrap;gap:10px}
.gallery figure{margin:0;border:1px solid #ddd;padding:4px;font-size:11px;max-width:260px;min-width:0;box-sizing:border-box}
.gallery img{width:250px;max-width:100%;height:auto;display:block}
#view3d-box{position:relative;width:902px;max-width:100%}
body.view-only{margin:0}body.view-only>:not(#view3d-box){display:none}
#view3d{width:100%;height:auto;aspect-ratio:902/562;box-sizing:border-box;border:1px solid #ccc;background:#f4f4f4;display:block}
#view3d-legend{position:absolute;right:14px;top:12px;max-width:calc(100% - 46px);background:rgba(255,255,255,0.9);border:1px solid #bbb;padding:6px 8px;font-size:12px;display:none}
#view3d-legend canvas{display:block;width:200px;max-width:100%;height:14px;margin:4px 0}
#view3d-legend .ends{display:flex;justify-content:space-between;gap:16px}
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
  var data = document.getElementById('woven-models');
  var models = data ? JSON.parse(data.textContent) : [];
  var params = new URLSearchParams(location.hash.slice(1));
  function bytes(s){
    var bin = atob(s), buf = new Uint8Array(bin.length);
    for(var i = 0; i < bin.length; ++i) buf[i] = bin.charCodeAt(i);
    return buf.buffer;
  }
  // viridis at 9 stops (matplotlib's), linear between them.
  var VIRIDIS = [[68,1,84],[71,45,123],[59,82,139],[44,114,142],[33,145,140],[40,174,128],[94,201,98],[170,220,50],[253,231,37]];
  function viridis(t){
    t = Math.min(1, Math.max(0, t)) * (VIRIDIS.length - 1);
    var i = Math.min(VIRIDIS.length - 2, Math.floor(t)), f = t - i, a = VIRIDIS[i], b = VIRIDIS[i + 1];
    return [(a[0] + f * (b[0] - a[0])) / 255, (a[1] + f * (b[1] - a[1])) / 255, (a[2] + f * (b[2] - a[2])) / 255];
  }
  function fmt(v){ return Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(3) : +v.toPrecision(4) + ''; }
  var note = document.getElementById('view3d-note');
  var pending = 0;
  function finish(){ document.body.dataset.view = view; document.body.dataset.ready = '1'; }
  if(models.length){
    try {
      if(!window.THREE) throw new Error('three.js was not found when the page was made (Debian package libjs-three)');
      if(!THREE.GLTFLoader) throw new Error("three.js's GLTFLoader was not found when the page was made");
      var canvas = document.getElementById('view3d');
      var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
      renderer.setPixelRatio(window.devicePixelRatio || 1);
      renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
      var scene = new THREE.Scene();
      scene.background = new THREE.Color(0xf4f4f4);
      scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 1.0));
      var sun = new THREE.DirectionalLight(0xffffff, 0.7);
      sun.position.set(1, -1.5, 2);
      scene.add(sun);
      var camera = new THREE.PerspectiveCamera(35, canvas.clientWidth / canvas.clientHeight, 0.001, 100);
      camera.up.set(0, 0, 1);
      var controls = new THREE.OrbitControls(camera, canvas);
      var render = function(){ renderer.render(scene, camera); };
      controls.addEventListener('change', render);
      // The canvas takes its box's width (at most 900 px, 900:560 by the style): its drawing
      // buffer and the camera follow it when the window (or the box) changes size.
      var resize = function(){
        var w = canvas.clientWidth, h = canvas.clientHeight;
        if(!w || !h || (w === canvas.width / renderer.getPixelRatio() && h === canvas.height / renderer.getPixelRatio())) return;
        renderer.setSize(w, h, false);
        camera.aspect = w / h;
        camera.updateProjectionMatrix();
        render();
      };
      window.addEventListener('resize', resize);
      if(window.ResizeObserver) new ResizeObserver(resize).observe(canvas);
      var current = null, cloth = null, fields = {};
      var pickField = document.getElementById('view3d-field'), legend = document.getElementById('view3d-legend');
      var hidden = (params.get('hide') || '').split(',').filter(function(h){ return h; });
      var obstacleColour = new THREE.Color(params.has('obstacles') ? '#' + params.get('obstacles') : '#8a96a8');
      var colourBy = function(name){
        if(!cloth) return;
        var g = cloth.geometry, f = fields[name];
        if(!f){
          cloth.material.vertexColors = THREE.NoColors;
          cloth.material.color.copy(cloth.userData.colour);
          legend.style.display = 'none';
        } else {
          var lo = Infinity, hi = -Infinity, v = f.values;
          for(var i = 0; i < v.length; ++i){ lo = Math.min(lo, v[i]); hi = Math.max(hi, v[i]); }
          var c = new Float32Array(v.length * 3), lin = new THREE.Color();
          for(var i = 0; i < v.length; ++i){
            var rgb = viridis(hi > lo ? (v[i] - lo) / (hi - lo) : 0.5);
            lin.setRGB(rgb[0], rgb[1], rgb[2]);
            c[3 * i] = lin.r; c[3 * i + 1] = lin.g; c[3 * i + 2] = lin.b;
          }
          g.setAttribute('color', new THREE.BufferAttribute(c, 3));
          cloth.material.vertexColors = THREE.VertexColors;
          cloth.material.color.setRGB(1, 1, 1);
          legend.style.display = 'block';
          legend.querySelector('.name').textContent = name + (f.unit ? ', ' + f.unit : '');
          legend.querySelector('.lo').textContent = fmt(lo);
          legend.querySelector('.hi').textContent = fmt(hi);
          legend.dataset.field = name; legend.dataset.unit = f.unit; legend.dataset.min = lo; legend.dataset.max = hi;
          var bar = legend.querySelector('canvas'), ctx = bar.getContext('2d');
          for(var x = 0; x < bar.width; ++x){
            var rgb = viridis(x / (bar.width - 1));
            ctx.fillStyle = 'rgb(' + Math.round(255 * rgb[0]) + ',' + Math.round(255 * rgb[1]) + ',' + Math.round(255 * rgb[2]) + ')';
            ctx.fillRect(x, 0, 1, bar.height);
          }
        }
        cloth.material.needsUpdate = true;
        render();
      };
      var show = function(k, done){
        var m = models[k];
        if(current){ scene.remove(current); current = null; cloth = null; }
        new THREE.GLTFLoader().parse(bytes(m.glb), '', function(gltf){
          var root = new THREE.Group();
          root.add(gltf.scene);
          gltf.scene.rotation.x = Math.PI / 2;  // glTF y-up back to woven's z-up
          var units = (gltf.asset && gltf.asset.extras && gltf.asset.extras.units) || {};
          fields = {};
          gltf.scene.traverse(function(o){
            if(!o.isMesh) return;
            if(!o.geometry.attributes.normal) o.geometry.computeVertexNormals();
            if(o.name === 'cloth' || (o.parent && o.parent.name === 'cloth')){
              cloth = o;
              o.material = new THREE.MeshStandardMaterial({color: new THREE.Color(m.colour[0], m.colour[1], m.colour[2]), side: THREE.DoubleSide, roughness: 0.9});
              o.userData.colour = o.material.color.clone();
              var a = o.geometry.attributes;
              Object.keys(a).forEach(function(key){
                if(key.charAt(0) !== '_') return;
                fields[key.slice(1)] = {values: a[key].array, unit: units[key.toUpperCase()] || ''};
              });
              var pos = a.position, h = new Float32Array(pos.count);
              for(var i = 0; i < pos.count; ++i) h[i] = pos.getY(i);  // glTF y: woven's z
              fields.height = {values: h, unit: 'm'};
            } else {
              o.material = new THREE.MeshStandardMaterial({color: obstacleColour, side: THREE.DoubleSide, roughness: 0.7, flatShading: true});
              if(hidden.some(function(h){ return h === 'obstacles' || o.name.indexOf(h) >= 0; })) o.visible = false;
            }
          });
          root.updateMatrixWorld(true);
          var bounds = [];
          gltf.scene.traverse(function(o){
            if(!o.isMesh || o === cloth) return;
            var b = new THREE.Box3().setFromObject(o);
            bounds.push({name: o.name, box: [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z]});
          });
          if(cloth && hidden.indexOf('cloth') >= 0) cloth.visible = false;
          scene.add(root);
          current = root;
          document.body.dataset.bounds = JSON.stringify(bounds);
          var names = Object.keys(fields);
          pickField.innerHTML = '';
          ['none'].concat(names).forEach(function(n){
            var opt = document.createElement('option');
            opt.value = n; opt.textContent = n === 'none' ? 'fabric colour' : n + (fields[n].unit ? ' (' + fields[n].unit + ')' : '');
            pickField.appendChild(opt);
          });
          var want = params.get('field') || 'none';
          pickField.value = fields[want] ? want : 'none';
          colourBy(pickField.value);
          // Framed on the cloth (a floor plane may reach far beyond it).
          var s = new THREE.Box3().setFromObject(cloth || root).getBoundingSphere(new THREE.Sphere());
          s.radius *= 1.15;
          if(params.has('camera') && params.has('target')){
            var c = params.get('camera').split(',').map(Number), t = params.get('target').split(',').map(Number);
            camera.position.set(c[0], c[1], c[2]);
            controls.target.set(t[0], t[1], t[2]);
            camera.near = 0.001; camera.far = 10 * s.radius + 10;
          } else {
            controls.target.copy(s.center);
            camera.position.set(s.center.x + 1.6 * s.radius, s.center.y - 2.2 * s.radius, s.center.z + 1.6 * s.radius);
            camera.near = s.radius / 100; camera.far = s.radius * 100;
          }
          camera.updateProjectionMatrix();
          controls.update();
          render();
          if(done) done();
        }, function(e){
          view = 'failed';
          if(note) note.textContent = '3-D view not available: the glb did not load (' + (e && e.message ? e.message : e) + ')';
          if(done) done();
        });
      };
      var pick = document.getElementById('view3d-pick');
      pick.addEventListener('change', function(){ show(+pick.value); });
      pickField.addEventListener('change', function(){ colourBy(pickField.value); });
      view = 'webgl';
      var first = Math.min(models.length - 1, Math.max(0, +(params.get('model') || 0)));
      pick.value = first;
      if(Array.from(params.keys()).length) document.body.classList.add('view-only');
      pending = 1;
      show(first, finish);
    } catch(e) {
      view = 'failed';
      if(note) note.textContent = '3-D view not available: ' + e.message;
    }
  }
  if(!pending) finish();
})();
)";

}  // namespace

std::string html_page(const std::string& title, const std::string& body, const std::vector<ViewModel>& models, const ViewScripts& scripts)
{
    std::ostringstream o;
    o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>" << html_escape(title) << "</title><style>" << kStyle
      << "</style></head><body data-ready=\"0\">\n";
    o << body;
    if (!models.empty()) {
        o << "<h2 id=\"view3d-head\">3-D view</h2><p><select id=\"view3d-pick\">";
        for (std::size_t k = 0; k < models.size(); ++k) o << "<option value=\"" << k << "\">" << html_escape(models[k].name) << "</option>";
        o << "</select> colour by <select id=\"view3d-field\"></select> <span class=\"note\" id=\"view3d-note\">drag to turn, wheel to "
             "zoom, right-drag to pan; z up; the cloth as displayed (lifted off the obstacles by the contact distance)</span></p>"
             "<div id=\"view3d-box\"><canvas id=\"view3d\"></canvas><div id=\"view3d-legend\"><div class=\"name\"></div>"
             "<canvas width=\"200\" height=\"14\"></canvas><div class=\"ends\"><span class=\"lo\"></span><span class=\"hi\"></span></div></div></div>\n"
             "<script type=\"application/json\" id=\"woven-models\">[";
        for (std::size_t k = 0; k < models.size(); ++k) {
            const ViewModel& m = models[k];
            o << (k ? "," : "") << "{\"colour\":[" << m.colour[0] << "," << m.colour[1] << "," << m.colour[2] << "],\"glb\":\"" << base64(m.glb) << "\"}";
        }
        o << "]</script>\n";
        for (const std::string* js : {&scripts.three, &scripts.orbit_controls, &scripts.gltf_loader})
            if (!js->empty()) o << "<script>" << script_safe(*js) << "\n</script>\n";
    }
    o << "<script>" << kScript << "</script>\n</body></html>\n";
    return o.str();
}

}  // namespace woven::render
