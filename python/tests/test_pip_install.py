"""`pip install .` (pyproject.toml, setup.py driving the project's CMake) into a fresh virtual
environment of Debian's python3, without the package index, then the README's example run with
that environment's python from an empty folder."""
import os
import re
import subprocess
import sys
import time

import pytest

from conftest import SOURCE_DIR


def test_pip_install_into_a_venv_runs_the_readme_example(tmp_path):
    build = os.environ.get("WOVEN_BUILD_DIR")
    if not build:
        pytest.skip("WOVEN_BUILD_DIR not set (ctest sets it): the install reuses that build folder's objects")
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = str(venv / "bin" / "python")
    env = dict(os.environ, WOVEN_CMAKE_BUILD_DIR=build)
    env.pop("PYTHONPATH", None)
    start = time.monotonic()
    p = subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir", SOURCE_DIR], env=env,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    print(f"pip install: {time.monotonic() - start:.1f} s")
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    example = re.search(r"<!-- python-example[^>]*-->\n```python\n(.*?)```", readme, re.S).group(1)
    run = tmp_path / "run"
    run.mkdir()
    (run / "example.py").write_text(example)
    p = subprocess.run([python, "example.py"], cwd=run, env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    assert "(441, 3) (800, 3)" in p.stdout
    where = subprocess.run([python, "-c", "import woven; print(woven.__file__)"], cwd=run, env=env, capture_output=True, text=True,
                           check=True).stdout.strip()
    assert where.startswith(str(venv)), where
    assert sorted(os.listdir(run / "out-python")) == ["drape.glb", "drape.obj", "drape.ply", "drape.png", "report.json"]
