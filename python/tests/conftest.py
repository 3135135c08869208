"""Shared by the module's tests: the `woven` binary and the source tree, from the environment
ctest sets (python/CMakeLists.txt), and a helper that runs the binary."""
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("WOVEN_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ.get("WOVEN_BINARY", os.path.join(SOURCE_DIR, "build", "woven"))


@pytest.fixture
def run_woven(tmp_path):
    """Runs `woven ARGS...` in tmp_path; returns (exit code, stdout, stderr)."""

    def run(*args):
        p = subprocess.run([BINARY, *map(str, args)], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        return p.returncode, p.stdout, p.stderr

    return run
