#!/usr/bin/python3
"""Format checks of woven's outputs by independent readers (run by ctest with Debian's python3).

  schemas WOVEN SCHEMA_DIR   drape, fit, cusick, kes-test and garment outputs against docs/schemas
                             (python3-jsonschema), and altered copies that must fail
  meshes  WOVEN              drape.ply (binary and ASCII) read by python3-meshio, drape.glb by
                             `assimp info` (assimp-utils): the vertex count and bounds of
                             drape.obj (read here), the per-vertex fields equal in both PLYs
  check   WOVEN              `woven check` on a finished folder (0), then on damaged copies (2)

Each run is small (a 9 x 9 cloth, a few steps) and one thread, so the checks take seconds.
"""
import copy
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

TINY_SCENE = """name = "tiny"
[cloth]
size_m = [0.3, 0.3]
grid = [9, 9]
height_m = 0.12
fabric = "cotton"
[[obstacle]]
type = "plane"
[[obstacle]]
type = "sphere"
centre_m = [0.0, 0.0, 0.05]
radius_m = 0.05
"""

FIELDS = ["strain_warp", "strain_weft", "trellis_angle", "curvature_warp", "curvature_weft", "contact", "residual_force"]


def display_lift(gltf):
    """The largest lift of the glTF's display cloth off the obstacles (its node's extras say it), m."""
    holds = gltf["nodes"][0].get("extras", {}).get("holds", "")
    m = re.search(r"\(at most ([0-9.e+-]+) m\)", holds)
    if not holds.startswith("display surface: ") or not m:
        fail(f"GLB: the cloth node does not say what it holds: {holds!r}")
    return float(m.group(1))


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def run(args, cwd, expect=0):
    r = subprocess.run(args, cwd=cwd, capture_output=True, text=True, env=dict(os.environ, OPENBLAS_CORETYPE="Prescott"))
    if r.returncode != expect:
        fail(f"{' '.join(args)}: exit {r.returncode}, expected {expect}\nstdout: {r.stdout}\nstderr: {r.stderr}")
    return r


def drape(woven, work, out, *extra):
    with open(os.path.join(work, "tiny.toml"), "w") as f:
        f.write(TINY_SCENE)
    run([woven, "drape", "tiny.toml", "--out", out, "--max-steps", "30", "--threads", "1", "--no-render", *extra], work)
    return os.path.join(work, out)


def obj_vertices(path):
    """The `v` lines of an OBJ file, parsed here (no library)."""
    with open(path) as f:
        return [tuple(float(t) for t in line.split()[1:4]) for line in f if line.startswith("v ")]


