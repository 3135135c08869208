"""A drape started from given positions (issue 43 item 1): initial_positions= takes an (n, 3)
array, its SHA-256 goes into the report, a wrong shape is refused; and bias bending by name."""
import hashlib

import numpy as np
import pytest

import woven


def test_a_drape_started_from_its_own_rest_stays_there():
    first = woven.drape("sphere", grid=9, seed=1, threads=1, perturb=0)
    assert first.converged and first.report["start_sha256"] == ""
    start = np.ascontiguousarray(first.particles, dtype=np.float64)
    again = woven.drape("sphere", grid=9, seed=1, threads=1, perturb=0, initial_positions=start)
    assert again.report["start_sha256"] == hashlib.sha256(start.tobytes()).hexdigest()
    e = first.report["energy"]["total_J"]
    assert again.report["energy_initial_J"] == pytest.approx(e, rel=1e-12)
    assert again.report["energy"]["total_J"] == pytest.approx(e, rel=1e-6)
    assert again.steps <= first.steps


def test_initial_positions_of_another_grid_or_shape_are_refused():
    with pytest.raises(woven.InputError, match="initial_positions: shape: expected 81 rows"):
        woven.drape("sphere", grid=9, threads=1, initial_positions=np.zeros((80, 3)))
    with pytest.raises(TypeError, match=r"\(n, 3\) array"):
        woven.drape("sphere", grid=9, threads=1, initial_positions=np.zeros((81, 2)))
    bad = np.zeros((81, 3))
    bad[:, 2] = 2.0  # above the sphere
    bad[5, 1] = np.nan
    with pytest.raises(woven.InputError, match=r"initial_positions: values: row 5: expected finite positions \(m\)"):
        woven.drape("sphere", grid=9, threads=1, initial_positions=bad)


def test_initial_positions_are_checked_as_the_flat_start_is():
    # Issue 53 item 2: inside an obstacle (here on the floor) or beyond the scene's bounds was
    # draped; rows are counted from 0, as numpy counts them.
    start = np.zeros((81, 3))
    start[:, 2] = 2.0
    floor = start.copy()
    floor[3, 2] = -0.01
    with pytest.raises(woven.InputError, match=r"initial_positions: values: row 3: the position \(0, 0, -0.01\) m lies inside or touches obstacle\[1\] \(plane\)"):
        woven.drape("sphere", grid=9, threads=1, initial_positions=floor)
    far = start.copy()
    far[80, 0] = 1e7
    with pytest.raises(woven.InputError, match=r"row 80: the position \(10000000, 0, 2\) m lies outside the scene's bounds"):
        woven.drape("sphere", grid=9, threads=1, initial_positions=far)


def test_bias_bending_is_an_option():
    r = woven.drape("sphere", grid=9, seed=1, threads=1, bias="fabric")
    assert r.report["model"]["bias_bending"] == "fabric" and r.report["energy"]["twist_J"] > 0
    with pytest.raises(woven.InputError, match="^bias: expected"):
        woven.drape("sphere", grid=9, threads=1, bias="diagonal")


@pytest.mark.parametrize("call, message", [
    (lambda: woven.drape("cube", grid=2), "grid: expected an integer in [3, 100000], got '2'"),
    (lambda: woven.drape("cube", grid=2 ** 70), "grid: expected an integer in [3, 100000], got '1180591620717411303424'"),
    (lambda: woven.drape("cube", grid=True), "grid: expected an integer in [3, 100000], got 'True'"),
    (lambda: woven.drape("cube", max_steps=-1), "max_steps: expected an integer in [0, 1000000000], got '-1'"),
    (lambda: woven.drape("cube", perturb=0.5), "perturb: expected a number in [0, 0.01], got '0.5'"),
    (lambda: woven.Drape("cube", threads=-1), "threads: expected an integer in [0, 4096], got '-1'"),
    (lambda: woven.cusick("cotton", seeds=0), "seeds: expected an integer in [1, "),
    (lambda: woven.cusick("cotton", specimen_cm=-3), "specimen_cm: expected a number in (0, "),
    (lambda: woven.cusick("cotton", modes=[3], render=False), "modes: expected only with"),
    (lambda: woven.cusick("cotton", search=True, modes=[5, 3], render=False), "modes: expected"),
    (lambda: woven.cusick("cotton", clamp="glue", render=False), "clamp: expected"),
])
def test_errors_name_the_python_keyword(call, message):
    # The command names its option (command line: --grid: ...); Python the keyword.
    with pytest.raises(woven.InputError) as e:
        call()
    assert str(e.value).startswith(message), str(e.value)


def test_cusick_takes_every_option_of_the_command():
    # search, modes and jobs; bias; clamp: as `woven cusick` takes them.
    r = woven.cusick("cotton", spacing_cm=3, threads=1, render=False, search=True, modes=[3], jobs=1, bias="fabric",
                     clamp="discs")
    assert r["runs"] and 0 < r["drape_coefficient_percent"] < 100
    assert len(r["runs"][0]["states"]) >= 2  # the release and the start on 3 guides (and their continuations)


def test_cusick_takes_the_path_and_the_threads_of_the_command():
    # solver, discretization, fall_s, thread_compression, grid_rotation_deg: recorded in the report.
    r = woven.cusick("cotton", spacing_cm=3, threads=1, render=False, fall_s=0.5, thread_compression=0.25,
                     grid_rotation_deg=30)
    assert r["solver"] == "fast" and r["discretization"] == "convergent"
    assert r["fall_duration_s"] == 0.5 and r["thread_compression"] == 0.25 and r["grid_rotation_deg"] == 30
    with pytest.raises(woven.InputError) as e:
        woven.cusick("cotton", spacing_cm=3, threads=1, render=False, thread_compression=2)
    assert str(e.value).startswith("thread_compression: "), str(e.value)
    with pytest.raises(woven.InputError) as e:
        woven.cusick("cotton", spacing_cm=3, threads=1, render=False, solver="newton")
    assert str(e.value).startswith("solver: "), str(e.value)
