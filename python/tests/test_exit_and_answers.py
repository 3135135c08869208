"""Issue 53 item 6: a woven call on a daemon thread when the interpreter exits (SIGABRT
"exception not rethrown", once SIGSEGV: woven.drape 4 of 9), a progress callable answering
numpy's False or 0 (the run went on), a numpy mesh obstacle without a limit (2 M faces: 2.1 GB,
43 s) and its rows counted from 1."""
import subprocess
import sys
import time

import numpy as np
import pytest

import woven

EXIT_SCRIPT = """
import threading, time, woven
def run():
    {call}
threading.Thread(target=run, daemon=True).start()
time.sleep({wait})
"""


@pytest.mark.parametrize("call", [
    'woven.drape("cube", fabric="cotton", grid=41, seed=1, threads=1, progress=lambda i: True)',
    'woven.drape("cube", fabric="cotton", grid=41, seed=1, threads=1)',
])
def test_the_interpreter_exits_cleanly_while_a_daemon_thread_is_in_woven(call, tmp_path):
    for wait in (0.3, 0.8, 1.5):
        r = subprocess.run([sys.executable, "-c", EXIT_SCRIPT.format(call=call, wait=wait)], cwd=tmp_path, capture_output=True,
                           text=True, timeout=120)
        assert r.returncode == 0, (wait, r.returncode, r.stderr[-2000:])


@pytest.mark.parametrize("answer", [np.False_, 0, np.int64(0), False, np.array(False)])
def test_a_falsy_progress_answer_stops_the_drape(answer):
    r = woven.drape("cube", fabric="cotton", grid=9, seed=1, threads=1, progress=lambda info: answer)
    assert r.interrupted and r.steps <= 1


@pytest.mark.parametrize("answer", [None, True, np.True_, 1])
def test_a_truthy_or_none_answer_goes_on(answer):
    r = woven.drape("cube", fabric="cotton", grid=9, seed=1, threads=1, progress=lambda info: answer)
    assert r.converged and not r.interrupted


def test_a_numpy_mesh_beyond_the_row_limit_is_refused_before_it_is_converted():
    n = 200_001
    v = np.zeros((n, 3))
    f = np.zeros((10, 3), dtype=np.int32)
    t = time.monotonic()
    with pytest.raises(woven.InputError, match=r"Python obstacle: vertices_m: expected at most 200000 rows .*, got 200001"):
        woven.Obstacle.mesh(v, f)
    with pytest.raises(woven.InputError, match=r"Python obstacle: faces: expected at most 200000 rows"):
        woven.Obstacle({"type": "mesh", "vertices_m": np.zeros((3, 3)), "faces": np.zeros((2_000_000, 3), dtype=np.int32)})
    assert time.monotonic() - t < 2.0


DRAPE_STEP_KEYS = {"event", "step", "max_steps", "time_s", "energy_J", "residual", "tolerance", "move_m", "wall_s", "fraction"}
DRAPE_ITERATION_KEYS = {"event", "step", "iteration", "total_iterations", "time_step_s", "residual", "tolerance", "wall_s"}


def test_cusick_sends_each_newton_iteration_as_drape_does():
    calls = []
    c = woven.cusick("cotton", spacing_cm=3, threads=1, render=False, progress=calls.append)
    steps = [p for p in calls if p["event"] == "step"]
    iterations = [p for p in calls if p["event"] == "iteration"]
    assert not c["interrupted"] and steps
    # At least one Newton iteration before each step ends, with woven.drape's keys.
    assert len(iterations) >= len(steps)
    assert all(set(p) == DRAPE_STEP_KEYS for p in steps)
    assert all(set(p) == DRAPE_ITERATION_KEYS for p in iterations)
    assert iterations[0]["step"] == 1 and iterations[0]["iteration"] == 0  # counted from 0, as drape counts them
    assert all(p["total_iterations"] >= p["iteration"] >= 0 and p["time_step_s"] > 0 and p["tolerance"] > 0 for p in iterations)
    # The first iteration comes before the first step's end.
    assert calls.index(iterations[0]) < calls.index(steps[0])


@pytest.mark.parametrize("answer", [np.False_, 0, np.int64(0), False])
def test_a_falsy_answer_to_a_cusick_iteration_stops_the_run(answer):
    calls = []

    def progress(p):
        calls.append(p["event"])
        return answer if p["event"] == "iteration" else None

    c = woven.cusick("cotton", spacing_cm=3, threads=1, render=False, progress=progress)
    assert c["interrupted"] is True
    assert calls.count("iteration") == 1 and "step" not in calls, calls[:10]


DAEMON_AT_EXIT = {
    # The main thread exits at once, while the daemon thread is before, in or after its call.
    "cusick": 'threading.Thread(target=lambda: woven.cusick("cotton", spacing_cm=2, seeds=1, threads=1, render=False), daemon=True).start()',
    # Fabric and Scene readers release the GIL outside any call's lock.
    "loads": "def run():\n    while True:\n        woven.Fabric.load('cotton'); woven.Scene.load('cube')\n"
             "threading.Thread(target=run, daemon=True).start()\ntime.sleep(0.05)",
}


@pytest.mark.parametrize("what", sorted(DAEMON_AT_EXIT))
def test_the_interpreter_exits_cleanly_when_a_daemon_thread_is_in_woven_as_it_exits(what, tmp_path):
    # Before the fix: cusick 16 of 20 such exits ended in SIGABRT ("PyThreadState_Get: the
    # function must be called with the GIL held") or SIGSEGV; the loads 18 of 20 in SIGABRT.
    outcomes = []
    for _ in range(10):
        r = subprocess.run([sys.executable, "-c", "import threading, time, woven\n" + DAEMON_AT_EXIT[what]], cwd=tmp_path,
                           capture_output=True, text=True, timeout=60)
        outcomes.append((r.returncode, r.stderr[-300:]))
    assert all(code == 0 for code, _ in outcomes), outcomes
