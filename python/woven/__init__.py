"""woven: drape of woven cloth from Kawabata (KES) measurements (Breen, House & Wozny 1994).

The library the `woven` command runs, from Python (README "Python"):

    import woven
    result = woven.drape("cube", fabric="cotton", grid=21, seed=1)
    result.positions          # (n, 3) float64, metres, z up
    result.report["energy_J"] # report.json as a dict
    result.save("out")        # drape.obj, drape.ply, drape.glb, drape.png, report.json

woven.fabrics(), woven.scenes(): the built-in names. woven.Fabric, woven.Scene: read from a file
or a built-in (load), or made from values with the files' keys. woven.kes_test, woven.cusick,
woven.fit: the virtual instruments. Bad input raises woven.InputError (a ValueError) with the
command's message; inputs read with a warning give woven.InputWarning.
"""
from ._woven import (
    DrapeResult,
    Error,
    Fabric,
    InputError,
    InputWarning,
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
    "DrapeResult",
    "Error",
    "Fabric",
    "InputError",
    "InputWarning",
    "Scene",
    "__version__",
    "cusick",
    "drape",
    "fabrics",
    "fit",
    "kes_test",
    "scenes",
]