def bounds(points):
    return [min(p[k] for p in points) for k in range(3)], [max(p[k] for p in points) for k in range(3)]


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def schemas(woven, schema_dir, work):
    import jsonschema

    def load(name):
        with open(os.path.join(schema_dir, name)) as f:
            s = json.load(f)
        jsonschema.Draft7Validator.check_schema(s)
        return jsonschema.Draft7Validator(s)

    report, cusick, kes = load("report.schema.json"), load("cusick.schema.json"), load("kes-report.schema.json")
    garment = load("garment-report.schema.json")
    examples = os.path.join(os.path.dirname(os.path.dirname(schema_dir)), "examples", "garments")
    d = drape(woven, work, "d")
    # The cube (the paper's box): a report with its corner folds.
    run([woven, "drape", "cube", "--grid", "11", "--max-steps", "10", "--threads", "1", "--no-render", "--out", "cube"], work)
    run([woven, "fit", "cotton", "--out", "fit"], work)
    run([woven, "cusick", "silk", "--specimen-cm", "12", "--disc-cm", "6", "--spacing-cm", "1", "--seeds", "2",
         "--no-render", "--threads", "1", "--out", "c"], work)
    run([woven, "cusick", "silk", "--specimen-cm", "12", "--disc-cm", "6", "--spacing-cm", "1", "--clamp", "discs",
         "--no-render", "--threads", "1", "--out", "c2"], work)
    # Friction inside the weave, the lowered protocol and a shake: hysteresis, protocol, lower_step_m, shakes.
    run([woven, "cusick", "silk", "--specimen-cm", "12", "--disc-cm", "6", "--spacing-cm", "1", "--hysteresis", "friction",
         "--protocol", "lowered", "--shakes", "1", "--no-render", "--threads", "1", "--out", "c3"], work)
    run([woven, "drape", "tiny.toml", "--fabric", "wool", "--hysteresis", "friction", "--max-steps", "30", "--threads", "1",
         "--no-render", "--out", "df"], work)
    run([woven, "kes-test", "cotton", "--test", "bending", "--direction", "warp", "--out", "k"], work)
    # A shear loop with friction (the default): the hysteresis fields filled.
    run([woven, "kes-test", "wool", "--test", "shear", "--direction", "warp", "--sigma-cm", "1", "--out", "k2"], work)
    # The cheapest garment: the tube skirt (two rectangles, its seams closed from the start: one
    # stage) at 4 cm, one thread; `woven check` reads its folder as every command's.
    run([woven, "garment", os.path.join(examples, "tube-skirt.toml"), "--spacing", "4", "--threads", "1", "--no-render",
         "--out", "g"], work)
    run([woven, "check", os.path.join(work, "g")], work)
    cases = [(garment, os.path.join(work, "g", "report.json")),
             (report, os.path.join(d, "report.json")), (report, os.path.join(work, "cube", "report.json")),
             (report, os.path.join(work, "fit", "report.json")),
             (cusick, os.path.join(work, "c", "cusick.json")), (cusick, os.path.join(work, "c2", "cusick.json")),
             (cusick, os.path.join(work, "c3", "cusick.json")), (report, os.path.join(work, "df", "report.json")),
             (kes, os.path.join(work, "k", "kes-report.json")), (kes, os.path.join(work, "k2", "kes-report.json"))]
    for validator, path in cases:
        with open(path) as f:
            doc = json.load(f)
        errors = [e.message for e in validator.iter_errors(doc)]
        if errors:
            fail(f"{path}: {errors[:3]}")
        print(f"ok: {path} matches its schema")
    # The schemas must reject what they describe as wrong.
    with open(os.path.join(d, "report.json")) as f:
        good = json.load(f)
    bad_docs = []
    for change in ("drop model", "null energy", "bad solver", "unknown key", "short sha"):
        doc = copy.deepcopy(good)
        if change == "drop model":
            del doc["model"]
        elif change == "null energy":
            doc["energy"]["total_J"] = None
        elif change == "bad solver":
            doc["solver"] = "magic"
        elif change == "unknown key":
            doc["extra"] = 1
        else:
            doc["files"]["drape.obj"]["sha256"] = "abc"
        bad_docs.append((change, doc))
    for change, doc in bad_docs:
        if report.is_valid(doc):
            fail(f"report.schema.json accepts a report with '{change}'")
    with open(os.path.join(work, "c", "cusick.json")) as f:
        c = json.load(f)
    del c["runs"]
    if cusick.is_valid(c):
        fail("cusick.schema.json accepts a report without runs")
    with open(os.path.join(work, "cube", "report.json")) as f:
        cube = json.load(f)
    if not isinstance(cube["folds"], dict):
        fail("the cube's report has no folds")
    cube["folds"]["corners"].pop()
    if report.is_valid(cube):
        fail("report.schema.json accepts folds with three corners")
    with open(os.path.join(work, "g", "report.json")) as f:
        good = json.load(f)
    if not good["hem"]["particles"] or len(good["hem"]["radius_m"]) != 72 or good["memory_estimate_bytes"] <= 0:
        fail(f"the tube skirt's report has no hem or no memory estimate: {good['hem']['particles']} hem particles, "
             f"{len(good['hem']['radius_m'])} bins, {good['memory_estimate_bytes']} bytes")
    for change in ("negative hem nodes", "drop hem", "outputs as an object", "71 hem bins", "node at 360 deg",
                   "drop memory estimate", "negative gap", "no flare", "unknown key", "another command", "short sha"):
        doc = copy.deepcopy(good)
        if change == "negative hem nodes":
            doc["hem"]["nodes"] = -1
        elif change == "drop hem":
            del doc["hem"]
        elif change == "outputs as an object":
            doc["outputs"] = {n: True for n in doc["outputs"]}
        elif change == "71 hem bins":
            doc["hem"]["radius_m"].pop()
        elif change == "node at 360 deg":
            doc["hem"]["node_angle_deg"].append(360.0)
        elif change == "drop memory estimate":
            del doc["memory_estimate_bytes"]
        elif change == "negative gap":
            doc["seams"][0]["max_gap_m"] = -1e-3
        elif change == "no flare":
            doc["hem"]["flare"] = 0.0
        elif change == "unknown key":
            doc["hem"]["extra"] = 1
        elif change == "another command":
            doc["command"] = "drape"
        else:
            doc["files"]["garment.glb"]["sha256"] = "abc"
        if garment.is_valid(doc):
            fail(f"garment-report.schema.json accepts a report with '{change}'")
    print("ok: altered reports are rejected")


