"""numpy in as well as out (issue 45 item 2): obstacles from arrays and constructors, a drape
stepped from Python with obstacles moved between steps, the testers' arrays and progress,
nothing on stdout, and the docstrings' examples run as written."""
import doctest
import os
import subprocess
import sys

import numpy as np
import pytest

import woven

BOX_V = np.array([[x, y, z] for z in (0, 0.5) for y in (-0.25, 0.25) for x in (-0.25, 0.25)], dtype=float)
# Outward, counter-clockwise seen from outside.
BOX_F = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4], [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6],
                  [1, 3, 5], [3, 7, 5]])


def cube_values(obstacles):
    return dict(name="numpy cube", cloth={"size_m": [1, 1], "grid": [9, 9], "height_m": 0.51, "fabric": "cotton"}, obstacle=obstacles)


def test_a_numpy_mesh_drapes_as_the_same_mesh_from_a_file(tmp_path):
    obj = tmp_path / "box.obj"
    obj.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in BOX_V) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in BOX_F))
    from_file = woven.Scene(cube_values([{"type": "plane"}, {"type": "mesh", "file": str(obj)}]))
    from_numpy = woven.Scene(cube_values([woven.Obstacle.plane(), woven.Obstacle.mesh(BOX_V, BOX_F)]))
    assert from_numpy.obstacles == ["plane", "mesh"]
    a = woven.drape(from_file, seed=1, threads=1)
    b = woven.drape(from_numpy, seed=1, threads=1)
    assert a.converged and b.converged
    np.testing.assert_array_equal(a.positions, b.positions)
    # A mesh obstacle answers distances as the solver sees them.
    m = woven.Obstacle.mesh(BOX_V, BOX_F)
    np.testing.assert_allclose(m.distance(np.array([[0, 0, 1.0], [0, 0, 0.25]])), [0.5, -0.25], atol=1e-12)
    np.testing.assert_array_equal(m.vertices, BOX_V)


def test_primitive_obstacles_are_the_scene_files():
    box = woven.Obstacle.box((0, 0, 0.25), (0.5, 0.5, 0.5))
    assert box.kind == "box" and box.values == {"type": "box", "centre_m": [0, 0, 0.25], "size_m": [0.5, 0.5, 0.5]}
    a = woven.drape(woven.Scene(cube_values([woven.Obstacle.plane(), box])), seed=1, threads=1)
    b = woven.drape(woven.Scene(cube_values([{"type": "plane"}, {"type": "box", "centre_m": [0, 0, 0.25], "size_m": [0.5, 0.5, 0.5]}])),
                    seed=1, threads=1)
    np.testing.assert_array_equal(a.positions, b.positions)
    s = woven.Obstacle.sphere(np.array([0, 0, 0.3]), 0.2)
    np.testing.assert_allclose(s.bounds, ((-0.2, -0.2, 0.1), (0.2, 0.2, 0.5)), atol=1e-15)
    assert woven.Obstacle.cylinder((0, 0, 0), 0.1, 0.3).kind == "cylinder"
    assert woven.Obstacle.disc((0, 0, 0.5), 0.09).kind == "disc"
    assert woven.Obstacle({"type": "sphere", "centre_m": [0, 0, 0], "radius_m": 1}).kind == "sphere"


@pytest.mark.parametrize("make,message", [
    (lambda: woven.Obstacle.sphere((0, 0, 0), -1), "Python obstacle: radius_m: expected a positive number in [0.0001, 1000] m, got -1"),
    (lambda: woven.Obstacle.mesh(BOX_V, BOX_F + 1), "Python obstacle: faces[3]: expected an integer in [0, 7], got 8"),
    (lambda: woven.Obstacle.mesh(BOX_V[:, :2], BOX_F), "Python obstacle: vertices_m[0]: expected [x, y, z] in m"),
    (lambda: woven.Obstacle.mesh(np.array([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]])), "Python obstacle: vertices_m[0]"),
    (lambda: woven.Obstacle({"radius_m": 1}), "Python obstacle: type: missing"),
])
def test_bad_obstacles_raise_the_readers_messages(make, message):
    with pytest.raises(woven.InputError) as e:
        make()
    assert str(e.value).startswith(message), str(e.value)


