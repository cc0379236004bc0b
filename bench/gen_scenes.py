#!/usr/bin/env python3
"""Generate the benchmark scenes in SynthaVision's scene language.

Deterministic (Python's Mersenne Twister with fixed seeds), standard library
only. The scenes follow the POV-Ray baseline scenes many.pov and
big_union.pov (same kind of geometry, camera, light and shading); as the
random numbers differ from POV-Ray's, the comparison renders these very
scenes in POV-Ray through `synthavision export --format pov`.

Coordinates: POV-Ray's left-handed y-up <x, y, z> is our right-handed z-up
(x, z, y). POV-Ray's camera `angle` is the horizontal field of view; ours is
the vertical one: vfov = 2 atan(tan(hfov / 2) * H / W). POV-Ray's
Sun(<a, b, c>) shines from that direction, so the light travels along
-(a, c, b) in our coordinates.

Usage: gen_scenes.py [OUTDIR] [--sizes 100,1000,10000,100000] [--crowds] [--coverage]
Writes OUTDIR/many.sv and OUTDIR/big_union_N.sv (big_union.sv for
N = 10000, the baseline's size); with --crowds also crowd_sparse.sv and
crowd_far.sv (100,000 spheres: tiles crowded past their zone lists); with
--coverage also big_union_cc_N.sv: the N spheres with their radii scaled by
sqrt(10000 / N), so that their summed cross-section, and with it the share
of the picture they cover and the number of spheres a ray passes, stay
those of the 10,000 (the scaling series at constant coverage).
OUTDIR defaults to examples/bench.
"""
import math
import os
import random
import sys

W, H = 960, 720


def vfov(hfov_deg):
    return math.degrees(2 * math.atan(math.tan(math.radians(hfov_deg) / 2) * H / W))


def pov_to_ours(p):
    x, y, z = p
    return (x, z, y)


def fmt(x):
    s = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def vec(p):
    return "(" + ", ".join(fmt(c) for c in p) + ")"


def sun(pov_dir):
    a, b, c = pov_dir
    return pov_to_ours((-a, -b, -c))


def common(title, eye_pov, at_pov, hfov, sun_pov):
    return [
        f"TITLE {title}",
        "UNITS m",
        "",
    ], [
        "",
        f"CAMERA EYE {vec(pov_to_ours(eye_pov))} AT {vec(pov_to_ours(at_pov))} UP (0, 0, 1) FOV {fmt(vfov(hfov))}",
        f"LIGHT SUN PARALLEL DIR {vec(sun(sun_pov))} INTENSITY 1",
        "AMBIENT 0.15",
        "BACKGROUND 0",
        f"SIZE {W} {H}",
        "",
    ]


def many():
    """10x10x10 grid: spheres r=0.45 each minus a randomly oriented
    cylinder r=0.22 of length 1.2 through its centre (many.pov)."""
    head, tail = common(
        "many: 1000 spheres each minus a randomly oriented cylinder (after many.pov)",
        (4.5 + 15, 4.5 + 12, 4.5 - 19), (4.5, 4.0, 4.5), 48, (0.8, 1.6, -0.6))
    rnd = random.Random(12345)
    body, reg = [], []
    n = 0
    for i in range(10):
        for j in range(10):
            for k in range(10):
                c = (float(i), float(j), float(k))  # POV-Ray's <I, J, K>
                d = [rnd.random() - 0.5, rnd.random() - 0.5, rnd.random() - 0.5]
                d[1] += 1e-6
                ln = math.sqrt(sum(x * x for x in d))
                d = [x / ln for x in d]
                v = [c[a] - 0.6 * d[a] for a in range(3)]
                h = [1.2 * d[a] for a in range(3)]
                body.append(f"BODY s{n} SPH {vec(pov_to_ours(c))} 0.45")
                body.append(f"BODY c{n} RCC {vec(pov_to_ours(v))} {vec(pov_to_ours(h))} 0.22")
                reg.append(f"REGION r{n} = +s{n} -c{n} K 0.85")
                n += 1
    return "\n".join(head + body + [""] + reg + tail)


def big_union(nsph, shrink=1.0, eye=(24, 18, -30), hfov=57, what=""):
    """One region: the union (OR) of `nsph` random spheres in a 20^3 cube,
    radii 0.25 to 0.45 (big_union.pov), divided by `shrink`; seen from
    `eye` (POV-Ray coordinates) with horizontal field `hfov`."""
    head, tail = common(
        f"big_union: one region, the union of {nsph} random spheres{what} (after big_union.pov)",
        eye, (0, -1.0, 0), hfov, (0.8, 1.6, -0.6))
    rnd = random.Random(4242)
    body = []
    for n in range(nsph):
        c = (20 * rnd.random() - 10, 20 * rnd.random() - 10, 20 * rnd.random() - 10)
        r = (0.25 + 0.2 * rnd.random()) / shrink
        body.append(f"BODY s{n} SPH {vec(pov_to_ours(c))} {fmt(r)}")
    region = "REGION all = " + " OR ".join(f"+s{n}" for n in range(nsph)) + " K 0.85"
    return "\n".join(head + body + ["", region] + tail)


def main(argv):
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "bench")
    sizes = [100, 1000, 10000]
    args = list(argv)
    if any(a in ("-h", "--help") for a in args):
        print(__doc__)
        return 0
    flags = ("--sizes", "--crowds", "--coverage")
    bad = [a for a in args if a.startswith("-") and a not in flags]
    if bad:
        sys.stderr.write(f"gen_scenes.py: unknown option {bad[0]}\n{__doc__}")
        return 2
    if "--sizes" in args:
        i = args.index("--sizes")
        sizes = [int(s) for s in args[i + 1].split(",")]
        del args[i:i + 2]
    crowds, coverage = "--crowds" in args, "--coverage" in args
    args = [a for a in args if a not in ("--crowds", "--coverage")]
    if args:
        out = args[0]
    os.makedirs(out, exist_ok=True)

    def put(name, text):
        with open(os.path.join(out, name), "w") as f:
            f.write(text)

    put("many.sv", many())
    for n in sizes:
        put("big_union.sv" if n == 10000 else f"big_union_{n}.sv", big_union(n))
    if coverage:
        for n in sizes:
            put(f"big_union_cc_{n}.sv", big_union(
                n, shrink=math.sqrt(n / 10000),
                what=f", radii x {math.sqrt(10000 / n):.3g} (constant coverage)"))
    if crowds:
        # Crowded tiles: the 100,000 spheres 20 times smaller (most rays
        # slip between them), and the full-size ones from 30 times as far
        # (a speck in the picture: most rays of its tiles pass it by).
        put("crowd_sparse.sv", big_union(100000, shrink=20, what=", radii / 20"))
        put("crowd_far.sv", big_union(100000, eye=(720, 540, -900), hfov=26,
                                      what=", seen from 30 times as far"))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
