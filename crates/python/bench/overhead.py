"""The Python call's cost over the CLI's for the bundled helicopter, and a
film on a two-worker LocalCluster against the CLI's `film`
(BENCHMARKS.md, "The Python package"). Run from the repository root after
`cargo build --release` and `pip install "./crates/python[test]"`::

    python crates/python/bench/overhead.py [REPEATS]
"""

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import synthavision as sv

REPO = Path(__file__).resolve().parents[3]
CLI = REPO / "target" / "release" / "synthavision"
HELICOPTER = REPO / "examples" / "helicopter" / "helicopter.sv"


def median_seconds(work, repeats):
    work()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 9
    bench = subprocess.run(
        [CLI, "bench", HELICOPTER, "--size", "960x720", "--repeat", str(repeats), "--json"],
        capture_output=True, text=True, check=True,
    )
    cli_render = json.loads(bench.stdout.splitlines()[-1])["median_s"]
    model = sv.load(HELICOPTER)
    picture = Path(tempfile.mkdtemp()) / "helicopter.png"
    rows = {
        "CLI bench: render only (median)": cli_render,
        "CLI render process, PNG written": median_seconds(
            lambda: subprocess.run([CLI, "render", "-o", picture], capture_output=True, check=True),
            repeats,
        ),
        "Python model.render(aovs=False)": median_seconds(
            lambda: model.render(size=(960, 720), aovs=False), repeats
        ),
        "Python model.render() with region, depth, normal": median_seconds(
            lambda: model.render(size=(960, 720)), repeats
        ),
        "Python model.render(size=(1, 1))": median_seconds(
            lambda: model.render(size=(1, 1), aovs=False), repeats
        ),
    }
    for name, value in rows.items():
        print(f"{name:<52} {value * 1000:9.2f} ms")
    film = REPO / "examples" / "helicopter-film" / "film.svs"
    with tempfile.TemporaryDirectory() as scratch:
        start = time.perf_counter()
        subprocess.run(
            [CLI, "film", film, "-o", f"{scratch}/cli", "--frames", "0..96", "--size", "480x360",
             "--no-mp4"], check=True, capture_output=True,
        )
        cli_film = time.perf_counter() - start
        start = time.perf_counter()
        sv.dask.render_film(film, f"{scratch}/dask", frames=range(0, 96), size=(480, 360),
                            chunk=12, mp4=False)
        dask_film = time.perf_counter() - start
    print(f"{'film, 96 frames 480x360: CLI':<52} {cli_film:9.2f} s")
    print(f"{'film, 96 frames 480x360: 2-worker LocalCluster':<52} {dask_film:9.2f} s")


if __name__ == "__main__":
    main()
