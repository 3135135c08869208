#!/usr/bin/env python3
"""The hem-node count of `woven garment` runs, recounted independently and at other thresholds.

For each DIR/report.json given (or found under a folder): the hem's radius per 5-degree bin
(hem.radius_m) is searched for periodic peaks by scipy.signal.find_peaks (an implementation
independent of woven's analysis/peaks.cpp), at woven's own threshold (hem.min_prominence_m)
and at the others a reader might choose: a fraction f of the hem's reach beyond the waist
(f = 0.05, 0.1, 0.2, 0.3) and fixed heights (6, 10, 20, 40 mm; 6 mm is the Cusick count's).
Prints one Markdown table; exit 1 if scipy's count at woven's threshold differs from woven's.

Usage: scripts/garment_hem_nodes.py DIR_OR_REPORT...
"""
import json
import os
import sys

import numpy as np
from scipy.signal import find_peaks

FRACTIONS = (0.05, 0.1, 0.2, 0.3)
FIXED_MM = (6, 10, 20, 40)


def periodic_peak_count(r, min_prominence):
    """Peaks of a periodic sequence: found in three copies side by side, kept in the middle one."""
    n = len(r)
    tiled = np.concatenate([r, r, r])
    peaks, _ = find_peaks(tiled, prominence=min_prominence, plateau_size=1)
    return int(np.sum((peaks >= n) & (peaks < 2 * n)))


def reports(args):
    for a in args:
        if os.path.isfile(a):
            yield a
        else:
            for root, _, files in sorted(os.walk(a)):
                if "report.json" in files:
                    path = os.path.join(root, "report.json")
                    with open(path) as f:
                        if json.load(f).get("command") == "garment":
                            yield path


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    header = ["run", "spacing (cm)", "reach (cm)", "woven", "scipy at woven's"]
    header += [f"{f:g} reach" for f in FRACTIONS] + [f"{mm} mm" for mm in FIXED_MM]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    disagree = 0
    for path in reports(argv[1:]):
        with open(path) as f:
            rep = json.load(f)
        hem = rep["hem"]
        r = np.asarray(hem["radius_m"], dtype=float)
        reach = hem["mean_radius_m"] - rep["waist"]["radius_m"]
        ours = periodic_peak_count(r, hem["min_prominence_m"])
        disagree += ours != hem["nodes"]
        row = [os.path.basename(os.path.dirname(os.path.abspath(path))), f"{100 * rep['spacing_m']:g}", f"{100 * reach:.1f}",
               str(hem["nodes"]), str(ours)]
        # No reach (a tube hanging straight): a fraction of it is no threshold.
        row += [str(periodic_peak_count(r, f * reach)) if reach > 0 else "-" for f in FRACTIONS]
        row += [str(periodic_peak_count(r, mm * 1e-3)) for mm in FIXED_MM]
        print("| " + " | ".join(row) + " |")
    if disagree:
        print(f"{disagree} run(s): scipy's count at woven's threshold differs from woven's", file=sys.stderr)
    return 1 if disagree else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
