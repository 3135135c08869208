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
from ._woven import (
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
    "kes_test",
    "scenes",
]
