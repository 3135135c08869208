"""woven.garment (issue 54): a garment file's pieces cut on the grain, sewn and draped on the dress
form, its report.json back as a dict; bad values refused with woven.InputError."""
import os

import pytest

import woven

SOURCE = os.path.join(os.path.dirname(__file__), "..", "..")
TUBE = os.path.join(SOURCE, "examples", "garments", "tube-skirt.toml")


def test_a_tube_skirt_drapes_closed_and_hangs_straight(tmp_path):
    r = woven.garment(TUBE, spacing_cm=4, threads=1, render=False, out=str(tmp_path))
    assert r["converged"] and not r["interrupted"]
    # The seams stay closed: far below the target of a tenth of the spacing.
    assert r["seam_max_gap_over_spacing"] < 0.01
    # A tube hangs straight down: its hem as wide as its waist, within 2 %.
    assert r["hem"]["flare"] == pytest.approx(1.0, abs=0.02)
    assert r["spacing_m"] == pytest.approx(0.04)
    # The memory the run was checked against before it started, bytes (docs/GARMENT-FORMAT.md).
    assert isinstance(r["memory_estimate_bytes"], int) and r["memory_estimate_bytes"] > 0
    assert sorted(os.listdir(tmp_path)) == ["garment.glb", "report.json"]


def test_bad_values_and_missing_files_are_input_errors(tmp_path):
    with pytest.raises(woven.InputError, match=r"expected a number in \[0.2, 10\], got '-1'"):
        woven.garment(TUBE, spacing_cm=-1, out=str(tmp_path))
    with pytest.raises(woven.InputError, match="no such garment file"):
        woven.garment(str(tmp_path / "nope.toml"), out=str(tmp_path))


def test_a_bad_spacing_is_named_by_its_keyword(tmp_path):
    # The command's option is --spacing; Python's keyword is spacing_cm, and the error says so.
    with pytest.raises(woven.InputError) as e:
        woven.garment(TUBE, spacing_cm=-1, out=str(tmp_path))
    assert str(e.value) == "spacing_cm: expected a number in [0.2, 10], got '-1'"
    with pytest.raises(woven.InputError) as e:
        woven.garment(TUBE, spacing_cm="wide", out=str(tmp_path))
    assert str(e.value) == "spacing_cm: expected a number in [0.2, 10], got 'wide'"
