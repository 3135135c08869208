"""What a user drives and sees at the edges of the `woven` command (issue 45, items 5 and 6): word
on every long wait on stderr (a bar that fills and fits the terminal, one line per event
otherwise), exit codes as documented, option types in --help, one wording of ranges, defaults
that leave the repository alone, the docs' links. Run by ctest (UX.Edges) with WOVEN_BINARY."""
import json
import os
import pty
import re
import select
import subprocess

import pytest

SOURCE_DIR = os.environ.get("WOVEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ.get("WOVEN_BINARY", os.path.join(SOURCE_DIR, "build", "woven"))


def woven(*args, cwd=None, env=None, timeout=240):
    p = subprocess.run([BINARY, *map(str, args)], cwd=cwd, env=dict(os.environ, **(env or {})), capture_output=True, text=True,
                       timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def woven_on_a_terminal(*args, cwd=None, env=None, columns=80, timeout=240):
    """Runs woven with stderr on a pseudo-terminal `columns` wide; returns (exit code, stdout, what the terminal got)."""
    import fcntl
    import struct
    import termios
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, columns, 0, 0))
    p = subprocess.Popen([BINARY, *map(str, args)], cwd=cwd, env=dict(os.environ, **(env or {})), stdout=subprocess.PIPE,
                         stderr=slave, stdin=subprocess.DEVNULL)
    os.close(slave)
    got = b""
    while True:
        r, _, _ = select.select([master], [], [], timeout)
        if not r:
            p.kill()
            break
        try:
            chunk = os.read(master, 65536)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        got += chunk
    out = p.stdout.read().decode()
    p.wait(timeout=timeout)
    os.close(master)
    return p.returncode, out, got.decode(errors="replace")


def screen_lines(terminal):
    """Each line as drawn on the terminal: redraws split at \\r, the clear-to-end-of-line code removed."""
    text = terminal.replace("\033[K", "").replace("\r\n", "\n")
    return [seg for line in text.split("\n") for seg in line.split("\r") if seg]


# --- Item 5: word on every wait -------------------------------------------------------------


def test_the_drape_bar_fills_and_fits_80_columns(tmp_path):
    code, out, term = woven_on_a_terminal("drape", "cube", "--grid", "15", "--seed", "1", "--threads", "1", "--no-render",
                                          "--out", tmp_path / "o", cwd=tmp_path)
    assert code == 0, term
    bars = [l for l in screen_lines(term) if l.startswith("[")]
    assert len(bars) >= 3, term
    # The redrawn lines fit (a wrapped line is not redrawn in place).
    assert all(len(l) <= 79 for l in bars), [l for l in bars if len(l) > 79]
    filled = [len(re.match(r"\[(#*)", l).group(1)) for l in bars]
    # The bar moves before the end (not empty until the last step), and ends full.
    assert any(0 < n < 20 for n in filled[:-1]), filled
    assert filled[-1] == 20, filled


def test_render_gives_word_on_stderr_as_lines_when_not_a_terminal(tmp_path):
    code, out, err = woven("drape", "cube", "--grid", "7", "--seed", "1", "--threads", "1", "--no-render", "--out", "d", cwd=tmp_path)
    assert code == 0, err
    code, out, err = woven("render", "d/drape.obj", "--scene", "cube", "--size", "160x120", "--out", "r.png", cwd=tmp_path,
                           env={"WOVEN_PROGRESS_DELAY_S": "0"})
    assert code == 0, err
    lines = err.splitlines()
    assert lines and all(l.startswith("woven: rendering r.png (160 x 120): ") for l in lines), err
    assert re.fullmatch(r"woven: rendering r\.png \(160 x 120\): done in \d+\.\d s", lines[-1]), err
    assert all(len(l) <= 80 for l in lines)
    assert "rendering" not in out
    # Under the delay (two seconds by default) a quick picture says nothing.
    code, out, err = woven("render", "d/drape.obj", "--scene", "cube", "--size", "16x12", "--out", "q.png", cwd=tmp_path)
    assert code == 0 and err == "", err


