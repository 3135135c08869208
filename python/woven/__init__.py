"""woven: drape of woven cloth from Kawabata (KES) measurements (Breen, House & Wozny 1994).

The library the `woven` command runs, from Python (README "Python"):

>>> import woven
>>> result = woven.drape("cube", fabric="cotton", grid=11, seed=1, threads=1)
>>> result.positions.shape              # (n, 3) float64, metres, z up
(121, 3)
>>> result.converged, result.report["steps"] == result.steps   # report.json as a dict
(True, True)
>>> sorted(result.save("out", render=False)["files"])  # and drape.png unless render=False
['drape.glb', 'drape.obj', 'drape.ply']

woven.fabrics(), woven.scenes(): the built-in names. woven.Fabric, woven.Scene: read from a file
or a built-in (load), or made from values with the files' keys; woven.Obstacle: a numpy mesh,
box, sphere, cylinder, disc or plane for a scene's obstacle list. woven.Drape: a drape stepped
from Python, its obstacles movable between steps. woven.kes_test, woven.cusick,
woven.fit: the virtual instruments. Bad input raises woven.InputError (a ValueError) with the
command's message, a value named by its keyword (grid: ...); inputs read with a warning give woven.InputWarning.
"""
import os as _os
import resource as _resource


def _one_blas_thread_under_a_memory_limit():
    # Under an address-space or data limit (a scheduler's `ulimit -v`), OpenBLAS's threads,
    # started as the library loads, may fail to map their buffers and spin for ever: the
    # interpreter then never exits (issue 53). woven runs its BLAS on one thread; OpenBLAS reads
    # OPENBLAS_NUM_THREADS once, as it loads (here, with the extension, unless already loaded).
    limited = any(_resource.getrlimit(r)[0] != _resource.RLIM_INFINITY for r in (_resource.RLIMIT_AS, _resource.RLIMIT_DATA))
    if limited and _os.environ.get("OPENBLAS_NUM_THREADS") != "1":
        _os.environ["OPENBLAS_NUM_THREADS"] = "1"


_one_blas_thread_under_a_memory_limit()

from ._woven import (  # noqa: E402
    Drape,
    DrapeResult,
    Error,
    Fabric,
    InputError,
    InputWarning,
    Obstacle,
    Scene,
    __version__,
    cusick,
    drape,
    fabrics,
    fit,
    garment,
    kes_test,
    scenes,
)

__all__ = [
    "Drape",
    "DrapeResult",
    "Error",
    "Fabric",
    "InputError",
    "InputWarning",
    "Obstacle",
    "Scene",
    "__version__",
    "cusick",
    "drape",
    "fabrics",
    "fit",
    "garment",
    "kes_test",
    "scenes",
]
