#!/usr/bin/env bash
# Side-by-side benchmark: SynthaVision against POV-Ray 3.7 on the same
# scenes. Our scenes are exported with `synthavision export --format pov`,
# so both programs trace exactly the same geometry, camera and light.
#
# Usage: bench/compare.sh [REPS [REPS_HI]]      (defaults 5 and REPS)
#   REPS     repetitions at 960x720 (medians are reported)
#   REPS_HI  repetitions at 3840x2880 (steady state, parallel efficiency)
# Environment:
#   PARTS   which parts to run (default "C A B S M"):
#           C  same-geometry check (pictures compared pixel by pixel)
#           A  960x720, -A -D -V, +WT1/+WT2, shadows off/on (as the baseline's part A)
#           B  3840x2880, -F (no file), same settings (the baseline's part B)
#           S  scaling: union of 100, 1000, 10000, 100000 spheres, one thread,
#              in two series: radii as big_union's (fixed size), and radii
#              scaled by sqrt(10000 / N) (constant coverage, see gen_scenes.py)
#           M  reading and preparing: time and peak memory of `synthavision info`
#   SCENES  scenes for parts C, A and B (default "figure1 helicopter many big_union")
#   SIZES   sphere counts for part S (default "100 1000 10000 100000")
#   SERIES  part S's series (default "big_union big_union_cc")
#   UPDATE_DOC=1  also put the summary into BENCHMARKS.md (between the
#           "compare.sh begin/end" markers) and the plot into docs/scaling.png
#
# Needs povray (Debian/Ubuntu: apt-get install povray), python3, GNU time
# (/usr/bin/time) and cargo. Installs nothing. Results go to
# bench/results/<UTC time>/ (CSV, summary.md; raw logs under logs/).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
REPS=${1:-5}
REPS_HI=${2:-$REPS}
PARTS=${PARTS:-"C A B S M"}
SCENES=${SCENES:-"figure1 helicopter many big_union"}
SIZES=${SIZES:-"100 1000 10000 100000"}
SERIES=${SERIES:-"big_union big_union_cc"}
TOOL="python3 $ROOT/bench/benchtool.py"

missing=0
for c in povray python3 cargo; do
  if ! command -v $c >/dev/null 2>&1; then
    echo "compare.sh: \`$c\` is not installed." >&2
    [ $c = povray ] && echo "  install POV-Ray 3.7 with: apt-get install povray" >&2
    missing=1
  fi
done
[ -x /usr/bin/time ] || { echo "compare.sh: GNU time (/usr/bin/time) is missing: apt-get install time" >&2; missing=1; }
[ $missing = 0 ] || exit 1

echo "== building: cargo build --release -p synthavision" >&2
(cd "$ROOT" && cargo build --release -p synthavision >&2)
SV="$ROOT/target/release/synthavision"

RES="$ROOT/bench/results/$(date -u +%Y%m%dT%H%M%SZ)"
LOGS="$RES/logs"; OUT="$RES/logs/out"
mkdir -p "$LOGS" "$OUT"

scene_file() {
  case $1 in
    figure1) echo "$ROOT/examples/figure1/figure1.sv" ;;
    helicopter) echo "$ROOT/examples/helicopter/helicopter.sv" ;;
    big_union_10000) echo "$ROOT/examples/bench/big_union.sv" ;;
    big_union_100000)
      [ -f "$ROOT/bench/out/big_union_100000.sv" ] ||
        python3 "$ROOT/bench/gen_scenes.py" "$ROOT/bench/out" --sizes 100000
      echo "$ROOT/bench/out/big_union_100000.sv" ;;
    big_union_cc_*)
      [ -f "$ROOT/bench/out/$1.sv" ] ||
        python3 "$ROOT/bench/gen_scenes.py" "$ROOT/bench/out" --coverage --sizes "${1#big_union_cc_}"
      echo "$ROOT/bench/out/$1.sv" ;;
    big_union_*)
      [ -f "$ROOT/examples/bench/$1.sv" ] ||
        python3 "$ROOT/bench/gen_scenes.py" "$ROOT/bench/out" --sizes "${1#big_union_}"
      [ -f "$ROOT/examples/bench/$1.sv" ] && echo "$ROOT/examples/bench/$1.sv" || echo "$ROOT/bench/out/$1.sv" ;;
    *) echo "$ROOT/examples/bench/$1.sv" ;;
  esac
}