def test_kes_test_gives_word_and_takes_threads(tmp_path):
    code, out, err = woven("kes-test", "cotton", "--test", "cantilever", "--direction", "warp", "--sigma-cm", "1", "--threads", "1",
                           "--out", "k", cwd=tmp_path, env={"WOVEN_PROGRESS_DELAY_S": "0"})
    assert code == 0, err
    lines = [l for l in err.splitlines() if l.startswith("woven: kes-test cotton: ")]
    assert len(lines) >= 2 and "(cantilever warp" in lines[0] and lines[-1].startswith("woven: kes-test cotton: done in "), err
    assert "kes-test cotton:" not in out
    assert json.load(open(tmp_path / "k" / "kes-report.json"))["tests"][0]["test"] == "cantilever"
    code, out, err = woven("kes-test", "cotton", "--threads", "-1", cwd=tmp_path)
    assert code == 2 and err == "woven: error: command line: --threads: expected an integer in [0, 4096], got '-1'\n", err


# --- Item 6: the edges --------------------------------------------------------------------------


def test_an_output_folder_that_cannot_be_made_is_an_io_error(tmp_path):
    code, out, err = woven("drape", "cube", "--grid", "5", "--out", "/proc/nope", cwd=tmp_path)
    assert code == 1, err
    assert err.startswith("woven: error: command line: --out: cannot create the directory /proc/nope: ") and err.count("\n") == 1


def test_the_readme_lists_every_exit_code_the_help_names():
    code, out, err = woven("--help")
    named = sorted(int(c) for c in re.findall(r"\b(\d+) (?:ok|runtime|bad|interrupted|terminated)", out))
    assert named == [0, 1, 2, 130, 143], out
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    table = re.search(r"## Exit codes\n\n(.*?)\n\n", readme, re.S).group(1)
    assert sorted(int(c) for c in re.findall(r"^\| (\d+) \|", table, re.M)) == named


INTEGER_OPTIONS = {
    "drape": ["--grid", "--seed", "--threads", "--max-steps", "--width", "--height"],
    "cusick": ["--seeds", "--seed", "--threads", "--max-steps", "--shakes"],
    "kes-test": ["--threads"],
    "sweep": ["--jobs"],
    "experiment": ["--seeds", "--grid", "--threads", "--jobs"],
}


@pytest.mark.parametrize("command", sorted(INTEGER_OPTIONS))
def test_integer_options_are_typed_int_in_help(command):
    code, out, err = woven(command, "--help")
    assert code == 0, err
    for option in INTEGER_OPTIONS[command]:
        m = re.search(r"^\s+" + re.escape(option) + r"\s+([A-Z]+)", out, re.M)
        assert m and m.group(1) == "INT", f"{command} {option}: {m.group(0) if m else out}"


TYPED_HELP = [
    # command, option, --help's type, a bad value whose error states the same range (None: a choice)
    ("drape", "--grid", "INT in [3, 100000]", "2"),
    ("drape", "--max-steps", "INT in [0, 1000000000]", "-1"),
    ("drape", "--threads", "INT in [0, 4096]", "-1"),
    ("drape", "--perturb", "NUMBER in [0, 0.01]", "1"),
    ("drape", "--width", "INT in [1, 16384]", "0"),
    ("drape", "--solver", "{fast,paper}", None),
    ("drape", "--hysteresis", "{loading-branch,friction}", None),
    ("drape", "--bias", "{threads,fabric}", None),
    ("cusick", "--specimen-cm", "NUMBER in (0, 200]", "0"),
    ("cusick", "--seeds", "INT in [1, 1000]", "0"),
    ("cusick", "--shakes", "INT in [0, 100]", "-1"),
    ("cusick", "--clamp-margin", "NUMBER in [-2, 2]", "3"),
    ("cusick", "--clamp", "{pinned,discs}", None),
    ("cusick", "--protocol", "{release,lowered}", None),
    ("cusick", "--shear-law", "{deembedded,measured}", None),
    ("kes-test", "--sigma-cm", "NUMBER in [0.02, 2]", "5"),
    ("kes-test", "--test", "{cantilever,bending,shear,all}", None),
    ("kes-test", "--bending-form", "{work,secant}", None),
    ("kes-test", "--threads", "INT in [0, 4096]", "-1"),
    ("fit", "--sigma-cm", "NUMBER in [0.01, 100]", "0"),
]


