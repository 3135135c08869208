#!/usr/bin/env python3
"""`woven report` pages opened in headless Chromium, one kind of folder per run:

  test_report_pages.py KIND WOVEN     KIND: drape, cusick, kes-test, fit, experiment, garment

Each run makes a small folder of that kind, writes its report.html, has Chromium build it
(--dump-dom after the page's script: data-ready="1") and checks the page against the folder:
every plot's embedded data (<script class="plot-data">) against the folder's JSON or CSV
numbers, and every plotted vertex of the SVG mapped back through the plot's axis frame to
those data (dots within 1e-4 of the axis range, lines within 0.05 px: cairo's coordinates
are 1/256 px). The drape
page's 3-D view is also checked in screenshots: where the cube's top edge meets the cloth no
cube-coloured pixel shows through the cloth, and the field legend is drawn. Each page is also
opened 360, 700 and 1280 px wide: it fits (no horizontal scrollbar), its plots and 3-D view scaled.
"""
import html
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

FAILURES = []
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILURES.append(what)


def run(cmd, check_rc=0):
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=dict(os.environ, OPENBLAS_CORETYPE="Prescott"))
    if check_rc is not None and p.returncode != check_rc:
        raise SystemExit(f"{' '.join(cmd)}: exit {p.returncode}, expected {check_rc}\n{p.stderr[-2000:]}")
    return p


def chromium(args):
    cmd = ["chromium", "--headless", "--disable-gpu", "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--hide-scrollbars", "--disable-dev-shm-usage", "--virtual-time-budget=10000"] + (["--no-sandbox"] if os.geteuid() == 0 else []) + args
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


def dump(page, fragment=""):
    dom = chromium(["--dump-dom", "file://" + page + fragment])
    body = re.search(r"<body[^>]*>", dom.stdout)
    check(body is not None and 'data-ready="1"' in body.group(0), f"Chromium built the page ({body.group(0)[:200] if body else dom.stderr[-300:]})")
    return dom.stdout, (body.group(0) if body else "")


def png_pixels(path):
    """(width, height, rows of RGB bytes, 3) of a PNG, decoded by Pillow (Debian python3-pil)."""
    from PIL import Image
    with Image.open(path) as im:
        rgb = im.convert("RGB")
        w, h = rgb.size
        data = rgb.tobytes()
    return w, h, [data[y * 3 * w:(y + 1) * 3 * w] for y in range(h)], 3


# --- plots -------------------------------------------------------------------------------------

def plots_of(dom):
    """{id: (data, svg)} of every plot on the page."""
    out = {}
    for m in re.finditer(r'<script type="application/json" class="plot-data" data-for="([^"]+)">(.*?)</script>', dom, re.S):
        data = json.loads(m.group(2))
        fig = re.search(r'<figure class="plot" id="' + re.escape(m.group(1)) + r'">(.*?)</figure>', dom, re.S)
        out[m.group(1)] = (data, fig.group(1) if fig else "")
    return out


def svg_paths(svg):
    """(rgb 0..255, stroked, [subpath: [(x, y), ...]]) of each <path> drawn in a colour."""
    paths = []
    for tag in re.findall(r"<path\b[^>]*>", svg):
        style = re.search(r'style="([^"]*)"', tag)
        d = re.search(r' d="([^"]*)"', tag)
        if not style or not d:
            continue
        c = re.search(r"(stroke|fill):rgb\(([\d.]+)%,([\d.]+)%,([\d.]+)%\)", style.group(1))
        if not c:
            continue
        rgb = tuple(round(float(v) * 2.55) for v in c.groups()[1:])
        subs, cur = [], None
        for cmd, nums in re.findall(r"([MLCZ])([^MLCZ]*)", d.group(1)):
            v = [float(x) for x in nums.split()]
            if cmd == "M":
                cur = []
                subs.append(cur)
            if cur is not None:
                cur.extend(zip(v[0::2], v[1::2]))
        paths.append((rgb, c.group(1) == "stroke", subs))
    return paths


def to_data(frame, px, py):
    x = frame["x_lo"] + (px - frame["left"]) / (frame["right"] - frame["left"]) * (frame["x_hi"] - frame["x_lo"])
    y = frame["y_lo"] + (frame["bottom"] - py) / (frame["bottom"] - frame["top"]) * (frame["y_hi"] - frame["y_lo"])
    return x, y


def to_pixel(frame, x, y):
    return (frame["left"] + (x - frame["x_lo"]) / (frame["x_hi"] - frame["x_lo"]) * (frame["right"] - frame["left"]),
            frame["bottom"] - (y - frame["y_lo"]) / (frame["y_hi"] - frame["y_lo"]) * (frame["bottom"] - frame["top"]))