# export <scene> <shadows 0|1> -> path of the POV-Ray scene
export_pov() {
  local f="$OUT/$1_s$2.pov"
  if [ ! -f "$f" ]; then
    local ns=""; [ "$2" = 0 ] && ns="--no-shadows"
    "$SV" export "$(scene_file "$1")" --format pov --size 960x720 $ns -o "$f" >&2
  fi
  echo "$f"
}

# pov <csv> <tag> <scene> <threads> <shadows> <rep> <W> <H> <extra options…>
pov() {
  local csv=$1 tag=$2 s=$3 t=$4 sh=$5 rep=$6 w=$7 h=$8; shift 8
  local base="$LOGS/${tag}_${s}_t${t}_s${sh}_r${rep}"
  local file; file=$(export_pov "$s" "$sh")
  /usr/bin/time -v -o "$base.time" povray "$file" -A -D -V "$@" +W"$w" +H"$h" +WT"$t" > "$base.log" 2>&1 ||
    { echo "compare.sh: povray failed, see $base.log" >&2; exit 1; }
  $TOOL pov-row "$base.log" "$base.time" "$s" "$t" "$sh" "$rep" "$w" "$h" >> "$csv"
}

# ours <csv> <scene> <threads> <shadows> <reps> <WxH> [<rep>]
ours() {
  local csv=$1 s=$2 t=$3 sh=$4 n=$5 size=$6 rep=${7:-}
  local ns=""; [ "$sh" = 0 ] && ns="--no-shadows"
  "$SV" bench "$(scene_file "$s")" --repeat "$n" --threads "$t" $ns --size "$size" --json 2>>"$LOGS/ours.stderr" |
    tee -a "$LOGS/ours.jsonl" | $TOOL ours-row "$s" $rep >> "$csv"
}

{
  echo "date: $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
  echo "commit: $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$ROOT" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "command: bench/compare.sh $REPS $REPS_HI   (PARTS=\"$PARTS\")"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
  echo "memory: $(free -m | awk '/^Mem:/ {print $2 " MB total, " $7 " MB available"}')"
  echo "povray: $(povray --version 2>&1 | grep -m1 'POV-Ray 3' || echo unknown)"
  echo "rustc: $(rustc --version)"
} > "$RES/meta.txt"
note_load() { echo "load before part $1: $(uptime | sed 's/.*load average: //')" >> "$RES/meta.txt"; }

for part in $PARTS; do
  note_load "$part"
  case $part in
  C)
    echo "== part C: same geometry check" >&2
    echo "scene,shadows,cov_pov,cov_ours,mask,differ" > "$RES/check.csv"
    for s in $SCENES; do for sh in 0 1; do
      file=$(export_pov "$s" "$sh")
      povray "$file" -A -D -V +W960 +H720 +FP +O"$OUT/${s}_s${sh}_pov.ppm" File_Gamma=1.0 > "$LOGS/C_${s}_s${sh}.log" 2>&1
      ns=""; [ "$sh" = 0 ] && ns="--no-shadows"
      "$SV" render "$(scene_file "$s")" --size 960x720 $ns -o "$OUT/${s}_s${sh}_ours.ppm"
      bg=$(sed -n 's/^background { rgb <\(.*\)> }$/\1/p' "$file" | tr -d ' ')
      echo "$s,$sh,$($TOOL ppmdiff "$OUT/${s}_s${sh}_pov.ppm" "$OUT/${s}_s${sh}_ours.ppm" "$bg")" >> "$RES/check.csv"
      rm -f "$OUT/${s}_s${sh}_pov.ppm" "$OUT/${s}_s${sh}_ours.ppm"
    done; done ;;
  A|B)
    # The two programs take turns, repetition by repetition, so that a slow
    # spell of the machine falls on both. Each of our runs is one process
    # rendering INNER times (its median is the run's figure): at 960x720 a
    # render takes milliseconds.
    if [ $part = A ]; then W=960; H=720; N=$REPS; INNER=5; opt="+FN"; else W=3840; H=2880; N=$REPS_HI; INNER=1; opt="-F"; fi
    echo "== part $part: ${W}x${H}, $N repetitions" >&2
    $TOOL pov-header > "$RES/pov_$part.csv"; $TOOL ours-header > "$RES/ours_$part.csv"
    for s in $SCENES; do for t in 1 2; do for sh in 0 1; do
      echo "   $s threads=$t shadows=$sh" >&2
      for rep in $(seq 1 "$N"); do
        o=$opt; [ $part = A ] && o="+FN +O$OUT/${s}_t${t}_s${sh}.png"
        pov "$RES/pov_$part.csv" "$part" "$s" "$t" "$sh" "$rep" "$W" "$H" $o
        ours "$RES/ours_$part.csv" "$s" "$t" "$sh" "$INNER" "${W}x${H}" "$rep"
      done
    done; done; done ;;
  S)
    echo "== part S: scaling ($SIZES spheres; $SERIES), one thread, $REPS repetitions" >&2
    $TOOL pov-header > "$RES/pov_S.csv"; $TOOL ours-header > "$RES/ours_S.csv"
    for series in $SERIES; do for n in $SIZES; do
      s=${series}_$n
      echo "   $s" >&2
      # Taking turns, as in parts A and B.
      for rep in $(seq 1 "$REPS"); do
        pov "$RES/pov_S.csv" S "$s" 1 0 "$rep" 960 720 -F
        for sh in 0 1; do ours "$RES/ours_S.csv" "$s" 1 "$sh" 5 960x720 "$rep"; done
      done
    done; done
    python3 - "$RES" <<'PY'