@pytest.mark.parametrize("command, option, shown, bad", TYPED_HELP, ids=[f"{c} {o}" for c, o, _, _ in TYPED_HELP])
def test_help_shows_each_number_and_choice_with_its_type_and_range(tmp_path, command, option, shown, bad):
    code, out, err = woven(command, "--help")
    assert code == 0, err
    assert re.search(r"^\s+" + re.escape(option) + r" " + re.escape(shown) + r"(=\S+)?(\s|$)", out, re.M), out
    # The range --help shows is the one the value is checked against (woven's own error).
    args = [command] + (["cube"] if command == "drape" else ["cotton"]) + [option, bad if bad else "nope"]
    code, out, err = woven(*args, cwd=tmp_path)
    assert code == 2, err
    if bad:
        assert shown.split(" in ")[1] in err, err
    else:
        assert err.startswith("woven: error: command line: " + option + ": expected"), err


SWEEP_PLAN = 'name = "t"\ncommand = "cusick"\n[axes]\nfabric = ["cotton"]\n[options]\nspacing_cm = 3\nrender = false\n'

BATCH_TYPED_HELP = [
    # command, option, --help's type, a command line with a bad value, what its error says of the range
    ("render", "--size", "WxH (INT in [1, 16384] each)", ["render", "d.obj", "--size", "0x10"],
     "command line: --size: expected WxH, each an integer in [1, 16384] (e.g. 1024x768), got '0x10'"),
    ("render", "--view", "{front,corner,side,top,scene}", ["render", "d.obj", "--view", "sideways"],
     "command line: --view: expected front, corner, side, top or scene, got 'sideways'"),
    ("sweep", "--jobs", "INT in [1, 4096]", ["sweep", "plan.toml", "--jobs", "0"],
     "command line: --jobs: expected an integer in [1, 4096], got '0'"),
    ("experiment", "EXPERIMENT", "{cube,map,figure1}", ["experiment", "chair", "--out", "e"],
     "command line: EXPERIMENT: expected cube, map or figure1, got 'chair'"),
    ("experiment", "--seeds", "INT in [1, 100]", ["experiment", "cube", "--seeds", "0", "--out", "e"],
     "command line: --seeds: expected an integer in [1, 100], got '0'"),
    ("experiment", "--grid", "INT in [3, 401]", ["experiment", "cube", "--grid", "2", "--out", "e"],
     "command line: --grid: expected an integer in [3, 401], got '2'"),
    ("experiment", "--threads", "INT in [0, 4096]", ["experiment", "cube", "--threads", "-1", "--out", "e"],
     "command line: --threads: expected an integer in [0, 4096], got '-1'"),
    ("experiment", "--jobs", "INT in [1, 4096]", ["experiment", "cube", "--jobs", "0", "--out", "e"],
     "command line: --jobs: expected an integer in [1, 4096], got '0'"),
    ("experiment", "--map-grid", "RxL (INT in [2, 9] each)", ["experiment", "map", "--map-grid", "1x4", "--out", "e"],
     "command line: --map-grid: expected RxL: R ratios by L bending lengths, each an integer in [2, 9]"),
]


@pytest.mark.parametrize("command, option, shown, args, error", BATCH_TYPED_HELP, ids=[f"{c} {o}" for c, o, _, _, _ in BATCH_TYPED_HELP])
def test_help_of_render_sweep_and_experiment_types_each_number_and_choice(tmp_path, command, option, shown, args, error):
    code, out, err = woven(command, "--help")
    assert code == 0, err
    assert re.search(r"^\s+" + re.escape(option) + r" " + re.escape(shown) + r"(=\S+)?(\s|$)", out, re.M), out
    # The same range in woven's own one-line error, exit 2, nothing written.
    (tmp_path / "plan.toml").write_text(SWEEP_PLAN)
    code, out, err = woven(*args, cwd=tmp_path)
    assert (code, err) == (2, "woven: error: " + error + "\n")
    assert sorted(os.listdir(tmp_path)) == ["plan.toml"]