def seg_dist(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = 0 if dx == dy == 0 else max(0, min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def check_plot(pid, data, svg, tol=1e-4, tol_px=0.05):
    """The SVG's vertices, mapped back through the frame, are the embedded data: dots within
    `tol` of the axes' ranges, lines within `tol_px` pixels (cairo writes 1/256 px)."""
    f = data["frame"]
    W, H = f["width"], f["height"]
    lx, ly, lw, lh = f["legend"]
    labelled = [s for s in data["series"] if s["label"]]
    check(lw > 0 if labelled else lw == 0, f"{pid}: a legend exactly when a series is labelled")
    if lw > 0:
        inside = f["left"] <= lx and lx + lw <= f["right"]
        check((inside or lx >= f["right"]) and f["top"] <= ly and ly + lh <= f["bottom"] and 0 <= lx and lx + lw <= W and ly + lh <= H,
              f"{pid}: the legend box {lx:.0f},{ly:.0f} {lw:.0f}x{lh:.0f} lies inside the axes or right of them, inside the {W}x{H} image")
    check(f["legend_whole"], f"{pid}: the legend's text is whole (not clipped)")
    labels = [s["label"] for s in labelled]
    check(len(labels) == len(set(labels)), f"{pid}: each legend label once: {labels}")
    # The text is SVG text (searchable, read by screen readers), not glyph outlines.
    texts = [html.unescape(t) for t in re.findall(r"<text\b[^>]*>([^<]*)</text>", svg)]
    want = [t for t in [data["title"], data["x_label"], data["y_label"]] + labels if t]
    check(all(t in texts for t in want) and "<symbol" not in svg, f"{pid}: its title, axis labels and legend are <text>: missing "
          f"{[t for t in want if t not in texts]}, glyph outlines: {'<symbol' in svg}")
    paths = svg_paths(svg)
    sx, sy = tol * (f["x_hi"] - f["x_lo"]), tol * (f["y_hi"] - f["y_lo"])
    for s in data["series"]:
        pts = [(x, y) for x, y in zip(s["x"], s["y"]) if x is not None and y is not None]
        inside = [(x, y) for x, y in pts if f["x_lo"] <= x <= f["x_hi"] and f["y_lo"] <= y <= f["y_hi"]]
        if not inside:
            continue
        rgb = tuple(s["color"])
        near = lambda c: all(abs(a - b) <= 1 for a, b in zip(c, rgb))
        if s["style"] != "points":
            # cairo keeps a polyline's vertices but merges the middle points of collinear runs:
            # each vertex is a data point (in order) and each data point lies on the polyline.
            want = [to_pixel(f, *p) for p in inside]
            ok = False
            for _, _, subs in [p for p in paths if p[1] and near(p[0])]:
                verts = [v for sub in subs for v in sub]
                # Where a line leaves the axes cairo's clip ends it on the frame (2 px out): those
                # ends are not data points.
                verts = [v for v in verts if f["left"] <= v[0] <= f["right"] and f["top"] <= v[1] <= f["bottom"]]
                k, matched = 0, 0
                for v in verts:
                    while k < len(want) and math.dist(v, want[k]) > tol_px:
                        k += 1
                    matched += k < len(want)
                on = all(any(seg_dist(w, sub[i], sub[i + 1]) <= tol_px for sub in subs for i in range(len(sub) - 1)) or
                         any(math.dist(w, v) <= tol_px for v in verts) for w in want)
                ok = ok or (matched == len(verts) and len(verts) >= 2 and on)
            check(ok, f"{pid}: '{s['label']}': the line's vertices are data points and its {len(inside)} data points lie on it (within {tol_px} px)")
        if s["style"] != "line":
            centres = []
            for _, stroked, subs in paths:
                pass
            dots = [p for p in paths if not p[1] and near(p[0])]
            for _, _, subs in dots:
                for sub in subs:
                    if sub:
                        xs, ys = [v[0] for v in sub], [v[1] for v in sub]
                        centres.append(to_data(f, (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2))
            missing = [p for p in inside if not any(abs(c[0] - p[0]) <= sx and abs(c[1] - p[1]) <= sy for c in centres)]
            check(not missing and len(centres) >= len(inside), f"{pid}: '{s['label']}': a dot at each of its {len(inside)} data points ({len(centres)} dots; missing {missing[:3]})")


def same(a, b, rel=1e-9):
    return a is not None and b is not None and abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


def check_series(pid, series, x, y, what, rel=1e-9):
    n = min(len(x), len(y))
    ok = len(series["x"]) == n and all(same(series["x"][k], x[k], rel) and same(series["y"][k], y[k], rel) for k in range(n))
    check(ok, f"{pid}: '{series['label']}' holds {what} ({n} points, within {rel:g} relative)")


def read_csv(path):
    lines = open(path).read().split("\n")
    head = lines[0].split(",")
    cols = {h: [] for h in head}
    for line in lines[1:]:
        if not line:
            continue
        v = line.split(",")
        for h, x in zip(head, v):
            try:
                cols[h].append(float(x))
            except ValueError:
                cols[h].append(x)
    return cols


def table_rows(dom, table_id):
    t = re.search(r'<table class="sortable" id="' + table_id + r'">.*?<tbody>(.*?)</tbody>', dom, re.S)
    return [re.findall(r"<td>([^<]*)</td>", r) for r in re.findall(r"<tr[^>]*>(.*?)</tr>", t.group(1), re.S)] if t else []


def points_cell(dom, column):
    """The points table's cell of `column` in its first row ("" if none)."""
    head = re.search(r'<table class="sortable" id="points"><thead><tr>(.*?)</tr>', dom, re.S)
    cols = re.findall(r"<th[^>]*>([^<]*)</th>", head.group(1)) if head else []
    rows = table_rows(dom, "points")
    return rows[0][cols.index(column)] if rows and column in cols else ""


def check_wall(dom, want, what):
    """The page's wall_time_s (its points table) is `want` (> 0 s), to its 6 digits."""
    cell = points_cell(dom, "wall_time_s")
    check(cell != "" and want > 0 and same(float(cell), want, 1e-5), f"the table's wall_time_s {cell!r} is {what} ({want:.6g} s)")


def check_tables_fit(page, width=700):
    """Opened in a `width` px window, every table lies inside the page: a table wider than the
    page scrolls inside its box instead of running off it (at least one does here)."""
    measure = page[:-len(".html")] + "-measure.html"
    script = """<script>(function(){
      var page = document.body.getBoundingClientRect(), out = [];
      document.querySelectorAll('table.sortable').forEach(function(t){
        var box = t.parentElement, r = box.getBoundingClientRect();
        out.push({id: t.id, box: box.className, right: r.right, page_right: page.right, table_w: t.scrollWidth,
                  box_w: box.clientWidth, scroll_w: box.scrollWidth, overflow: getComputedStyle(box).overflowX});
      });
      document.body.dataset.tables = JSON.stringify(out);
    })();</script>"""
    with open(page) as f, open(measure, "w") as g:
        g.write(f.read().replace("</body>", script + "</body>"))
    dom = chromium([f"--window-size={width},600", "--dump-dom", "file://" + measure])
    m = re.search(r'data-tables="([^"]*)"', dom.stdout)
    tables = json.loads(html.unescape(m.group(1))) if m else []
    check(tables != [], f"the page's tables were measured at {width} px ({len(tables)})")
    outside = [t["id"] for t in tables if t["right"] > t["page_right"] + 0.5]
    check(outside == [], f"every table's box ends inside the page at {width} px: {outside} run off")
    wide = [t for t in tables if t["table_w"] > t["box_w"]]
    check(wide != [] and all(t["box"] == "table-box" and t["overflow"] in ("auto", "scroll") and t["scroll_w"] > t["box_w"] for t in wide),
          f"the tables wider than the page scroll inside their box: {[(t['id'], t['table_w'], t['box_w'], t['overflow']) for t in wide]}")


FIT_WIDTHS = (360, 700, 1280)


def check_page_fits(page, view3d, plots=True, widths=FIT_WIDTHS):
    """Opened in windows `widths` px wide (phone to desktop), nothing runs off the page: no
    horizontal scrollbar (the document no wider than the window), every plot's SVG and every
    canvas inside the window, the plots (`plots`: the page has some) scaled whole (their aspect ratio, their text drawn) and,
    with a 3-D view (`view3d`), its canvas not empty, its drawing buffer the size it is shown at,
    900:560, and re-sized with its box when the window is. Headless Chromium's windows are at
    least 500 px wide, so each width is a frame that wide in one window: one run for all."""
    measure = page[:-len(".html")] + "-fit.html"
    script = """<script>(function(){
      function rect(e){ var r = e.getBoundingClientRect(); return {left: r.left, right: r.right, w: r.width, h: r.height}; }
      function measure(){
        var W = window.innerWidth, out = {inner: W, scroll: document.documentElement.scrollWidth, svgs: [], canvases: [], off: []};
        document.querySelectorAll('svg').forEach(function(s){
          if(s.parentElement.closest('svg')) return;
          var v = s.viewBox && s.viewBox.baseVal, texts = [];
          s.querySelectorAll('text').forEach(function(t){ texts.push([t.textContent, rect(t)]); });
          var fig = s.closest('figure');
          out.svgs.push({id: fig ? fig.id : '', box: rect(s), vw: v ? v.width : 0, vh: v ? v.height : 0, texts: texts});
        });
        document.querySelectorAll('canvas').forEach(function(c){
          out.canvases.push({id: c.id, box: rect(c), cw: c.clientWidth, ch: c.clientHeight, bw: c.width, bh: c.height});
        });
        document.querySelectorAll('body *').forEach(function(e){
          var r = e.getBoundingClientRect();
          if(r.right > W + 0.5 && !e.closest('.table-box') && !e.closest('svg') && out.off.length < 6)
            out.off.push(e.tagName.toLowerCase() + (e.id ? '#' + e.id : typeof e.className === 'string' && e.className ? '.' + e.className.split(' ')[0] : '') + ' ' + Math.round(r.right));
        });
        return out;
      }
      function done(){
        var m = measure(), box = document.getElementById('view3d-box'), c = document.getElementById('view3d');
        if(box && c){
          box.style.width = '300px';
          window.dispatchEvent(new Event('resize'));
          m.resized = {cw: c.clientWidth, ch: c.clientHeight, bw: c.width, bh: c.height, dpr: window.devicePixelRatio || 1};
        }
        parent.postMessage(JSON.stringify(m), '*');
      }
      (function wait(){ document.body.dataset.ready === '1' ? done() : setTimeout(wait, 50); })();
    })();</script>"""
    with open(page) as f, open(measure, "w") as g:
        g.write(f.read().replace("</body>", script + "</body>"))
    frames = page[:-len(".html")] + "-frames.html"
    with open(frames, "w") as g:
        g.write('<!DOCTYPE html><html><body style="margin:0;display:flex;align-items:flex-start">' +
                "".join(f'<iframe src="{os.path.basename(measure)}" style="width:{w}px;height:900px;border:0;flex:none"></iframe>' for w in widths) +
                """<script>var got = [];
                window.addEventListener('message', function(e){
                  got.push(JSON.parse(e.data));
                  if(got.length === %d) document.body.dataset.fit = JSON.stringify(got);
                });</script></body></html>""" % len(widths))
    dom = chromium([f"--window-size={sum(widths) + 40},900", "--dump-dom", "file://" + frames])
    m = re.search(r'data-fit="([^"]*)"', dom.stdout)
    got = {f["inner"]: f for f in json.loads(html.unescape(m.group(1)))} if m else {}
    check(sorted(got) == sorted(widths), f"the page was measured in windows {sorted(got)} px wide ({list(widths)} wanted)")
    for width in widths:
        fit = got.get(width)
        if fit is None:
            continue
        W = width
        check(fit["scroll"] <= W, f"{width} px: no horizontal scrollbar: the document is {fit['scroll']} px wide in {W} px (past it: {fit['off']})")
        svgs, canvases = fit["svgs"], fit["canvases"]
        check((svgs != []) == plots and all(s["box"]["right"] <= W + 0.5 and s["box"]["left"] >= -0.5 for s in svgs),
              f"{width} px: every SVG inside the window: {[(s['id'], round(s['box']['left']), round(s['box']['right'])) for s in svgs]}")
        check(all(c["box"]["right"] <= W + 0.5 for c in canvases),
              f"{width} px: every canvas inside the window: {[(c['id'], round(c['box']['right'])) for c in canvases]}")
        # Scaled whole: the viewBox's aspect ratio, every label drawn (non-empty, inside its plot).
        bad = [s["id"] for s in svgs if not (s["vw"] > 0 and s["box"]["w"] > 0 and abs(s["box"]["h"] / s["box"]["w"] - s["vh"] / s["vw"]) < 0.01 * s["vh"] / s["vw"])]
        check(bad == [], f"{width} px: each plot keeps its aspect ratio (viewBox): {bad} do not")
        bad = [s["id"] for s in svgs if len(s["texts"]) < 3 or not all(t and r["w"] > 0 and r["h"] > 0 and r["left"] >= s["box"]["left"] - 1
                                                                        and r["right"] <= s["box"]["right"] + 1 for t, r in s["texts"])]
        check(bad == [], f"{width} px: each plot's text is there, drawn inside it ({[len(s['texts']) for s in svgs]} texts): {bad} not")
        if view3d:
            v = next((c for c in canvases if c["id"] == "view3d"), None)
            check(v is not None and v["cw"] > 0 and v["ch"] > 0 and abs(v["cw"] / v["ch"] - 900 / 560) < 0.02 and v["bw"] == v["cw"] and v["bh"] == v["ch"],
                  f"{width} px: the 3-D view's canvas {v and (v['cw'], v['ch'])} px, 900:560, its drawing buffer {v and (v['bw'], v['bh'])} the same")
            r = fit.get("resized")
            check(r is not None and abs(r["cw"] - 298) <= 1 and abs(r["cw"] / r["ch"] - 900 / 560) < 0.02 and r["bw"] == round(r["cw"] * r["dpr"])
                  and r["bh"] == round(r["ch"] * r["dpr"]), f"{width} px: its box made 300 px wide, the window's resize re-sizes the canvas and its buffer: {r}")

def report(woven, folder):
    run([woven, "report", folder])
    page = os.path.join(folder, "report.html")
    html = open(page).read()
    outside = re.findall(r"<(?:script|img|link|iframe|source)\b[^>]*\b(?:src|href)\s*=\s*[\"'](?!data:)[^\"']*", html)
    check(outside == [], f"the page fetches nothing: {outside[:3]}")
    return page


# --- the kinds -----------------------------------------------------------------------------------

def test_kes(woven, tmp):
    out = os.path.join(tmp, "kes")
    # The cantilever and shear (both directions, one input curve) and the bending loop (warp).
    for test, extra in (("cantilever", []), ("shear", ["--sigma-cm", "1"]), ("bending", ["--direction", "warp", "--sigma-cm", "0.4"])):
        run([woven, "kes-test", "wool", "--test", test, "--out", os.path.join(out, test), "--threads", "1"] + extra)
    for test in ("cantilever", "shear", "bending"):
        folder = os.path.join(out, test)
        page = report(woven, folder)
        dom, _ = dump(page)
        check_wall(dom, json.load(open(os.path.join(folder, "kes-report.json"))).get("wall_time_s", 0), "kes-report.json's")
        if test == "shear":
            check_tables_fit(page)  # its table: a column per test and direction's summary values
            check_page_fits(page, False)
        plots = plots_of(dom)
        check(len(plots) == 1, f"kes-test {test}: one plot ({list(plots)})")
        for pid, (data, svg) in plots.items():
            check_plot(pid, data, svg)
            by = {s["label"]: s for s in data["series"]}
            if test == "cantilever":
                for d in ("warp", "weft"):
                    c = read_csv(os.path.join(folder, f"cantilever_{d}.csv"))
                    for src, label in (("simulated", f"simulated {d}"), ("elastica", f"elastica {d}")):
                        rows = [k for k, s in enumerate(c["source"]) if s == src]
                        check(label in by, f"{pid}: series '{label}'")
                        if label in by:
                            check_series(pid, by[label], [c["x_m"][k] for k in rows], [c["z_m"][k] for k in rows], f"cantilever_{d}.csv's {src} x_m, z_m")
                    xs = [x for x in by.get(f"simulated {d}", {"x": [0]})["x"]]
                    check(max(xs) - min(xs) > 0.01, f"{pid}: the cantilever is plotted along x (spans {max(xs) - min(xs):.3f} m), not at x = 0")
            else:
                name, x, y = ("shear", "phi_deg", "F_gf_per_cm") if test == "shear" else ("bending", "K_per_cm", "M_gf_cm_per_cm")
                dirs = ("warp", "weft") if test == "shear" else ("warp",)
                for d in dirs:
                    c = read_csv(os.path.join(folder, f"{name}_loop_{d}.csv"))
                    check(f"simulated {d}" in by, f"{pid}: series 'simulated {d}'")
                    if f"simulated {d}" in by:
                        check_series(pid, by[f"simulated {d}"], c[x], c["simulated_" + y], f"{name}_loop_{d}.csv's loop")
                    xs = by.get(f"simulated {d}", {"x": [0]})["x"]
                    check(any(xs[k + 1] < xs[k] for k in range(len(xs) - 1)), f"{pid}: the whole loop (the unloading too) is plotted")
                c = read_csv(os.path.join(folder, f"{name}_loop_{dirs[0]}.csv"))
                inputs = [s for s in data["series"] if s["label"].startswith("input")]
                check(len(inputs) == 1 and inputs[0]["label"] == "input", f"{pid}: one input curve, labelled once: {[s['label'] for s in inputs]}")
                if inputs:
                    check_series(pid, inputs[0], c[x], c["input_" + y], f"{name}_loop_{dirs[0]}.csv's input")


def test_cusick(woven, tmp):
    out = os.path.join(tmp, "cusick")
    run([woven, "cusick", "cotton", "--spacing-cm", "2", "--out", out, "--threads", "1", "--no-render"])
    j = json.load(open(os.path.join(out, "cusick.json")))
    page = report(woven, out)
    dom, body = dump(page)
    check_wall(dom, j.get("wall_time_s", 0), "cusick.json's")
    rows = dict((r[0], r[1]) for r in table_rows(dom, "cusick"))
    check(same(float(rows.get("drape_coefficient_percent", "nan")), j["drape_coefficient_percent"], 1e-5), f"the DC in the table: {rows.get('drape_coefficient_percent')}")
    nodes = table_rows(dom, "nodes")
    check(len(nodes) == j["nodes"] and all(same(float(r[1]), a, 1e-5) for r, a in zip(nodes, j["node_angles_deg"])), f"the nodes' table: {len(nodes)} rows")
    plots = plots_of(dom)
    check(len(plots) == 1, "one plot: the shadow")
    for pid, (data, svg) in plots.items():
        check_plot(pid, data, svg)
        by = {s["label"]: s for s in data["series"]}
        n = by.get("nodes", {"x": [], "y": []})
        run0 = next(r for r in j["runs"] if r["node_angles_deg"] == j["node_angles_deg"])
        radii = run0["node_radii_m"]
        want = [(r * math.sin(math.radians(a)), r * math.cos(math.radians(a))) for a, r in zip(j["node_angles_deg"], radii)]
        check_series(pid, n, [w[0] for w in want], [w[1] for w in want], "cusick.json's node angles and their run's radii as (r sin a, r cos a)", 1e-9)
        o = by.get("shadow outline", {"x": [0], "y": [0]})
        r = [math.hypot(x, y) for x, y in zip(o["x"], o["y"])]
        # The outline reaches each node's radius at its angle (the nodes are its lobes).
        for a, rn in zip(j["node_angles_deg"], radii):
            k = round(a / 360 * 720) % 720
            check(abs(r[k] - rn) < 0.002, f"{pid}: the outline at the node at {a:.1f} deg: r {r[k]:.4f} m, node {rn:.4f} m")
        check(min(r) >= 0.5 * j["disc_diameter_m"] - 1e-6 and max(r) <= 0.5 * j["specimen_diameter_m"] + 1e-6,
              f"{pid}: the outline lies between the disc and the flat specimen ({min(r):.3f} .. {max(r):.3f} m)")
        f = data["frame"]
        ppx = (f["right"] - f["left"]) / (f["x_hi"] - f["x_lo"])
        ppy = (f["bottom"] - f["top"]) / (f["y_hi"] - f["y_lo"])
        check(abs(ppx / ppy - 1) < 1e-9, f"{pid}: equal scales on x and y ({ppx:.2f}, {ppy:.2f} px/m)")
    check('data-view="webgl"' in body, "the 3-D view of cusick.glb was built")
    check_page_fits(page, True)


def test_fit(woven, tmp):
    out = os.path.join(tmp, "fit")
    run([woven, "fit", "wool", "--out", out])
    page = report(woven, out)
    dom, _ = dump(page)
    check_wall(dom, json.load(open(os.path.join(out, "report.json"))).get("wall_time_s", 0), "report.json's")
    check_page_fits(page, False)
    plots = plots_of(dom)
    titles = [d["title"] for d, _ in plots.values()]
    check(len(plots) == 5, f"fit: five plots (three KES curves with fits, B and T): {titles}")
    for pid, (data, svg) in plots.items():
        check_plot(pid, data, svg)
        by = {s["label"]: s for s in data["series"]}
        if data["title"].startswith("Bending energy"):
            for d in ("warp", "weft"):
                c = read_csv(os.path.join(out, f"bending_{d}_energy.csv"))
                check_series(pid, by.get(d, {"x": [], "y": []}) | {"label": d}, c["theta_rad"], c["B_J"], f"bending_{d}_energy.csv")
        if data["title"].startswith("Trellis"):
            c = read_csv(os.path.join(out, "trellis_energy.csv"))
            check_series(pid, by.get("T(phi)", {"x": [], "y": [], "label": "T(phi)"}), c["phi_rad"], c["T_J"], "trellis_energy.csv")
        if "KES curve" in data["title"]:
            check("KES data" in by and "fit (Sec. 5.1)" in by, f"{pid}: the KES data and the fit")


def test_experiment(woven, tmp):
    out, sweep = os.path.join(tmp, "exp"), os.path.join(tmp, "exp-sweep")
    run([woven, "experiment", "cube", "--seeds", "1", "--grid", "5", "--out", out, "--sweep", sweep])
    j = json.load(open(os.path.join(out, "cube_results.json")))
    page = report(woven, out)
    dom, body = dump(page)
    check_wall(dom, sum(r["wall_s"] for r in j["runs"]), "the sum of its drapes' wall_s")
    check_page_fits(page, 'data-view="webgl"' in body)
    stats = {r[0]: r for r in table_rows(dom, "statistics")}
    check(set(stats) == set(j["statistics"]), f"the statistics table has each fabric: {sorted(stats)}")
    for fab, s in j["statistics"].items():
        check(fab in stats and int(stats[fab][1]) == s["corners"] and int(stats[fab][2]) == s["single_diagonal"], f"{fab}: corners and single_diagonal")
    runs = table_rows(dom, "experiment-0-runs")
    head = re.search(r'<table class="sortable" id="experiment-0-runs"><thead><tr>(.*?)</tr>', dom, re.S)
    cols = re.findall(r"<th[^>]*>([^<]*)</th>", head.group(1)) if head else []
    check(len(runs) == len(j["runs"]) and all(same(float(r[cols.index("energy_J")]), x["energy_J"], 1e-5) for r, x in zip(runs, j["runs"])),
          f"the runs' table: a row per run with its energy ({len(runs)} rows)")
    plots = plots_of(dom)
    check(len(plots) == 2, "two plots: energy and projected area against the bending length")
    for pid, (data, svg) in plots.items():
        check_plot(pid, data, svg)
        energy = data["title"].startswith("Energy")
        for s in data["series"]:
            fab = s["label"].split(" (")[0]
            ys = [r["energy_J"] if energy else r["folds"]["projected_area_m2"] for r in j["runs"] if r["fabric"] == fab]
            check(len(ys) == 1 and same(s["y"][0], ys[0]), f"{pid}: {fab}: {s['y']} is cube_results.json's {ys}")
            # The colour the figure beside it gives the fabric's cloth: its file's display colour.
            m = re.search(r"^color\s*=\s*\[([^\]]*)\]", open(os.path.join(SOURCE, "fabrics", fab + ".toml")).read(), re.M)
            want = [math.floor(255 * float(v) + 0.5) for v in m.group(1).split(",")] if m else None  # as the page rounds (half up)
            check(want is not None and s["color"] == want, f"{pid}: {fab} drawn in its display colour {want}: {s['color']}")
    # A changed file: a one-line error naming it (as `woven check` finds it: its size first), exit 2,
    # and the page as it was.
    page = os.path.join(out, "report.html")
    before = open(page, "rb").read()
    with open(os.path.join(out, "cube_folds.md"), "a") as f:
        f.write("changed\n")
    p = run([woven, "report", out], check_rc=2)
    check(p.stderr.count("\n") == 1 and "the output folder does not verify: " in p.stderr and "cube_folds.md: bytes: " in p.stderr,
          f"a changed experiment file: {p.stderr.strip()}")
    check(open(page, "rb").read() == before, "the page is not rewritten")


def glb_field(path, attribute):
    """The values of a float attribute of the glb's node "cloth", and the asset's units."""
    data = open(path, "rb").read()
    n = struct.unpack("<I", data[12:16])[0]
    js = json.loads(data[20:20 + n])
    binary = data[20 + n + 8:]
    node = next(x for x in js["nodes"] if x.get("name") == "cloth")
    acc = js["accessors"][js["meshes"][node["mesh"]]["primitives"][0]["attributes"][attribute]]
    view = js["bufferViews"][acc["bufferView"]]
    at = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    return list(struct.unpack(f"<{acc['count']}f", binary[at:at + 4 * acc["count"]])), js["asset"].get("extras", {}).get("units", {})


def test_drape(woven, tmp):
    out = os.path.join(tmp, "drape")
    run([woven, "drape", "cube", "--grid", "15", "--out", out, "--threads", "1"])
    j = json.load(open(os.path.join(out, "report.json")))
    page = report(woven, out)
    dom, body = dump(page)
    energy = dict((r[0], r[1]) for r in table_rows(dom, "energy"))
    check(all(k in energy and same(float(energy[k]), v, 1e-5) for k, v in j["energy"].items()), f"the energy table is report.json's energy: {energy}")
    folds = table_rows(dom, "folds")
    want = [(c["corner"], b) for c in j["folds"]["corners"] for b in c["billows"]]
    check([(int(r[0]), int(r[2])) for r in folds] == want, f"the folds table: corners and billows {want}")
    check('data-view="webgl"' in body, "the 3-D view was built with WebGL")
    check_page_fits(page, True, plots=False)
    boxes = json.loads(re.search(r'data-bounds="([^"]*)"', body).group(1).replace("&quot;", '"')) if "data-bounds" in body else []
    box = next((b for b in boxes if "box" in b["name"]), None)
    check(box is not None, f"the page reports the cube's bounds: {[b['name'] for b in boxes]}")
    if box is None:
        return
    x0, y0, z0, x1, y1, z1 = box["box"]
    # Where the cube's top edge (+x side, its middle) meets the cloth: seen from outside, a little above.
    t = (x1, 0.5 * (y0 + y1), z1)
    d = 0.6 * (x1 - x0)
    cam = (t[0] + d, t[1] - 0.3 * d, t[2] + 0.6 * d)
    # The cube in magenta (neither the cotton's colour nor the background), the floor hidden.
    view = f"#camera={cam[0]},{cam[1]},{cam[2]}&target={t[0]},{t[1]},{t[2]}&obstacles=ff00ff&field=none"
    shots = {}
    for name, extra in (("bare", "&hide=cloth,plane"), ("cloth", "&hide=plane")):
        shot = os.path.join(tmp, name + ".png")
        chromium(["--window-size=1000,700", "--screenshot=" + shot, "file://" + page + view + extra])
        shots[name] = png_pixels(shot) if os.path.isfile(shot) else None
    check(all(shots.values()), "Chromium wrote both screenshots")
    if not all(shots.values()):
        return
    magenta = lambda r, g, b: r > 90 and b > 90 and g < 0.45 * min(r, b) and abs(r - b) < 60
    w, h, bare, ch = shots["bare"]
    _, _, cloth, _ = shots["cloth"]
    cube, through, covered = 0, 0, 0
    for y in range(h):
        for x in range(0, w * ch, ch):
            if magenta(*bare[y][x:x + 3]):
                cube += 1
                if magenta(*cloth[y][x:x + 3]):
                    through += 1
                elif cloth[y][x:x + 3] != bare[y][x:x + 3]:
                    covered += 1
    check(cube > 50000, f"without the cloth the cube's edge fills much of the view ({cube} cube-coloured pixels)")
    check(through == 0, f"with the cloth no cube-coloured pixel shows through ({through} of {cube})")
    check(covered > 0.99 * cube, f"the cloth covers the cube there ({covered} of {cube} pixels)")
    # The legend of a field: its name, unit, min and max as the glb holds them, and its colours drawn.
    values, units = glb_field(os.path.join(out, "drape.glb"), "_STRAIN_WARP")
    dom, body = dump(page, "#field=strain_warp")
    leg = re.search(r'<div id="view3d-legend"([^>]*)>(.*?)</div></div>', dom, re.S)
    attrs = dict(re.findall(r'data-(\w+)="([^"]*)"', leg.group(1))) if leg else {}
    check(attrs.get("field") == "strain_warp" and attrs.get("unit") == units.get("_STRAIN_WARP"), f"the legend names the field and its unit: {attrs}")
    check(same(float(attrs.get("min", "nan")), min(values), 1e-6) and same(float(attrs.get("max", "nan")), max(values), 1e-6),
          f"the legend's range is the field's: {attrs.get('min')} .. {attrs.get('max')} vs {min(values):.6g} .. {max(values):.6g}")
    check(leg is not None and "strain_warp" in leg.group(2) and "display: block" in leg.group(1), "the legend is shown with its text")
    shot = os.path.join(tmp, "legend.png")
    chromium(["--window-size=1000,700", "--screenshot=" + shot, "file://" + page + "#field=strain_warp&hide=cloth"])
    if os.path.isfile(shot):
        w, h, px, ch = png_pixels(shot)
        near = lambda p, c: all(abs(a - b) < 12 for a, b in zip(p, c))
        ends = [sum(near(px[y][x:x + 3], c) for y in range(h) for x in range(0, w * ch, ch)) for c in ((68, 1, 84), (253, 231, 37))]
        check(min(ends) >= 20, f"the legend's colour bar is drawn (viridis ends: {ends} pixels, the cloth hidden)")


def test_garment(woven, tmp):
    # The four-gore skirt cut on the bias (grain 45 degrees) at a coarse 4 cm: four nodes.
    out = os.path.join(tmp, "garment")
    run([woven, "garment", os.path.join(SOURCE, "examples", "garments", "gored-skirt-bias.toml"), "--spacing", "4", "--threads", "1",
         "--width", "200", "--height", "250", "--out", out])
    j = json.load(open(os.path.join(out, "report.json")))
    page = report(woven, out)
    dom, body = dump(page)
    cell = lambda name: points_cell(dom, name) or "nan"
    check_wall(dom, j["wall_time_s"], "report.json's")
    check(int(cell("hem_nodes")) == j["hem"]["nodes"] and same(float(cell("flare")), j["hem"]["flare"], 1e-5),
          f"the table's hem_nodes {cell('hem_nodes')} and flare {cell('flare')} are report.json's")
    g = dict((r[0], r[1]) for r in table_rows(dom, "garment"))
    check(g.get("fabric") == j["fabric"] and int(g.get("particles", -1)) == j["particles"] and same(float(g.get("spacing_m", "nan")), j["spacing_m"], 1e-5),
          f"the garment's table: fabric, particles, spacing {g}")
    pieces = table_rows(dom, "pieces")
    check([(r[0], float(r[1]), int(r[2])) for r in pieces] == [(p["name"], p["grain_deg"], p["particles"]) for p in j["pieces"]]
          and all(p["grain_deg"] == 45 for p in j["pieces"]), f"the pieces with their grain angles (45 deg): {pieces}")
    hem = dict((r[0], r[1]) for r in table_rows(dom, "hem"))
    for k in ("flare", "mean_radius_m", "below_waist_m", "length_drop_m"):
        check(same(float(hem.get(k, "nan")), j["hem"][k], 1e-5), f"the hem's {k}: {hem.get(k)} vs {j['hem'][k]}")
    check(int(hem.get("nodes", -1)) == j["hem"]["nodes"] == 4, f"the hem's nodes: {hem.get('nodes')} (report.json {j['hem']['nodes']}, 4 expected)")
    angles = [float(a) for a in hem.get("node_angle_deg", "").split()]
    check(len(angles) == len(j["hem"]["node_angle_deg"]) and all(same(a, b, 1e-5) for a, b in zip(angles, j["hem"]["node_angle_deg"])),
          f"the nodes' angles: {angles}")
    seams = table_rows(dom, "seams")
    check(len(seams) == len(j["seams"]) and all(r[0] == s["name"] and int(r[1]) == s["stitches"] and same(float(r[2]), s["max_gap_m"], 1e-5)
                                                  and same(float(r[4]), s["max_gap_over_spacing"], 1e-5) for r, s in zip(seams, j["seams"])),
          f"the seams' gaps: {len(seams)} rows")
    plots = plots_of(dom)
    check(len(plots) == 2, f"two plots: the hem's radius and height per angle ({[d['title'] for d, _ in plots.values()]})")
    h = j["hem"]

    def interpolated(values, a):
        # The hem per bin, periodic, linear between the bins beside angle a.
        xs, n = h["angle_deg"], len(h["angle_deg"])
        k = sum(1 for x in xs if x <= a)
        lo, hi = (n - 1 if k == 0 else k - 1), k % n
        a_lo, a_hi = xs[lo] - (360 if k == 0 else 0), xs[hi] + (360 if k == n else 0)
        t = (a - a_lo) / (a_hi - a_lo)
        return (1 - t) * values[lo] + t * values[hi]
    for pid, (data, svg) in plots.items():
        check_plot(pid, data, svg)
        by = {s["label"]: s for s in data["series"]}
        key, label = ("radius_m", "hem radius") if data["title"].startswith("Hem radius") else ("height_m", "hem height")
        check(label in by, f"{pid}: series '{label}'")
        if label in by:
            check_series(pid, by[label], h["angle_deg"], h[key], f"report.json's hem angle_deg, {key} (72 bins)")
        nodes = by.get("nodes", {"x": [], "y": [], "label": "nodes"})
        check_series(pid, nodes, h["node_angle_deg"], [interpolated(h[key], a) for a in h["node_angle_deg"]],
                     f"the nodes at report.json's node_angle_deg, on the line between bins")
        if key == "radius_m":
            w = by.get("waist radius", {"y": []})
            check(len(w["y"]) == 2 and all(same(y, j["waist"]["radius_m"]) for y in w["y"]), f"{pid}: the waist's radius {w['y']}")
    check(re.search(r'<img alt="garment garment.png" src="data:image/png;base64,', dom) is not None, "the gallery holds garment.png")
    # The 3-D view: garment.glb, the cloth on the body (the dress form from waist - hip depth - 22 cm to waist + 30 cm).
    check('data-view="webgl"' in body, "the 3-D view of garment.glb was built with WebGL")
    check_page_fits(page, True)
    boxes = json.loads(re.search(r'data-bounds="([^"]*)"', body).group(1).replace("&quot;", '"')) if "data-bounds" in body else []
    b = j["body"]
    lo, hi = b["waist_height_m"] - b["hip_depth_m"] - 0.22, b["waist_height_m"] + 0.30
    check(len(boxes) == 1 and abs(boxes[0]["box"][2] - lo) < 1e-3 and abs(boxes[0]["box"][5] - hi) < 1e-3,
          f"the view holds the body from z {lo:.3f} to {hi:.3f} m: {boxes}")
    models = json.loads(re.search(r'<script type="application/json" id="woven-models">(.*?)</script>', dom, re.S).group(1)) if "woven-models" in dom else []
    import base64
    glb = open(os.path.join(out, "garment.glb"), "rb").read()
    check(len(models) == 1 and base64.b64decode(models[0]["glb"]) == glb, "the view's model is the folder's garment.glb, byte for byte")


def main():
    which, woven = sys.argv[1], os.path.abspath(sys.argv[2])
    tmp = tempfile.mkdtemp(prefix="woven-report-")
    try:
        {"drape": test_drape, "cusick": test_cusick, "kes-test": test_kes, "fit": test_fit, "experiment": test_experiment,
         "garment": test_garment}[which](woven, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} failed")
        sys.exit(1)


if __name__ == "__main__":
    main()