def meshes(woven, work):
    import meshio
    import numpy as np

    binary = drape(woven, work, "b")
    ascii_ = drape(woven, work, "a", "--ply-ascii")
    v = obj_vertices(os.path.join(binary, "drape.obj"))
    lo, hi = bounds(v)
    if len(v) != 81:
        fail(f"drape.obj has {len(v)} vertices, expected 81")
    with open(os.path.join(binary, "drape.ply"), "rb") as f:
        if not f.read(40).startswith(b"ply\nformat binary_little_endian 1.0\n"):
            fail("drape.ply is not binary little-endian by default")
    with open(os.path.join(ascii_, "drape.ply"), "rb") as f:
        if not f.read(24).startswith(b"ply\nformat ascii 1.0\n"):
            fail("--ply-ascii does not write ASCII PLY")
    mb = meshio.read(os.path.join(binary, "drape.ply"))
    ma = meshio.read(os.path.join(ascii_, "drape.ply"))
    for name, m in (("binary", mb), ("ascii", ma)):
        if m.points.shape != (81, 3):
            fail(f"meshio reads {m.points.shape} points from the {name} PLY")
        if not close(m.points.min(axis=0), lo, 1e-7) or not close(m.points.max(axis=0), hi, 1e-7):
            fail(f"meshio: {name} PLY bounds {m.points.min(axis=0)} {m.points.max(axis=0)}, drape.obj {lo} {hi}")
        if sum(len(c.data) for c in m.cells if c.type == "triangle") != 2 * 8 * 8:
            fail(f"meshio: {name} PLY has not 128 triangles")
        for field in FIELDS:
            if field not in m.point_data:
                fail(f"meshio: {name} PLY has no field {field} ({sorted(m.point_data)})")
            if not np.all(np.isfinite(m.point_data[field])):
                fail(f"{name} PLY: {field} is not finite")
    for field in FIELDS:  # float32 in binary, 7 significant digits in ASCII
        a, b = ma.point_data[field], mb.point_data[field]
        if not np.allclose(a, b, rtol=1e-6, atol=1e-12 * max(1.0, float(np.abs(b).max()))):
            fail(f"{field}: ASCII and binary PLY differ")
    contact = mb.point_data["contact"]
    if not set(np.unique(contact)) <= {0.0, 1.0} or contact.sum() == 0:
        fail(f"contact flag: {np.unique(contact)} (the cloth lies on a sphere: some particles touch it)")
    print(f"ok: meshio reads 81 points, bounds {lo} {hi}, fields {FIELDS}")

    # assimp (its own glTF importer): the cloth mesh has drape.obj's vertices and 2 triangles per
    # cell, and each obstacle is a mesh of its own.
    text = run(["assimp", "info", os.path.join(binary, "drape.glb")], work).stdout
    listed = dict(re.findall(r"^\s*\d+ \(([^)]*)\): \[(\d+ / \d+ / \d+)", text, re.M))
    if listed.get("cloth") != "81 / 0 / 128":
        fail(f"assimp: the cloth mesh is {listed.get('cloth')}, expected 81 vertices, 128 faces:\n{text}")
    if sorted(listed) != ["cloth", "obstacle 0 plane", "obstacle 1 sphere"]:
        fail(f"assimp: meshes {sorted(listed)}")
    print(f"ok: assimp reads drape.glb: {listed}")

    # The GLB read here (its JSON and binary chunks, glTF 2.0 spec 4.4): the cloth's bounds in
    # glTF's y-up axes are drape.obj's (x, z, -y), and its fields are the PLY's.
    glb = read_glb(os.path.join(binary, "drape.glb"))
    gltf, blob = glb
    prim = gltf["meshes"][gltf["nodes"][0]["mesh"]]["primitives"][0]
    pos = accessor(gltf, blob, prim["attributes"]["POSITION"]).reshape(-1, 3)
    if pos.shape != (81, 3):
        fail(f"GLB: {pos.shape} positions")
    expect_lo, expect_hi = [lo[0], lo[2], -hi[1]], [hi[0], hi[2], -lo[1]]
    # The glTF's cloth is for display: lifted off the obstacles by at most what its node says.
    lift = display_lift(gltf)
    if not close(pos.min(axis=0), expect_lo, 1e-6 + lift) or not close(pos.max(axis=0), expect_hi, 1e-6 + lift):
        fail(f"GLB bounds {pos.min(axis=0)} {pos.max(axis=0)}, expected {expect_lo} {expect_hi} (lift {lift})")
    acc = gltf["accessors"][prim["attributes"]["POSITION"]]
    if not close(acc["min"], pos.min(axis=0), 1e-6) or not close(acc["max"], pos.max(axis=0), 1e-6):
        fail(f"GLB accessor bounds {acc['min']} {acc['max']}")
    for field in FIELDS:
        values = accessor(gltf, blob, prim["attributes"]["_" + field.upper()])
        if not np.array_equal(values, mb.point_data[field].astype(np.float32)):
            fail(f"GLB {field} differs from the PLY's")
    print(f"ok: drape.glb read here: bounds {expect_lo} {expect_hi} (y-up), the PLY's fields")

    # A cloth cut to a disc: drape.obj and drape.glb hold its clipped surface, no drape.ply.
    with open(os.path.join(work, "disc.toml"), "w") as f:
        f.write(TINY_SCENE.replace('fabric = "cotton"', 'fabric = "cotton"\n[cloth.outline]\ntype = "disc"\nradius_m = 0.14'))
    run([woven, "drape", "disc.toml", "--out", "disc", "--max-steps", "10", "--threads", "1", "--no-render"], work)
    disc = os.path.join(work, "disc")
    if os.path.exists(os.path.join(disc, "drape.ply")):
        fail("a cut cloth has a drape.ply")
    vd = obj_vertices(os.path.join(disc, "drape.obj"))
    gltf, blob = read_glb(os.path.join(disc, "drape.glb"))
    prim = gltf["meshes"][gltf["nodes"][0]["mesh"]]["primitives"][0]
    pos = accessor(gltf, blob, prim["attributes"]["POSITION"]).reshape(-1, 3)
    dlo, dhi = bounds(vd)
    if pos.shape[0] != len(vd) or not close(pos.min(axis=0), [dlo[0], dlo[2], -dhi[1]], 1e-6 + display_lift(gltf)):
        fail(f"cut cloth: GLB {pos.shape[0]} vertices, OBJ {len(vd)}; bounds {pos.min(axis=0)} {dlo}")
    # assimp joins the surface's repeated vertices and drops triangles with two at one place (the
    # clipped surface has a few where the outline passes through a particle): compare the others.
    faces = 0
    with open(os.path.join(disc, "drape.obj")) as f:
        for line in f:
            if line.startswith("f "):
                p = [vd[int(t.split("/")[0]) - 1] for t in line.split()[1:4]]
                faces += p[0] != p[1] and p[1] != p[2] and p[0] != p[2]
    text = run(["assimp", "info", os.path.join(disc, "drape.glb")], work).stdout
    listed = dict(re.findall(r"^\s*\d+ \(([^)]*)\): \[\d+ / \d+ / (\d+)", text, re.M))
    if listed.get("cloth") != str(faces):
        fail(f"assimp: the cut cloth has {listed.get('cloth')} triangles, drape.obj {faces}")
    print(f"ok: a cut cloth's drape.glb: {len(vd)} vertices as its drape.obj (read here), {faces} triangles (assimp)")