def test_ranges_are_worded_one_way(tmp_path):
    text = open(os.path.join(SOURCE_DIR, "fabrics", "cotton.toml")).read()
    for value, expected in [("0.1", "areal_density_mg_cm2: expected a number in [0.5, 500] mg/cm^2 (W), got 0.1"),
                            ("2e9", "areal_density_mg_cm2: expected a positive number in (0, 1000000000] mg/cm^2")]:
        bad = tmp_path / "f.toml"
        bad.write_text(re.sub(r"(?m)^areal_density_mg_cm2\s*=.*$", f"areal_density_mg_cm2 = {value}", text))
        code, out, err = woven("check", bad, cwd=tmp_path)
        assert code == 2 and expected in err, err
        assert not re.search(r"expected [0-9.e+-]+ to [0-9]", err), err


def test_experiment_writes_under_out_by_default():
    code, out, err = woven("experiment", "--help")
    assert code == 0, err
    assert re.search(r"--out TEXT=out/experiments\s", out), out
    assert "docs/experiments" not in out


def test_check_takes_sweep_folders(tmp_path):
    (tmp_path / "plan.toml").write_text('name = "t"\ncommand = "cusick"\n[axes]\nfabric = ["cotton"]\nseed = [1, 2]\n[options]\n'
                                        'spacing_cm = 3\nthreads = 1\nrender = false\n')
    code, out, err = woven("sweep", "plan.toml", "--out", "s", cwd=tmp_path)
    assert code == 0, err
    code, out, err = woven("check", "s", cwd=tmp_path)
    assert code == 0, err
    assert re.fullmatch(r"s: ok \(sweep t of cusick, 2 points: 2 done and verified, 0 not done\)\n", out), out
    point = sorted(p for p in os.listdir(tmp_path / "s") if p.startswith("fabric-"))[0]
    with open(tmp_path / "s" / point / "cusick.obj", "a") as f:
        f.write("# changed\n")
    code, out, err = woven("check", "s", cwd=tmp_path)
    assert code == 2 and "fabric-cotton_seed-1/cusick.obj: bytes: " in err and out == "", err


MARKDOWN_FILES = {f for d, dirs, files in os.walk(SOURCE_DIR) if "/build" not in d and "/." not in d for f in files if f.endswith(".md")}


def test_the_docs_links_lead_somewhere():
    docs = [os.path.join(SOURCE_DIR, "README.md")] + [os.path.join(SOURCE_DIR, "docs", f) for f in os.listdir(os.path.join(SOURCE_DIR, "docs"))
                                                     if f.endswith(".md")]
    dead = []
    for path in docs:
        text = open(path).read()
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
            if re.match(r"[a-z]+:", target):
                continue
            if not os.path.exists(os.path.join(os.path.dirname(path), target)):
                dead.append(f"{os.path.basename(path)}: {target}")
        # The model notes are not in the repository: no page sends the reader to them.
        if "MODEL-NOTES.md" not in MARKDOWN_FILES and "MODEL-NOTES.md" in text:
            dead.append(f"{os.path.basename(path)}: MODEL-NOTES.md")
    assert dead == []


# --- Item 4: the 3-D view ---------------------------------------------------------------------


