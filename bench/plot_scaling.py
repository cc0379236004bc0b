#!/usr/bin/env python3
"""Plot the scaling curve (bodies against nanoseconds per primary ray)
from a scaling.csv written by bench/compare.sh.

Usage: plot_scaling.py SCALING_CSV [OUT_PNG]   (default docs/scaling.png)
Needs matplotlib (pip install matplotlib).
"""
import csv
import os
import sys


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    src = argv[0]
    out = argv[1] if len(argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "docs", "scaling.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.stderr.write("plot_scaling.py: matplotlib is missing (pip install matplotlib)\n")
        return 1
    rows = list(csv.DictReader(open(src)))
    n = [int(r["bodies"]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    series = [("ours_ns_off", "SynthaVision, shadows off", "o-"),
              ("ours_ns_on", "SynthaVision, shadows on", "s-"),
              ("pov_ns_off", "POV-Ray 3.7 (trace time), shadows off", "^--")]
    for key, label, style in series:
        pts = [(x, float(r[key])) for x, r in zip(n, rows) if r.get(key)]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("spheres in the union (bodies)")
    ax.set_ylabel("ns per primary ray (one thread)")
    ax.set_title("Union of N random spheres, 960×720, one ray per pixel")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
