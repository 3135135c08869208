"""The Python module against the `woven` command: the same drape bit for bit, the same files, the
same messages for bad input; progress, interrupts, the GIL, values, the README's example."""
import json
import math
import os
import re
import signal
import subprocess
import sys
import threading
import tomllib
import warnings

import numpy as np
import pytest

import woven
from conftest import BINARY, SOURCE_DIR

# A small drape: the paper's cube under an 11 x 11 cotton cloth (8 steps, well under a second).
SMALL = dict(grid=11, seed=1, threads=1)
SMALL_ARGS = ["--grid", "11", "--seed", "1", "--threads", "1"]


def cli_error(stderr):
    """The message of the command's `woven: error: ...` line."""
    lines = [l for l in stderr.splitlines() if l.startswith("woven: error: ")]
    assert len(lines) == 1, stderr
    return lines[0][len("woven: error: "):]


def obj_vertices(path):
    return np.array([[float(t) for t in l.split()[1:4]] for l in open(path) if l.startswith("v ")])


def obj_faces(path):
    return np.array([[int(t.split("/")[0]) - 1 for t in l.split()[1:4]] for l in open(path) if l.startswith("f ")])


def test_drape_is_the_commands_bit_for_bit(tmp_path, run_woven):
    code, out, err = run_woven("drape", "cube", *SMALL_ARGS, "--no-render", "--out", "cli")
    assert code == 0, err
    result = woven.drape("cube", **SMALL)
    written = result.save(tmp_path / "py", render=False)
    for name in ("drape.obj", "drape.ply", "drape.glb"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    cli = json.load(open(tmp_path / "cli" / "report.json"))
    py = json.load(open(tmp_path / "py" / "report.json"))
    assert py == written
    for r in (cli, py):
        r.pop("wall_time_s")
    assert py == cli
    # The arrays are the OBJ's mesh (printed with 9 significant digits).
    assert result.positions.dtype == np.float64 and result.positions.shape == (121, 3)
    assert result.faces.dtype == np.int32 and result.faces.shape == (200, 3)
    np.testing.assert_allclose(result.positions, obj_vertices(tmp_path / "cli" / "drape.obj"), rtol=1e-8, atol=1e-9)
    np.testing.assert_array_equal(result.faces, obj_faces(tmp_path / "cli" / "drape.obj"))
    np.testing.assert_array_equal(result.particles, result.positions)
    assert result.grid == (11, 11)
    assert result.converged and not result.interrupted and result.steps == cli["steps"]
    report = result.report
    assert report["outputs"] == [] and "files" not in report
    assert report["energy"] == cli["energy"] and report["steps"] == cli["steps"]
    fields = result.fields
    assert sorted(fields) == sorted(["strain_warp", "strain_weft", "trellis_angle", "curvature_warp", "curvature_weft",
                                     "contact", "residual_force"])
    assert all(f.shape == (121,) and np.isfinite(f).all() for f in fields.values())
    assert fields["contact"].sum() == cli["contact"]["particles"]
    assert abs(fields["strain_warp"]).max() <= cli["strain"]["max_abs"] + 1e-12


def test_every_builtin_fabric_and_scene_loads():
    assert len(woven.fabrics()) == 11 and "cotton" in woven.fabrics()
    for name in woven.fabrics():
        f = woven.Fabric.load(name)
        assert f.name and f.source and f.origin == f"built-in fabric '{name}'"
        assert 0 < f.W < 100 and f.W == f.areal_density_mg_cm2
        assert 0 < f.B_warp < 10 and 0 < f.B_weft < 10 and 0 < f.G < 20
        for c in (f.bending_warp_curve, f.bending_weft_curve, f.shear_curve):
            assert c.ndim == 2 and c.shape[1] == 2 and c.shape[0] >= 3 and np.all(np.diff(c[:, 0]) > 0)
        assert repr(f).startswith(f"<woven.Fabric '{f.name}'")
    assert woven.scenes() == ["chair", "cube", "drape_tester", "sphere", "table"]
    for name in woven.scenes():
        s = woven.Scene.load(name)
        assert s.name == name and s.source == f"scenes/{name}.toml"
        assert min(s.grid) >= 3 and s.sigma_m > 0 and s.obstacles and s.solver in ("fast", "paper")
    cube = woven.Scene.load("cube")
    assert cube.grid == (51, 51) and cube.obstacles == ["plane", "box"] and cube.fabric == "cotton"
    np.testing.assert_allclose(cube.size_m, (1.0, 1.0))


def test_values_are_read_as_the_files_are():
    cotton = tomllib.load(open(os.path.join(SOURCE_DIR, "fabrics", "cotton.toml"), "rb"))
    cube = tomllib.load(open(os.path.join(SOURCE_DIR, "scenes", "cube.toml"), "rb"))
    f = woven.Fabric(cotton)
    g = woven.Fabric.load("cotton")
    assert f.origin == "Python fabric" and f.name == g.name
    for c in ("bending_warp_curve", "bending_weft_curve", "shear_curve"):
        np.testing.assert_array_equal(getattr(f, c), getattr(g, c))
    # A dict and keyword arguments together, the keywords last.
    h = woven.Fabric({k: v for k, v in cotton.items() if k != "shear"}, shear=cotton["shear"])
    np.testing.assert_array_equal(h.shear_curve, g.shear_curve)
    s = woven.Scene(cube)
    assert s.source == "Python scene" and s.grid == (51, 51) and s.obstacles == ["plane", "box"]
    a = woven.drape(s, fabric=f, grid=7, seed=1, threads=1)
    b = woven.drape("cube", fabric="cotton", grid=7, seed=1, threads=1)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.report["scene_source"] == "Python scene" and a.report["fabric"] == "cotton"
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        woven.Fabric(cotton, colour=[1, 0, 0])
    assert [str(x.message) for x in w] == ["Python fabric: colour: unknown key, ignored"]
    assert w[0].category is woven.InputWarning and issubclass(woven.InputWarning, UserWarning)
    # numpy values are values.
    woven.Scene(cube, cloth=dict(cube["cloth"], size_m=np.array([1.0, 1.0]), grid=np.array([5, 5])))


def bad_fabric(tmp_path):
    text = open(os.path.join(SOURCE_DIR, "fabrics", "cotton.toml")).read()
    text, n = re.subn(r"(?m)^areal_density_mg_cm2\s*=.*$", "areal_density_mg_cm2 = -1", text)
    assert n == 1
    path = tmp_path / "bad_fabric.toml"
    path.write_text(text)
    return str(path)


def bad_scene(tmp_path):
    text = open(os.path.join(SOURCE_DIR, "scenes", "cube.toml")).read()
    text, n = re.subn(r"(?m)^grid\s*=.*$", "grid = [2, 2]", text)
    assert n == 1
    path = tmp_path / "bad_scene.toml"
    path.write_text(text)
    return str(path)


CASES = [
    (["drape", "cube", "--grid", "2"], lambda t: woven.drape("cube", grid=2)),
    (["drape", "cube", "--seed", "-1"], lambda t: woven.drape("cube", seed=-1)),
    (["drape", "cube", "--threads", "5000"], lambda t: woven.drape("cube", threads=5000)),
    (["drape", "cube", "--max-steps", "-3"], lambda t: woven.drape("cube", max_steps=-3)),
    (["drape", "cube", "--perturb", "1"], lambda t: woven.drape("cube", perturb=1.0)),
    (["drape", "cube", "--grid", "1.5"], lambda t: woven.drape("cube", grid=1.5)),
    (["drape", "nope"], lambda t: woven.drape("nope")),
    (["drape", "cube", "--fabric", "nope"], lambda t: woven.drape("cube", fabric="nope")),
    (["drape", "cube", "--fabric", "nope"], lambda t: woven.Fabric.load("nope")),
    (["drape", "cube", "--fabric", "BAD_FABRIC"], lambda t: woven.drape("cube", fabric=bad_fabric(t))),
    (["fit", "BAD_FABRIC"], lambda t: woven.Fabric.load(bad_fabric(t))),
    (["drape", "BAD_SCENE"], lambda t: woven.Scene.load(bad_scene(t))),
    (["drape", "BAD_SCENE"], lambda t: woven.drape(bad_scene(t))),
    (["drape", "cube", "--width", "0"], lambda t: woven.drape("cube", grid=5, max_steps=1).save(t / "o", width=0)),
    (["drape", "cube", "--out", ""], lambda t: woven.drape("cube", grid=5, max_steps=1).save("")),
    (["fit", "cotton", "--sigma-cm", "0"], lambda t: woven.fit("cotton", sigma_cm=0)),
    (["kes-test", "cotton", "--sigma-cm", "5"], lambda t: woven.kes_test("cotton", sigma_cm=5)),
    (["kes-test", "cotton", "--test", "tensile"], lambda t: woven.kes_test("cotton", test="tensile")),
    (["cusick", "cotton", "--specimen-cm", "-1"], lambda t: woven.cusick("cotton", specimen_cm=-1)),
    (["cusick", "cotton", "--seeds", "0"], lambda t: woven.cusick("cotton", seeds=0)),
    (["drape", "cube", "--hysteresis", "sticky"], lambda t: woven.drape("cube", hysteresis="sticky")),
    (["cusick", "cotton", "--hysteresis", "sticky"], lambda t: woven.cusick("cotton", hysteresis="sticky")),
    (["cusick", "cotton", "--protocol", "drop"], lambda t: woven.cusick("cotton", protocol="drop")),
    (["cusick", "cotton", "--shakes", "-1"], lambda t: woven.cusick("cotton", shakes=-1)),
]


@pytest.mark.parametrize("args,call", CASES, ids=[" ".join(a) for a, _ in CASES])
def test_bad_input_raises_the_commands_message(tmp_path, run_woven, args, call):
    args = [bad_fabric(tmp_path) if a == "BAD_FABRIC" else bad_scene(tmp_path) if a == "BAD_SCENE" else a for a in args]
    code, out, err = run_woven(*args)
    assert code == 2, err
    with pytest.raises(woven.InputError) as e:
        call(tmp_path)
    assert isinstance(e.value, ValueError)
    # The same message, a value named by the keyword that gave it where the command names its
    # option ("command line: --max-steps: ..." -> "max_steps: ...").
    expected = re.sub(r"^command line: --([a-z-]+): ", lambda m: m.group(1).replace("-", "_") + ": ", cli_error(err))
    assert str(e.value) == expected


def test_bad_values_raise_the_files_messages(tmp_path, run_woven):
    cotton = tomllib.load(open(os.path.join(SOURCE_DIR, "fabrics", "cotton.toml"), "rb"))
    code, out, err = run_woven("fit", bad_fabric(tmp_path))
    with pytest.raises(woven.InputError) as e:
        woven.Fabric(cotton, areal_density_mg_cm2=-1)
    # The same message, naming the values instead of the file (and no line).
    assert str(e.value) == "Python fabric: " + re.sub(r" \(line \d+\)$", "", cli_error(err).split(": ", 1)[1])
    for values, message in [
        (dict(cotton, name=None), "Python fabric: name: expected a value, got None (leave the key out for its default)"),
        (dict(cotton, name=object()), "Python fabric: name: expected a str, int, float, bool, list or dict, got object"),
        (dict(cotton, bending={1: 2}), "Python fabric: bending: expected str keys, got the int key 1"),
        (dict(cotton, thickness_mm=2**63), "Python fabric: thickness_mm: expected an integer within 64 bits (at most 9223372036854775807), got 9223372036854775808"),
        (dict(cotton, thickness_mm=-2**70), "Python fabric: thickness_mm: expected an integer within 64 bits (at most 9223372036854775807), got -1180591620717411303424"),
        (dict(cotton, thickness_mm=float("nan")), None),
    ]:
        with pytest.raises(woven.InputError) as e:
            woven.Fabric(values)
        if message:
            assert str(e.value) == message
        assert "\n" not in str(e.value)
    loop = []
    loop.append(loop)
    with pytest.raises(woven.InputError, match="nested more than 32 levels deep"):
        woven.Scene(cloth={"grid": loop})
    with pytest.raises(woven.InputError, match="^Python scene: expected a dict of the file's keys, got list$"):
        woven.Scene([1, 2])


def test_progress_gets_the_progress_lines_fields():
    calls = []
    result = woven.drape("cube", **SMALL, progress=calls.append)
    steps = [c for c in calls if c["event"] == "step"]
    iterations = [c for c in calls if c["event"] == "iteration"]
    assert [c["step"] for c in steps] == list(range(1, result.steps + 1))
    assert len(iterations) >= len(steps)
    assert set(steps[0]) == {"event", "step", "max_steps", "time_s", "energy_J", "residual", "tolerance", "move_m", "wall_s",
                             "fraction"}
    assert set(iterations[0]) == {"event", "step", "iteration", "total_iterations", "time_step_s", "residual", "tolerance", "wall_s"}
    assert all(0 <= c["fraction"] <= 1 for c in steps) and steps[-1]["fraction"] == 1.0
    assert steps[-1]["residual"] <= steps[-1]["tolerance"] == result.report["residual_tolerance"] if "residual_tolerance" in result.report else True
    assert steps[-1]["energy_J"] == pytest.approx(result.report["energy"]["total_J"], rel=1e-12)
    assert steps[-1]["max_steps"] == 400 and all(c["wall_s"] >= 0 for c in calls)


def check_interrupted(result, steps):
    assert result.interrupted and not result.converged and result.steps == steps
    assert result.report["interrupted"] is True and result.report["steps"] == steps and result.report["converged"] is False
    assert np.isfinite(result.positions).all() and math.isfinite(result.report["energy"]["total_J"])


def test_interrupt_from_the_callback_returns_the_state_reached(tmp_path):
    stop_at_3 = lambda p: not (p["event"] == "step" and p["step"] == 3)
    result = woven.drape("cube", **SMALL, progress=stop_at_3)
    check_interrupted(result, 3)
    # The state reached, as the command writes it: a complete set marked interrupted, no picture.
    written = result.save(tmp_path / "o")
    assert written["interrupted"] is True and sorted(written["files"]) == ["drape.glb", "drape.obj", "drape.ply"]
    np.testing.assert_allclose(obj_vertices(tmp_path / "o" / "drape.obj"), result.positions, rtol=1e-8, atol=1e-9)
    # The same steps again stop at the same state.
    again = woven.drape("cube", **SMALL, progress=stop_at_3)
    np.testing.assert_array_equal(again.positions, result.positions)


def test_ctrl_c_stops_the_drape_as_the_command():
    def keyboard_interrupt(p):
        if p["event"] == "step" and p["step"] == 2:
            raise KeyboardInterrupt

    check_interrupted(woven.drape("cube", **SMALL, progress=keyboard_interrupt), 2)

    def sigint(p):
        if p["event"] == "step" and p["step"] == 2:
            signal.raise_signal(signal.SIGINT)  # Ctrl-C: Python's handler raises KeyboardInterrupt

    check_interrupted(woven.drape("cube", **SMALL, progress=sigint), 2)


def test_an_error_in_the_callback_is_raised():
    with pytest.raises(ZeroDivisionError):
        woven.drape("cube", **SMALL, progress=lambda p: 1 / 0)
    with pytest.raises(TypeError):
        woven.drape("cube", **SMALL, progress=3)


def test_the_solver_releases_the_gil():
    done = []
    worker = threading.Thread(target=lambda: done.append(woven.drape("cube", grid=15, seed=1, threads=1)))
    counted = 0
    worker.start()
    while worker.is_alive():
        counted += 1
    worker.join()
    assert done and done[0].converged
    # Held through the solve, the loop would have run a few times at most.
    assert counted > 1000


def test_kes_test_cusick_and_fit_are_the_commands(tmp_path, run_woven):
    code, out, err = run_woven("kes-test", "cotton", "--test", "cantilever", "--direction", "warp", "--sigma-cm", "1", "--out", "k")
    assert code == 0, err
    cli = json.load(open(tmp_path / "k" / "kes-report.json"))
    py = woven.kes_test("cotton", test="cantilever", direction="warp", sigma_cm=1)
    assert py["tests"] == cli["tests"] and py["fabric"] == "cotton"
    code, out, err = run_woven("cusick", "cotton", "--spacing-cm", "2", "--threads", "1", "--no-render", "--out", "c")
    assert code == 0, err
    cli = json.load(open(tmp_path / "c" / "cusick.json"))
    py = woven.cusick(woven.Fabric.load("cotton"), spacing_cm=2, threads=1, render=False, out=tmp_path / "pc")
    assert py["drape_coefficient_percent"] == cli["drape_coefficient_percent"] and py["nodes"] == cli["nodes"]
    assert py["interrupted"] is False and (tmp_path / "pc" / "shadow.png").exists()
    py = woven.fit("wool", sigma_cm=1)
    assert py["fabric"] == "wool" and py["sigma_cm"] == 1 and "trellis" in py["summary"]


def test_install_puts_an_importable_package(tmp_path):
    build = os.environ.get("WOVEN_BUILD_DIR")
    cmake = os.environ.get("WOVEN_CMAKE", "cmake")
    if not build:
        pytest.skip("WOVEN_BUILD_DIR not set (ctest sets it)")
    subprocess.run([cmake, "--install", build, "--prefix", str(tmp_path)], check=True, capture_output=True)
    packages = [p for p in (tmp_path / "lib").glob("python3*/dist-packages")]
    assert len(packages) == 1 and (tmp_path / "bin" / "woven").exists()
    env = dict(os.environ, PYTHONPATH=str(packages[0]))
    p = subprocess.run([sys.executable, "-c", "import woven; print(woven.__file__, woven.Fabric.load('silk').G)"], env=env,
                       cwd=tmp_path, capture_output=True, text=True, check=True)
    assert p.stdout.startswith(str(packages[0])) and p.stdout.split()[1] == "0.25"


def test_the_readmes_example_runs_as_written(tmp_path, monkeypatch, capsys):
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    m = re.search(r"<!-- python-example[^>]*-->\n```python\n(.*?)```", readme, re.S)
    assert m, "README.md: no python-example block"
    monkeypatch.chdir(tmp_path)
    exec(compile(m.group(1), "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "grid: expected an integer in [3, 100000], got '2'" in out and "command line" not in out
    assert "(441, 3) (800, 3)" in out
    assert sorted(os.listdir(tmp_path / "out-python")) == ["drape.glb", "drape.obj", "drape.ply", "drape.png", "report.json"]


def test_the_cusick_example_plots(tmp_path):
    script = os.path.join(SOURCE_DIR, "examples", "cusick_three_fabrics.py")
    p = subprocess.run([sys.executable, script, "--spacing-cm", "2", "--out", str(tmp_path / "dc.png")], capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "dc.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(re.findall(r"DC \d+\.\d %", p.stdout)) == 3


def test_cusick_and_drape_take_the_hysteresis_and_protocol():
    # Friction inside the weave, the lowered protocol and a shake, as the command's options.
    c = woven.cusick("silk", specimen_cm=12, disc_cm=6, spacing_cm=1, threads=1, render=False, hysteresis="friction",
                     protocol="lowered", shakes=1)
    assert (c["hysteresis"], c["protocol"], c["shakes"], c["runs"][0]["stages"]) == ("friction", "lowered", 1, 5)
    r = woven.drape("cube", fabric="wool", grid=7, threads=1, max_steps=5, hysteresis="friction")
    assert r.report["model"]["hysteresis"] == "friction" and r.report["protocol"] == "drop"
