#!/usr/bin/env python3
"""Helpers for bench/compare.sh (Python 3 standard library only).

  benchtool.py pov-header
  benchtool.py pov-row LOG TIMEFILE SCENE THREADS SHADOWS REP WIDTH HEIGHT
      One POV-Ray run as CSV: POV-Ray's own statistics from its render log
      (trace time, pixels, shadow tests) and `/usr/bin/time -v` figures.
  benchtool.py ours-header
  benchtool.py ours-row SCENE [REP] < JSON lines from `synthavision bench --json`
  benchtool.py ppmdiff A.ppm B.ppm R,G,B
      Coverage of two pictures (pixels differing from the background) and
      how many pixels differ, for checking that both programs trace the
      same geometry.
  benchtool.py summary RESULTS_DIR [BASELINE_DIR]
      Markdown tables from a results directory written by compare.sh.
"""
import csv
import json
import os
import re
import statistics
import sys

POV_HEADER = "scene,threads,shadows,rep,width,height,wall_s,maxrss_kb,parse_s,trace_s,pixels,shadow_tests,load1"
OURS_HEADER = "scene,threads,shadows,width,height,reps,median_s,min_s,max_s,mrays_per_s_per_core,coverage,load1,rep"


def find(pattern, text, default="0"):
    m = re.search(pattern, text)
    return m.group(1) if m else default


def wall_seconds(text):
    # "Elapsed (wall clock) time (h:mm:ss or m:ss): 0:01.23"
    s = find(r"Elapsed \(wall clock\) time.*?: (\d[\d:.]*)", text)
    total = 0.0
    for part in s.split(":"):
        total = total * 60 + float(part)
    return total


def load1():
    """The one-minute load average now (other work on the machine)."""
    try:
        return open("/proc/loadavg").read().split()[0]
    except OSError:
        return ""


def pov_row(argv):
    log_path, time_path, scene, threads, shadows, rep, width, height = argv
    log = open(log_path, errors="replace").read()
    tm = open(time_path, errors="replace").read()
    trace = find(r"Trace Time:.*\(\s*([\d.]+) seconds\)", log, "")
    if not trace:
        sys.stderr.write(f"benchtool: no trace time in {log_path}\n")
        return 1
    row = [scene, threads, shadows, rep, width, height, round(wall_seconds(tm), 3),
           find(r"Maximum resident set size \(kbytes\): (\d+)", tm),
           find(r"Parse Time:.*\(\s*([\d.]+) seconds\)", log), trace,
           find(r"Pixels:\s+(\d+)", log), find(r"Shadow Ray Tests:\s+(\d+)", log), load1()]
    print(",".join(str(x) for x in row))
    return 0


def ours_row(argv):
    scene, rep = argv[0], (argv[1] if len(argv) > 1 else "")
    n = 0
    for line in sys.stdin:
        line = line.strip()
        if not line.startswith("{"):
            continue
        j = json.loads(line)
        t = sorted(j["times_s"])
        print(",".join(str(x) for x in [
            scene, j["threads"], int(bool(j["shadows"])), j["width"], j["height"], len(t),
            j["median_s"], t[0], t[-1], j["mrays_per_s_per_core"], j.get("coverage", ""), load1(), rep]))
        n += 1
    if n == 0:
        sys.stderr.write("benchtool: no JSON line from synthavision bench\n")
        return 1
    return 0


def read_ppm(path):
    d = open(path, "rb").read()
    fields, i = [], 0
    while len(fields) < 4:
        while d[i:i + 1].isspace():
            i += 1
        if d[i:i + 1] == b"#":
            while d[i:i + 1] != b"\n":
                i += 1
            continue
        j = i
        while not d[j:j + 1].isspace():
            j += 1
        fields.append(d[i:j])
        i = j
    i += 1
    if fields[0] != b"P6":
        raise SystemExit(f"{path}: not a binary PPM")
    w, h, mx = int(fields[1]), int(fields[2]), int(fields[3])
    bpc = 2 if mx > 255 else 1
    raw = d[i:i + w * h * 3 * bpc]
    if bpc == 1:
        vals = [v / mx for v in raw]
    else:
        vals = [int.from_bytes(raw[k:k + 2], "big") / mx for k in range(0, len(raw), 2)]
    return w, h, vals