def test_a_stepped_drape_comes_to_rest_and_follows_a_moved_obstacle():
    whole = woven.drape("cube", fabric="cotton", grid=9, seed=1, threads=1)
    d = woven.Drape("cube", fabric="cotton", grid=9, seed=1, threads=1)
    assert d.steps == 0 and not d.converged and d.positions.shape == (81, 3)
    start = d.energy
    energies = []
    while not d.converged and d.steps < 100:
        d.step()
        energies.append(d.energy)
    assert d.converged and d.residual <= d.tolerance and d.energy < start
    assert d.steps == len(energies) == whole.steps and d.time_s > 0
    # Step by step, woven.drape's run bit for bit.
    np.testing.assert_array_equal(d.positions, whole.positions)
    assert energies[-1] == pytest.approx(whole.report["energy"]["total_J"], rel=1e-12)
    rest = d.positions.copy()
    # Lower the box by 10 cm: the cloth follows it down, and comes to rest again.
    d.obstacles = [woven.Obstacle.plane(), woven.Obstacle.box((0, 0, 0.2), (0.5, 0.5, 0.4))]
    assert not d.converged and d.obstacles == ["plane", "box"]
    while not d.converged and d.steps < 300:
        d.step(10)
    assert d.converged
    assert d.positions[:, 2].max() < rest[:, 2].max() - 0.08
    r = d.result()
    assert r.report["steps"] == d.steps and r.report["converged"] is True
    # An obstacle that a particle lies inside is refused; the drape keeps its obstacles.
    with pytest.raises(woven.InputError, match="lies inside an obstacle"):
        d.obstacles = [woven.Obstacle.box((0, 0, 0.5), (0.5, 0.5, 1.0))]
    assert d.obstacles == ["plane", "box"]


def test_a_stepped_drape_takes_every_keyword_drape_takes():
    # initial_positions and bias, as woven.drape takes them: the same run, bit for bit.
    flat = woven.drape("cube", grid=7, seed=1, threads=1, max_steps=3)
    start = flat.particles + np.array([0.0, 0.0, 0.01])
    whole = woven.drape("cube", grid=7, seed=1, threads=1, bias="fabric", initial_positions=start)
    d = woven.Drape("cube", grid=7, seed=1, threads=1, bias="fabric", initial_positions=start)
    np.testing.assert_array_equal(d.positions[:, 2] > flat.particles[:, 2], True)
    while not d.converged and d.steps < 100:
        d.step(5)
    assert d.steps == whole.steps
    np.testing.assert_array_equal(d.positions, whole.particles)
    assert d.result().report["start_sha256"] == whole.report["start_sha256"] != ""
    with pytest.raises(TypeError, match="Drape\\(\\): initial_positions"):
        woven.Drape("cube", grid=7, initial_positions=np.zeros(3))


def test_the_interpreter_exits_cleanly_in_the_middle_of_a_stepped_drape():
    # No worker thread: a Drape left mid-run at exit is an object like any other, with no
    # thread to stop or join while the interpreter finalises.
    code = "import woven\nd = woven.Drape('cube', grid=9, threads=1)\nd.step(2)\nprint(d.steps)"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "2"


def test_the_testers_return_arrays_take_progress_and_print_nothing(capfd):
    events = []
    k = woven.kes_test("cotton", test="cantilever", direction="warp", sigma_cm=1, threads=1, progress=events.append)
    assert events and all(e["event"] == "activity" and e["label"] == "kes-test cotton" for e in events)
    assert all(0 <= e["fraction"] <= 1 for e in events)
    curve = k["curves"]["cantilever_warp"]
    assert all(isinstance(v, np.ndarray) and v.dtype == np.float64 and len(v) > 3 for v in curve.values())
    steps = []
    c = woven.cusick("cotton", spacing_cm=2, threads=1, render=False, progress=lambda p: steps.append(p))
    assert any(p["event"] == "step" for p in steps)
    assert c["vertices"].ndim == 2 and c["vertices"].shape[1] == 3 and c["faces"].dtype == np.int32
    assert c["faces"].max() < len(c["vertices"])
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    # False from progress stops the Cusick run as Ctrl-C does.
    stopped = woven.cusick("cotton", spacing_cm=2, threads=1, render=False, progress=lambda p: p["event"] != "step")
    assert stopped["interrupted"] is True
    # The interpreter keeps its Ctrl-C: after cusick (whose command installs woven's own signal
    # handlers), SIGINT still raises KeyboardInterrupt and stops a drape.
    import signal

    def sigint(p):
        if p["event"] == "step" and p["step"] == 2:
            signal.raise_signal(signal.SIGINT)

    r = woven.drape("cube", grid=7, seed=1, threads=1, progress=sigint)
    assert r.interrupted and r.steps == 2


def test_the_docstrings_examples_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(woven, "woven", globs={})
    for obj in (woven.Obstacle, woven.Drape, woven.kes_test, woven.cusick):
        tests += finder.find(obj, obj.__name__, globs={})
    examples = sum(len(t.examples) for t in tests)
    assert examples >= 20
    for t in tests:
        runner.run(t)
    assert runner.summarize(verbose=False).failed == 0
