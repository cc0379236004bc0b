#!/usr/bin/env python3
"""Compare synthavision binaries by their fastest renders.

    bench/best_of.py BIN [BIN ...] [-- SCENE ...] [++ BENCH OPTIONS ...]

Runs `BIN bench SCENE --threads $THREADS --size $SIZE --repeat 7 --json`
for every binary and scene, ROUNDS times (default 3), interleaved, and
prints the primary rays per second per core of the fastest render of each.
On a shared machine the fastest run is the least disturbed one; running the
binaries in turn spreads the disturbances over all of them.

Environment: THREADS (default 1), ROUNDS (default 3), SIZE (default
960x720). Without scenes, the
four scenes of bench/compare.sh.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCENES = ["examples/figure1/figure1.sv", "examples/helicopter/helicopter.sv",
          "examples/bench/many.sv", "examples/bench/big_union.sv"]


def main(argv):
    extra = []
    if "++" in argv:
        i = argv.index("++")
        argv, extra = argv[:i], argv[i + 1:]
    bins, scenes = argv, []
    if "--" in argv:
        i = argv.index("--")
        bins, scenes = argv[:i], argv[i + 1:]
    if not bins:
        sys.stderr.write(__doc__)
        return 2
    scenes = scenes or [os.path.join(ROOT, s) for s in SCENES]
    threads = int(os.environ.get("THREADS", "1"))
    rounds = int(os.environ.get("ROUNDS", "3"))
    size = os.environ.get("SIZE", "960x720")
    best = {}
    for _ in range(rounds):
        for s in scenes:
            for b in bins:
                out = subprocess.run(
                    [b, "bench", s, "--threads", str(threads), "--size", size,
                     "--repeat", "7", "--json"] + extra,
                    capture_output=True, text=True, check=True).stdout
                j = json.loads(out.strip().splitlines()[-1])
                rate = j["width"] * j["height"] / min(j["times_s"]) / threads / 1e6
                best[(s, b)] = max(best.get((s, b), 0.0), rate)
    print("%-24s" % "Mrays/s/core (best)" + "".join("%16s" % os.path.basename(b)[-15:] for b in bins))
    for s in scenes:
        print("%-24s" % os.path.basename(s) + "".join("%16.2f" % best[(s, b)] for b in bins))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
