#!/usr/bin/python3
"""Drapes three fabrics in the virtual Cusick drape tester and plots their drape coefficients.

    PYTHONPATH=build/python python3 examples/cusick_three_fabrics.py            # the tester's 0.5 cm spacing
    PYTHONPATH=build/python python3 examples/cusick_three_fabrics.py --spacing-cm 1.5 --out dc.png

The drape coefficient DC is the shadow's area outside the 18 cm disc over the 30 cm specimen's
(BS 5058): 100 % hangs straight down, 0 % stays flat. Each fabric is draped from --seeds
perturbed starts; the bar is their mean, the points the runs.
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

import woven


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("fabrics", nargs="*", default=["silk", "cotton", "denim"], help="built-in names or fabric .toml files")
    parser.add_argument("--spacing-cm", type=float, default=None, help="particle spacing (default: the command's, 0.5 cm)")
    parser.add_argument("--seeds", type=int, default=1, help="runs per fabric")
    parser.add_argument("--out", default="cusick_three_fabrics.png", help="the plot (PNG)")
    args = parser.parse_args()

    names, means, runs = [], [], []
    for name in args.fabrics:
        fabric = woven.Fabric.load(name)
        report = woven.cusick(fabric, spacing_cm=args.spacing_cm, seeds=args.seeds, render=False)
        dcs = [run["drape_coefficient_percent"] for run in report["runs"]]
        names.append(f"{fabric.name}\nB {fabric.B_warp:.3g}/{fabric.B_weft:.3g}, G {fabric.G:.3g}")
        means.append(sum(dcs) / len(dcs))
        runs.append(dcs)
        print(f"{fabric.name}: DC {means[-1]:.1f} %, {report['nodes']} nodes")

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.bar(range(len(names)), means, color="#8aa8c8")
    for k, dcs in enumerate(runs):
        ax.plot([k] * len(dcs), dcs, "k.")
    ax.set_xticks(range(len(names)), names, fontsize=8)
    ax.set_ylabel("drape coefficient (%)")
    ax.set_ylim(0, 100)
    ax.set_title("Cusick drape test, simulated (woven)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
