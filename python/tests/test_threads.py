"""Calls from several Python threads: each returns what it returns alone, and the process never
crashes (the commands' printing, the interrupt poll and the thread counts are process-wide, so
calls run one at a time; python/src/bindings.hpp CallLock)."""
import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

import woven

SCRIPT = textwrap.dedent("""
    import sys, threading, warnings
    import numpy as np
    import woven
    alone = woven.drape("cube", grid=9, seed=1, threads=1).positions
    fit = woven.fit("wool", sigma_cm=1)["summary"]
    results, errors = [], []
    def work(k):
        try:
            for n in range(3):
                if (k + n) % 3 == 2:
                    results.append(("fit", woven.fit("wool", sigma_cm=1)["summary"]))
                else:
                    results.append(("drape", woven.drape("cube", grid=9, seed=1, threads=1,
                                                         progress=lambda p: None).positions))
        except BaseException as e:
            errors.append(repr(e))
    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads: t.start()
    for t in threads: t.join()
    assert not errors, errors
    assert len(results) == 6, len(results)
    for kind, value in results:
        if kind == "drape":
            assert np.array_equal(value, alone)
        else:
            assert value == fit, value
    print("ok", len(results))
""")


@pytest.mark.parametrize("run", range(3))
def test_two_threads_never_crash(run):
    # In a fresh interpreter each time: the crash this guards against came at exit.
    p = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])
    assert p.stdout.split() == ["ok", "6"]
    assert p.stderr == ""  # nothing printed past the capture


def test_a_call_from_a_progress_callback_is_refused():
    seen = []

    def nested(p):
        if p["event"] == "step" and not seen:
            with pytest.raises(woven.Error, match="inside a progress callback"):
                woven.drape("cube", grid=5, max_steps=1)
            seen.append(True)

    result = woven.drape("cube", grid=7, seed=1, threads=1, progress=nested)
    assert seen and result.converged


def test_a_waiting_call_runs_after_the_running_one():
    # A slow drape holds the lock; a second thread's call waits, then runs; both as alone.
    alone = woven.drape("cube", grid=9, seed=1, threads=1).positions
    started = threading.Event()
    order = []

    def slow(p):
        started.set()

    def first():
        woven.drape("cube", grid=15, seed=1, threads=1, progress=slow)
        order.append("first")

    t = threading.Thread(target=first)
    t.start()
    started.wait(30)
    second = woven.drape("cube", grid=9, seed=1, threads=1).positions
    order.append("second")
    t.join()
    assert order == ["first", "second"]
    np.testing.assert_array_equal(second, alone)