def ppmdiff(argv):
    a_path, b_path, bg = argv
    bg = [float(x) for x in bg.split(",")]
    wa, ha, a = read_ppm(a_path)
    wb, hb, b = read_ppm(b_path)
    if (wa, ha) != (wb, hb):
        raise SystemExit(f"sizes differ: {wa}x{ha} and {wb}x{hb}")
    n = wa * ha
    tol = 1.5 / 255
    cov_a = cov_b = mask = differ = 0
    for p in range(n):
        pa, pb = a[3 * p:3 * p + 3], b[3 * p:3 * p + 3]
        ha_ = any(abs(pa[c] - bg[c]) > tol for c in range(3))
        hb_ = any(abs(pb[c] - bg[c]) > tol for c in range(3))
        cov_a += ha_
        cov_b += hb_
        mask += ha_ != hb_
        differ += any(abs(pa[c] - pb[c]) > tol for c in range(3))
    print(f"{cov_a / n:.4f},{cov_b / n:.4f},{mask / n:.6f},{differ / n:.6f}")
    return 0


# ---------------------------------------------------------------- summary

def load_csv(path):
    if not os.path.exists(path):
        return []
    return list(csv.DictReader(open(path)))


def med(rows, key):
    return statistics.median(float(r[key]) for r in rows)


def group(rows, keys):
    out = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def pov_rate(rows, best=False):
    """Median (or best) trace time, and primary Mrays/s per thread from it."""
    tr = min(float(r["trace_s"]) for r in rows) if best else med(rows, "trace_s")
    px = med(rows, "pixels")
    t = int(rows[0]["threads"])
    return tr, px / tr / t / 1e6


def ours_rate(o, best=False):
    """Our primary Mrays/s per core from one `bench` process: its median
    render, or its fastest."""
    t = float(o["min_s"] if best else o["median_s"])
    return int(o["width"]) * int(o["height"]) / t / int(o["threads"]) / 1e6


def ours_rates(rows, best=False):
    """Over the processes of one configuration: the median of their median
    rates, or the fastest render of all."""
    if best:
        return max(ours_rate(o, True) for o in rows)
    return statistics.median(ours_rate(o) for o in rows)


def paired_ratio(ours, pov):
    """The median over repetitions of (our rate / POV-Ray's rate), each
    pair taken one right after the other: a slow spell of the machine
    then slows both sides of a pair alike."""
    mine = {o["rep"]: ours_rate(o) for o in ours if o.get("rep")}
    ratios = [mine[r["rep"]] / pov_rate([r])[1] for r in pov if r["rep"] in mine]
    return statistics.median(ratios) if ratios else None


def fmt(x, nd=2):
    return "–" if x is None else f"{x:.{nd}f}"


