#!/usr/bin/python3
"""Run the measured-drape validation set (docs/validation/README.md) and write its table and plot.

For every fabric in docs/validation/measured.csv: `woven cusick docs/validation/fabrics/<name>.toml
--seeds K` at the documented default spacing and specimen (30 cm on an 18 cm disc), then one table
row with the measured and simulated drape coefficient (DC) and nodes. Writes
docs/validation/table.md and docs/validation/dc_measured_vs_simulated.png.

No tuning: the fabric files hold the published values and nothing else, and no constant of the
model is fitted to this set, so the leave-one-out error of every fabric is its error itself.

  nice -n 19 /usr/bin/python3 scripts/validation.py [--woven build/woven] [--seeds 2] [--out out/validation]
  /usr/bin/python3 scripts/validation.py --table-only   # rebuild table and plot from --out
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VAL = os.path.join(ROOT, "docs", "validation")


def ranks(values):
    """Ranks 1..n, ties get the mean of their ranks."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    r = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return r


def pearson(a, b):
    ma, mb = sum(a) / len(a), sum(b) / len(b)
    num = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    den = math.sqrt(sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b))
    return num / den if den > 0 else float("nan")


def spearman(a, b):
    return pearson(ranks(a), ranks(b))


def run_fabric(woven, name, seeds, out):
    fabric = os.path.join(VAL, "fabrics", name + ".toml")
    d = os.path.join(out, name)
    cmd = [woven, "cusick", fabric, "--seeds", str(seeds), "--threads", "1", "--no-render", "--out", d]
    t0 = time.time()
    with open(os.path.join(out, name + ".log"), "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    if rc != 0:
        sys.exit(f"validation: {name}: `{' '.join(cmd)}` exited {rc}; see {out}/{name}.log")
    print(f"{name}: {time.time() - t0:.0f} s", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--woven", default=os.path.join(ROOT, "build", "woven"))
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "validation"))
    ap.add_argument("--table-only", action="store_true", help="do not run woven; use the cusick.json already in --out")
    a = ap.parse_args()

    with open(os.path.join(VAL, "measured.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    os.makedirs(a.out, exist_ok=True)
    if not a.table_only:
        for r in rows:
            run_fabric(a.woven, r["name"], a.seeds, a.out)

    res = []
    for r in rows:
        path = os.path.join(a.out, r["name"], "cusick.json")
        with open(path) as f:
            j = json.load(f)
        dcs = [run["drape_coefficient_percent"] for run in j["runs"]]
        nodes = [run["nodes"] for run in j["runs"]]
        res.append(dict(r=r, dc=sum(dcs) / len(dcs), dcs=dcs, nodes=nodes, conv=j["converged"],
                        spacing=j["spacing_m"], spec=j["specimen_diameter_m"], disc=j["disc_diameter_m"],
                        version=j.get("version", "?")))

    meas = [float(x["r"]["dc_measured_percent"]) for x in res]
    sim = [x["dc"] for x in res]
    clo = [float(x["r"]["dc_clo3d_percent"]) for x in res]
    err = [s - m for s, m in zip(sim, meas)]
    mae = sum(abs(e) for e in err) / len(err)
    bias = sum(err) / len(err)
    rho = spearman(meas, sim)
    mae_clo = sum(abs(c - m) for c, m in zip(clo, meas)) / len(meas)
    rho_clo = spearman(meas, clo)
    seeds = len(res[0]["dcs"])
    r0 = res[0]

    L = []
    L.append("# Measured drape against woven's Cusick test\n")
    L.append("Written by `scripts/validation.py` (sources, conversions and assumptions: docs/validation/README.md).")
    L.append(f"woven {r0['version']}, `woven cusick FILE --seeds {seeds} --threads 1 --no-render`: specimen "
             f"{r0['spec'] * 100:.0f} cm on a {r0['disc'] * 100:.0f} cm disc, spacing {r0['spacing'] * 100:g} cm "
             f"(the default), seeds 1-{seeds}. Simulated DC: mean over the seeds.\n")
    L.append("| fabric | W mg/cm2 | B warp / weft gf.cm2/cm | G gf/(cm.deg) | DC measured % | DC woven % (per seed) | error | nodes woven (per seed) | nodes measured | DC CLO3D % (published) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    for x, e in zip(res, err):
        r = x["r"]
        per = " ".join(f"{d:.1f}" for d in x["dcs"])
        conv = "" if x["conv"] else " (not all converged)"
        nm = r["nodes_measured"] or "not given"
        L.append(f"| {r['name']} ({r['petrak_fabric']}) | {float(r['W_mg_cm2']):.2f} | {float(r['B_warp_gf_cm2_cm']):.4f} / "
                 f"{float(r['B_weft_gf_cm2_cm']):.4f} | {float(r['G_gf_cm_deg']):.3f} | {float(r['dc_measured_percent']):.1f} | "
                 f"**{x['dc']:.1f}** ({per}){conv} | {e:+.1f} | {' '.join(map(str, x['nodes']))} | {nm} | {float(r['dc_clo3d_percent']):.1f} |")
    L.append("")
    L.append("| measure | woven | CLO3D (Petrak et al.'s own simulation, for reference) |")
    L.append("|---|---|---|")
    L.append(f"| mean absolute DC error, points | **{mae:.1f}** | {mae_clo:.1f} |")
    L.append(f"| mean signed error (simulated - measured), points | {bias:+.1f} | {sum(c - m for c, m in zip(clo, meas)) / len(meas):+.1f} |")
    L.append(f"| largest absolute error, points | {max(abs(e) for e in err):.1f} | {max(abs(c - m) for c, m in zip(clo, meas)):.1f} |")
    L.append(f"| Spearman rank correlation with the measured DC | **{rho:.2f}** | {rho_clo:.2f} |")
    L.append(f"| simulated DC range / measured range, points | {max(sim) - min(sim):.1f} / {max(meas) - min(meas):.1f} | {max(clo) - min(clo):.1f} / {max(meas) - min(meas):.1f} |")
    L.append("")
    L.append("No constant of the model was fitted to this set, so each fabric's leave-one-out error equals its error above.")
    L.append("Nodes: the source as read gives no measured node counts.\n")
    L.append("![simulated against measured DC](dc_measured_vs_simulated.png)")
    with open(os.path.join(VAL, "table.md"), "w") as f:
        f.write("\n".join(L) + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.2, 5.0), dpi=120)
    lo, hi = 0, 100
    ax.plot([lo, hi], [lo, hi], color="0.6", lw=1, label="simulated = measured")
    ax.fill_between([lo, hi], [lo - 2, hi - 2], [lo + 2, hi + 2], color="0.9", label="+-2 points (test repeatability)")
    for x in res:
        m = float(x["r"]["dc_measured_percent"])
        ax.plot([m] * len(x["dcs"]), x["dcs"], ".", color="tab:blue", alpha=0.4, ms=5)
    ax.plot(meas, sim, "o", color="tab:blue", label=f"woven (mean of {seeds} seeds): MAE {mae:.1f}, rho {rho:.2f}")
    ax.plot(meas, clo, "s", mfc="none", color="tab:orange", label=f"CLO3D (published): MAE {mae_clo:.1f}, rho {rho_clo:.2f}")
    for x in res:
        ax.annotate(x["r"]["petrak_fabric"], (float(x["r"]["dc_measured_percent"]), x["dc"]), textcoords="offset points",
                    xytext=(5, -3), fontsize=8)
    top = max(max(sim), max(clo), max(meas)) + 10
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.set_xlabel("measured drape coefficient, %")
    ax.set_ylabel("simulated drape coefficient, %")
    ax.set_title("Cusick DC: Petrak et al. (2025) fabrics M1-M6", fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(VAL, "dc_measured_vs_simulated.png"))
    print(f"MAE {mae:.2f} points, Spearman {rho:.3f} (CLO3D: {mae_clo:.2f}, {rho_clo:.3f}); wrote docs/validation/table.md")


if __name__ == "__main__":
    main()
