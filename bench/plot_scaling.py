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
    fig, ax = plt.subplots(figsize=(7.5, 5), dpi=110)
    lines = [("ours_ns_off", "SynthaVision, shadows off", "o", "C0"),
             ("ours_ns_on", "SynthaVision, shadows on", "s", "C1"),
             ("pov_ns_off", "POV-Ray 3.7 (trace time), shadows off", "^", "C2")]
    # Fixed-size spheres in solid lines, constant coverage dashed.
    names = {"big_union": "fixed size", "big_union_cc": "constant coverage"}
    dashes = {"big_union": "-", "big_union_cc": "--"}
    for series in dict.fromkeys(r.get("series", "big_union") for r in rows):
        part = [r for r in rows if r.get("series", "big_union") == series]
        for key, label, marker, colour in lines:
            pts = [(int(r["bodies"]), float(r[key])) for r in part if r.get(key)]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts],
                        marker=marker, color=colour, linestyle=dashes.get(series, ":"),
                        label=f"{label} ({names.get(series, series)})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("spheres in the union (bodies)")
    ax.set_ylabel("ns per primary ray (one thread)")
    ax.set_title("Union of N random spheres, 960×720, one ray per pixel")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
