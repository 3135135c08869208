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
