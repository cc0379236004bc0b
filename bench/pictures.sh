#!/usr/bin/env bash
# Regression pictures: render a fixed set of pictures, slices and reports
# with one binary and list their SHA-256 sums, so that a change meant to
# leave pictures alone can be checked byte for byte against the binary
# from before it.
#
#   bench/pictures.sh BINARY OUT_DIR          # writes OUT_DIR/*.png … and OUT_DIR/SUMS
#   bench/pictures.sh OLD_BIN /tmp/old && bench/pictures.sh NEW_BIN /tmp/new
#   diff /tmp/old/SUMS /tmp/new/SUMS          # empty when nothing moved
#
# The set: the bundled scenes with and without shadows and with 2x2
# supersampling, their region/depth/normal images, the three COMGEOM decks
# in three views, every FLUKA input of ../shared/decks/fluka (those the
# binary reads), the benchmark scenes under a lamp, 1 and 2 threads, and
# the slice and check reports of the decks. DECKS may point elsewhere.
set -uo pipefail
bin=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
decks=${DECKS:-$here/../shared/decks}
if [ ! -d "$decks/comgeom" ]; then
    echo "pictures.sh: $decks/comgeom is missing (set DECKS)" >&2
    exit 2
fi
mkdir -p "$out"
rm -f "$out"/SUMS
run() { # name, then the arguments of the binary
    local name=$1
    shift
    "$bin" "$@" >"$out/$name.stdout" 2>"$out/$name.stderr"
    echo "exit $?" >>"$out/$name.stdout"
    # Timings and the output folder differ from run to run.
    sed -i -e "s|$out|OUT|g" -e '/"seconds"/d' "$out/$name.stdout" "$out/$name.stderr"
}
s=512x384
for scene in figure1/figure1 figure3/figure3 helicopter/helicopter helicopter-film/gun; do
    n=$(basename "$scene")
    f=$here/examples/$scene.sv
    run "$n" render "$f" --size $s -o "$out/$n.png" --aov region,depth,normal
    run "$n-noshadow" render "$f" --size $s --no-shadows -o "$out/$n-noshadow.png"
    run "$n-ss2" render "$f" --size 256x192 --samples 2 -o "$out/$n-ss2.png" --threads 1
    run "$n-16" render "$f" --size $s --sixteen-bit --srgb -o "$out/$n-16.png" --threads 2
done
for b in many big_union_100 big_union_1000; do
    run "$b" render "$here/examples/bench/$b.sv" --size $s -o "$out/$b.png"
done
for d in "$decks"/comgeom/*.cg; do
    n=$(basename "$d" .cg)
    run "$n" render "$d" --size $s -o "$out/$n.png" --aov region,depth,normal
    run "$n-ortho" render "$d" --size $s --ortho --eye-light --no-shadows -o "$out/$n-ortho.png"
    run "$n-top" render "$d" --size $s --az 0 --el 90 -o "$out/$n-top.png" --threads 1
    run "$n-slice" slice "$d" --plane z=10 --size 400x300 -o "$out/$n-slice.png"
    run "$n-check" check "$d" --json --threads 2
    run "$n-info" info "$d"
done
for f in "$decks"/fluka/pyg4ometry-testdata/*.inp "$decks"/fluka/field/*.inp; do
    n=fluka-$(basename "$f" .inp)
    run "$n" render "$f" --size 256x192 -o "$out/$n.png"
done
run shoot shoot "$here/examples/figure3/figure3.sv" --from -9,0,0 --dir 1,0,0
(cd "$out" && sha256sum -- * | grep -v ' SUMS$' >SUMS)
echo "$(wc -l <"$out/SUMS") files in $out/SUMS"