def side_by_side(res, part, baseline, out):
    pov = group(load_csv(os.path.join(res, f"pov_{part}.csv")), ["scene", "threads", "shadows"])
    ours = group(load_csv(os.path.join(res, f"ours_{part}.csv")), ["scene", "threads", "shadows"])
    base = {}
    if baseline:
        for r in load_csv(os.path.join(baseline, f"summary_{part}.csv")):
            base[(r["scene"], r["threads"], r["shadows"])] = float(r["Mrays_s_per_thread_trace"])
    base_name = {"figure1": "seed_fig1", "helicopter": "helicopter21", "many": "many", "big_union": "big_union"}
    if not ours:
        return
    any_r = next(iter(ours.values()))[0]
    out.append(f"\n### {any_r['width']}×{any_r['height']}, one ray per pixel\n")
    out.append("Mrays/s per core (ours) and per thread (POV-Ray, from its trace time): the median run and the best run. "
               "The runs of the two programs alternate; \"paired\" is the median over the repetitions of the ratio "
               "of two runs taken one right after the other.\n")
    out.append("| scene | threads | shadows | ours, median | POV-Ray, median | ratio | ours, best | POV-Ray, best | ratio | paired | POV-Ray baseline (shared/bench/povray) | runs ours/POV | load (1-min avg) |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key, o in ours.items():
        s, t, sh = key
        p = pov.get(key)
        pr = pov_rate(p)[1] if p else None
        pb = pov_rate(p, best=True)[1] if p else None
        ours_r, ob = ours_rates(o), ours_rates(o, best=True)
        pair = paired_ratio(o, p) if p else None
        b = base.get((base_name.get(s, s), t, sh))
        loads = [float(r["load1"]) for r in o] + ([float(r["load1"]) for r in p] if p else [])
        runs = sum(int(r["reps"]) for r in o)
        out.append(f"| {s} | {t} | {'on' if sh == '1' else 'off'} | {ours_r:.2f} | {fmt(pr)} | "
                   f"{fmt(ours_r / pr if pr else None, 1)}× | {ob:.2f} | {fmt(pb)} | {fmt(ob / pb if pb else None, 1)}× | "
                   f"{fmt(pair, 1)}× | {fmt(b)} | {runs}/{len(p) if p else 0} | {min(loads):.1f}–{max(loads):.1f} |")
    # Parallel efficiency: total rate at 2 threads over 1 thread.
    lines = []
    for s in sorted({k[0] for k in ours}):
        for sh in ("0", "1"):
            o1, o2 = ours.get((s, "1", sh)), ours.get((s, "2", sh))
            p1, p2 = pov.get((s, "1", sh)), pov.get((s, "2", sh))
            so = 2 * ours_rates(o2) / ours_rates(o1) if o1 and o2 else None
            sob = 2 * ours_rates(o2, True) / ours_rates(o1, True) if o1 and o2 else None
            sp = pov_rate(p1)[0] / pov_rate(p2)[0] if p1 and p2 else None
            spb = pov_rate(p1, True)[0] / pov_rate(p2, True)[0] if p1 and p2 else None
            if so or sp:
                lines.append(f"| {s} | {'on' if sh == '1' else 'off'} | {fmt(so)}× | {fmt(sp)}× | {fmt(sob)}× | {fmt(spb)}× |")
    if lines:
        out.append("\nTwo threads over one thread (total throughput):\n")
        out.append("| scene | shadows | ours, median | POV-Ray, median | ours, best | POV-Ray, best |")
        out.append("|---|---|---|---|---|---|")
        out.extend(lines)


def summary(argv):
    res = argv[0]
    baseline = argv[1] if len(argv) > 1 and os.path.isdir(argv[1]) else None
    out = []
    meta = os.path.join(res, "meta.txt")
    if os.path.exists(meta):
        out.append("```")
        out.append(open(meta).read().rstrip())
        out.append("```")
    for part in ("A", "B"):
        side_by_side(res, part, baseline, out)

    sc = load_csv(os.path.join(res, "scaling.csv"))
    titles = {
        "big_union": "union of N random spheres, radii 0.25–0.45 (fixed size)",
        "big_union_cc": "union of N random spheres, radii × √(10000/N) (constant coverage)",
    }
    for series in dict.fromkeys(r.get("series", "big_union") for r in sc):
        rows = [r for r in sc if r.get("series", "big_union") == series]
        out.append(f"\n### Scaling: {titles.get(series, series)}, 960×720, one thread\n")
        out.append("| spheres | pixels on geometry | ours ns/ray, shadows off | ours ns/ray, shadows on | POV-Ray ns/ray, shadows off (trace) | ours ×(100), off | ours ×(100), on | POV-Ray ×(100) | ours ns per pixel on geometry, off | ×(100) |")
        out.append("|---|---|---|---|---|---|---|---|---|---|")
        first = {}
        for r in rows:
            n = r["bodies"]
            vals = [r.get("ours_ns_off"), r.get("ours_ns_on"), r.get("pov_ns_off")]
            vals = [float(v) if v else None for v in vals]
            # The frame's time over the rays that meet a sphere: rays that
            # meet nothing cost next to nothing, so this is the cost of
            # finding a surface among N bodies.
            cover = float(r["coverage"]) if r.get("coverage") else None
            vals.append(vals[0] / cover if vals[0] and cover else None)
            if not first:
                first = vals
            rel = [v / f if v and f else None for v, f in zip(vals, first)]
            cov = f"{cover:.1%}" if cover else "–"
            out.append(f"| {n} | {cov} | {fmt(vals[0], 1)} | {fmt(vals[1], 1)} | {fmt(vals[2], 1)} | "
                       f"{fmt(rel[0])}× | {fmt(rel[1])}× | {fmt(rel[2])}× | {fmt(vals[3], 1)} | {fmt(rel[3])}× |")

    mem = load_csv(os.path.join(res, "memory.csv"))
    if mem:
        out.append("\n### Reading and preparing (`synthavision info`), `/usr/bin/time -v`\n")
        out.append("| scene | bodies | wall s | max RSS MB |")
        out.append("|---|---|---|---|")
        for r in mem:
            out.append(f"| {r['scene']} | {r['bodies']} | {float(r['wall_s']):.2f} | {int(r['maxrss_kb']) / 1024:.1f} |")

    chk = load_csv(os.path.join(res, "check.csv"))
    if chk:
        out.append("\n### Same geometry? 960×720 pictures, POV-Ray (exported scene) against ours\n")
        out.append("| scene | shadows | coverage POV-Ray | coverage ours | pixels hit in one only | pixels differing by > 1.5/255 |")
        out.append("|---|---|---|---|---|---|")
        for r in chk:
            out.append(f"| {r['scene']} | {'on' if r['shadows'] == '1' else 'off'} | {float(r['cov_pov']):.2%} | {float(r['cov_ours']):.2%} | "
                       f"{float(r['mask']):.3%} | {float(r['differ']):.3%} |")
    print("\n".join(out))
    return 0


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    cmd, rest = argv[0], argv[1:]
    if cmd == "pov-header":
        print(POV_HEADER)
        return 0
    if cmd == "ours-header":
        print(OURS_HEADER)
        return 0
    return {"pov-row": pov_row, "ours-row": ours_row, "ppmdiff": ppmdiff, "summary": summary}[cmd](rest)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