def glb_mesh(path, node_name):
    """(vertices in woven's axes, faces, the node's extras) of a node of a GLB file."""
    import struct
    import numpy as np
    data = open(path, "rb").read()
    assert data[:4] == b"glTF"
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + n])
    binary = data[20 + n + 8:]
    node = next(x for x in doc["nodes"] if x["name"] == node_name)
    prim = doc["meshes"][node["mesh"]]["primitives"][0]

    def accessor(k, dtype, width):
        a = doc["accessors"][k]
        view = doc["bufferViews"][a["bufferView"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.frombuffer(binary, dtype=dtype, count=a["count"] * width, offset=start).reshape(a["count"], width)

    g = accessor(prim["attributes"]["POSITION"], np.float32, 3).astype(float)
    faces = accessor(prim["indices"], np.uint32, 1).reshape(-1, 3)
    return np.column_stack([g[:, 0], -g[:, 2], g[:, 1]]), faces, node.get("extras", {})


def cube_distance(p):
    """Signed distance to the paper's cube (0.5 m on the floor at the origin) and the floor."""
    import numpy as np
    q = np.abs(p - np.array([0, 0, 0.25])) - 0.25
    box = np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)
    return np.minimum(box, p[:, 2])


def sampled(vertices, faces, n=12):
    import numpy as np
    pts = []
    for i in range(n + 1):
        for j in range(n + 1 - i):
            u, v = i / n, j / n
            pts.append((1 - u - v) * vertices[faces[:, 0]] + u * vertices[faces[:, 1]] + v * vertices[faces[:, 2]])
    return np.concatenate(pts)


def test_the_glb_cloth_never_shows_the_cubes_edge(tmp_path):
    code, out, err = woven("drape", "cube", "--grid", "15", "--seed", "1", "--threads", "1", "--no-render", "--out", "o", cwd=tmp_path)
    assert code == 0, err
    import numpy as np
    obj_v = np.array([[float(t) for t in l.split()[1:4]] for l in open(tmp_path / "o" / "drape.obj") if l.startswith("v ")])
    v, f, extras = glb_mesh(tmp_path / "o" / "drape.glb", "cloth")
    # The physical cloth's triangles cut the cube's top edges (the reason for the display cloth)...
    assert cube_distance(sampled(obj_v, f)).min() < -1e-3
    # ...the glb's do not, by a margin, and it says what it holds.
    assert cube_distance(sampled(v, f)).min() > 0
    assert extras["holds"].startswith("display surface: ") and "drape.obj and drape.ply hold the particles" in extras["holds"]
    lift = np.linalg.norm(v - obj_v, axis=1)
    # Lifted by less than a particle spacing (1/14 m); most of the cloth by no more than the
    # contact distance (1 mm: a particle resting on the cube sits within it). Measured at this
    # coarse grid (7 cm triangles): 5.8 cm at most, 65 % of the vertices within 1 mm.
    assert 0 < lift.max() < 1 / 14 and np.mean(lift <= 1e-3 + 1e-9) > 0.6, (lift.max(), np.mean(lift <= 1e-3 + 1e-9))


def test_cusick_writes_a_glb_of_its_specimen(tmp_path):
    code, out, err = woven("cusick", "cotton", "--spacing-cm", "2", "--threads", "1", "--no-render", "--out", "c", cwd=tmp_path)
    assert code == 0, err
    report = json.load(open(tmp_path / "c" / "cusick.json"))
    assert "cusick.glb" in report["files"]
    v, f, extras = glb_mesh(tmp_path / "c" / "cusick.glb", "cloth")
    assert len(f) > 100 and extras["holds"].startswith("display surface: ")
    code, out, err = woven("check", "c", cwd=tmp_path)
    assert code == 0, err


@pytest.mark.parametrize("change, error", [
    (("radius_cm = 17", "radius_cm = 12"), "piece[1].place: piece 'front' starts inside the body"),
    (("azimuth_deg = 90", "azimuth_deg = -90"), "piece[2].place: pieces 'front' and 'back' overlap"),
    (('b = "back.left"', 'b = "back.right"'), "seam[1]: the seam 'front.right + back.right' crosses the body"),
])
def test_a_garment_that_cannot_start_is_one_line_and_exit_2_with_nothing_written(tmp_path, change, error):
    with open(os.path.join(SOURCE_DIR, "examples", "garments", "tube-skirt.toml")) as f:
        text = f.read()
    assert change[0] in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(change[0], change[1], 1))
    code, out, err = woven("garment", bad, "--spacing", "4", "--out", tmp_path / "out", cwd=tmp_path)
    assert code == 2, err
    assert err.startswith(f"woven: error: {bad}: {error}") and err.count("\n") == 1, err
    assert not (tmp_path / "out").exists()