def read_glb(path):
    """The JSON and the binary chunk of a GLB file."""
    import struct
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or length != len(data):
        fail(f"{path}: not a glTF 2.0 binary ({magic}, {version}, {length} of {len(data)} bytes)")
    n, kind = struct.unpack_from("<I4s", data, 12)
    if kind != b"JSON":
        fail(f"{path}: first chunk {kind}")
    gltf = json.loads(data[20:20 + n])
    m, kind = struct.unpack_from("<I4s", data, 20 + n)
    if kind != b"BIN\0":
        fail(f"{path}: second chunk {kind}")
    return gltf, data[28 + n:28 + n + m]


def accessor(gltf, blob, index):
    """A float accessor's values (tightly packed, as woven writes them)."""
    import numpy as np
    a = gltf["accessors"][index]
    if a["componentType"] != 5126:
        fail(f"accessor {index} is not float")
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    v = gltf["bufferViews"][a["bufferView"]]
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    return np.frombuffer(blob, dtype="<f4", count=a["count"] * width, offset=start)


def check(woven, work):
    d = drape(woven, work, "d")
    run([woven, "check", d, os.path.join(work, "tiny.toml"), os.path.join(d, "drape.obj")], work)
    damaged = os.path.join(work, "damaged")
    shutil.copytree(d, damaged)
    with open(os.path.join(damaged, "drape.obj"), "a") as f:
        f.write("# changed\n")
    r = run([woven, "check", damaged], work, expect=2)
    if "sha256" not in r.stderr and "bytes" not in r.stderr:
        fail(f"woven check does not name the changed file: {r.stderr}")
    print("ok: woven check passes the folder and finds the changed file: " + r.stderr.strip())


def main():
    mode, woven = sys.argv[1], os.path.abspath(sys.argv[2])
    work = tempfile.mkdtemp(prefix=f"woven_formats_{mode}_")
    try:
        if mode == "schemas":
            schemas(woven, os.path.abspath(sys.argv[3]), work)
        elif mode == "meshes":
            meshes(woven, work)
        elif mode == "check":
            check(woven, work)
        else:
            fail(f"unknown mode {mode}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
