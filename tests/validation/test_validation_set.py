#!/usr/bin/python3
"""The measured-drape validation set (docs/validation/): its files agree with each other, the
conversions are the documented unit changes, every fabric file loads in woven, and the statistics
of scripts/validation.py give known values.

  test_validation_set.py ROOT WOVEN
"""
import csv
import os
import subprocess
import sys
import tomllib

ROOT, WOVEN = sys.argv[1], sys.argv[2]
VAL = os.path.join(ROOT, "docs", "validation")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import validation as v  # noqa: E402

fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


def close(a, b, rel, what):
    check(abs(a - b) <= rel * max(abs(a), abs(b)), f"{what}: {a} vs {b} (relative tolerance {rel})")


rows = list(csv.DictReader(open(os.path.join(VAL, "measured.csv"), newline="")))
check(sum(r["set"] == "main" for r in rows) >= 6, "at least six main-set fabrics")
for r in rows:
    n = r["name"]
    path = os.path.join(VAL, "fabrics", n + ".toml")
    check(os.path.exists(path), f"{n}: fabric file exists")
    with open(path, "rb") as f:
        t = tomllib.load(f)
    check(t["name"] == n, f"{n}: name in the file")
    check(r["set"] in ("main", "supplementary"), f"{n}: set")
    close(t["areal_density_mg_cm2"], float(r["W_mg_cm2"]), 1e-9, f"{n}: W")
    close(t["bending"]["warp"]["B"], float(r["B_warp_gf_cm2_cm"]), 1e-9, f"{n}: B warp")
    close(t["bending"]["weft"]["B"], float(r["B_weft_gf_cm2_cm"]), 1e-9, f"{n}: B weft")
    check(0 < float(r["dc_measured_percent"]) < 100, f"{n}: measured DC in (0, 100)")
    check(float(r["disc_cm"]) < float(r["specimen_cm"]), f"{n}: disc smaller than specimen")
    if r["set"] == "main":
        # every model input from the source: G given, no bracket; the CLO3D values convert by units
        check(r["G_gf_cm_deg"] != "" and r["G_bracket_gf_cm_deg"] == "", f"{n}: main set has a G and no bracket")
        close(t["shear"]["G"], float(r["G_gf_cm_deg"]), 1e-9, f"{n}: G")
        sv = r["source_values"]
        if "CLO3D" in sv:
            w = float(sv.split("W ")[1].split()[0])
            bw = float(sv.split("warp ")[1].split()[0])
            bf = float(sv.split("weft ")[1].split()[0])
            sh = float(sv.split("shear ")[1].split()[0])
            close(float(r["W_mg_cm2"]), w / 10, 1e-4, f"{n}: W = g/m2 / 10")
            close(float(r["B_warp_gf_cm2_cm"]), bw / 98066.5, 2e-3, f"{n}: B warp = g.mm2/s2 / 98066.5")
            close(float(r["B_weft_gf_cm2_cm"]), bf / 98066.5, 2e-3, f"{n}: B weft = g.mm2/s2 / 98066.5")
            close(float(r["G_gf_cm_deg"]), sh * 1e-3 / 56.19, 2e-3, f"{n}: G = g/s2 x 1e-3 / 56.19")
    else:
        # a missing input is bracketed, the file says so, and its G is the bracket's first value
        br = [float(x) for x in r["G_bracket_gf_cm_deg"].split(";")]
        check(len(br) >= 2 and r["G_gf_cm_deg"] == "", f"{n}: supplementary set has a bracket and no G")
        close(t["shear"]["G"], br[0], 1e-12, f"{n}: file G = first bracket value")
        check("NOT MEASURED" in open(path).read(), f"{n}: file says G is not measured")
        close(t["bending"]["warp"]["2HB"], float(r["twoHB_gf_cm_cm"]), 1e-9, f"{n}: 2HB")
    # woven reads the file (a fast virtual FB2 in the warp direction)
    p = subprocess.run([WOVEN, "kes-test", path, "--test", "bending", "--direction", "warp", "--sigma-cm", "0.5",
                        "--out", os.path.join(os.environ.get("TMPDIR", "/tmp"), "woven-validation-set-" + n)],
                       capture_output=True, text=True)
    check(p.returncode == 0, f"{n}: woven kes-test exit {p.returncode}: {p.stderr.strip()[:200]}")

# statistics
close(v.spearman([1, 2, 3, 4], [10, 20, 30, 40]), 1.0, 1e-12, "spearman of a monotone pair")
close(v.spearman([1, 2, 3, 4], [40, 30, 20, 10]), -1.0, 1e-12, "spearman of a reversed pair")
close(v.spearman([22.3, 22.8, 34.9, 28.6, 44.3, 54.9], [48.6, 45.7, 56.1, 48.8, 61.4, 72.1]), 1 - 6 * 2 / 210, 1e-12,
      "spearman with one swapped pair, n=6")
close(v.spearman_p_exact([1, 2, 3, 4, 5, 6], [1, 2, 3, 4, 5, 6]), 1 / 720, 1e-12, "exact p of a perfect ranking, n=6")
check(v.ranks([3, 1, 1, 2]) == [4.0, 1.5, 1.5, 3.0], "ranks with a tie")

if fails:
    print("\n".join("FAIL: " + f for f in fails))
    sys.exit(1)
print(f"validation set: {len(rows)} fabrics consistent; statistics ok")