import csv, statistics, sys, os
res = sys.argv[1]
ours = list(csv.DictReader(open(os.path.join(res, "ours_S.csv"))))
pov = list(csv.DictReader(open(os.path.join(res, "pov_S.csv"))))
out = open(os.path.join(res, "scaling.csv"), "w")
out.write("series,bodies,coverage,ours_ns_off,ours_ns_on,pov_ns_off\n")
for n in dict.fromkeys(r["scene"] for r in ours):
    ns, cov = {}, ""
    for sh in ("0", "1"):
        rows = [r for r in ours if r["scene"] == n and r["shadows"] == sh]
        if rows:
            t = statistics.median(float(r["median_s"]) for r in rows)
            ns[sh] = t * 1e9 / (int(rows[0]["width"]) * int(rows[0]["height"]))
            cov = rows[0]["coverage"]
    p = [r for r in pov if r["scene"] == n]
    pn = statistics.median(float(r["trace_s"]) for r in p) * 1e9 / float(p[0]["pixels"]) if p else ""
    series, bodies = n.rsplit("_", 1)
    out.write(f"{series},{bodies},{cov},{ns.get('0', '')},{ns.get('1', '')},{pn}\n")
PY
    ;;
  M)
    echo "== part M: reading and preparing" >&2
    echo "scene,bodies,wall_s,maxrss_kb" > "$RES/memory.csv"
    for n in $SIZES; do
      f=$(scene_file big_union_$n)
      t0=$(date +%s%N)
      /usr/bin/time -v -o "$LOGS/M_$n.time" "$SV" info "$f" > "$LOGS/M_$n.out"
      t1=$(date +%s%N)
      w=$(python3 -c "print(($t1 - $t0) / 1e9)")
      rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$LOGS/M_$n.time")
      echo "big_union_$n,$n,$w,$rss" >> "$RES/memory.csv"
    done ;;
  *) echo "compare.sh: unknown part $part" >&2; exit 2 ;;
  esac
done
note_load end

$TOOL summary "$RES" /work/shared/bench/povray > "$RES/summary.md"
[ -f "$RES/scaling.csv" ] && python3 "$ROOT/bench/plot_scaling.py" "$RES/scaling.csv" "$RES/scaling.png" >&2 || true
cat "$RES/summary.md"
if [ "${UPDATE_DOC:-0}" = 1 ]; then
  python3 - "$ROOT/BENCHMARKS.md" "$RES/summary.md" "${RES#$ROOT/}" <<'PY'
import sys
doc, summary, res = sys.argv[1:]
text = open(doc).read()
begin, end = "<!-- compare.sh begin -->", "<!-- compare.sh end -->"
i, j = text.index(begin) + len(begin), text.index(end)
body = open(summary).read().rstrip()
text = text[:i] + f"\n(Written by bench/compare.sh from {res}.)\n\n" + body + "\n" + text[j:]
open(doc, "w").write(text)
PY
  if [ -f "$RES/scaling.png" ]; then
    mkdir -p "$ROOT/docs" && cp "$RES/scaling.png" "$ROOT/docs/scaling.png"
    echo "updated BENCHMARKS.md and docs/scaling.png" >&2
  else
    echo "updated BENCHMARKS.md; docs/scaling.png left as it was (no plot)" >&2
  fi
fi
echo >&2
echo "results: $RES" >&2
