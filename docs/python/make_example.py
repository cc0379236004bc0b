"""Run the walk-through and write it as docs/python/example.md with its pictures
(docs/python/images/). Run from the repository root after
``pip install "./crates/python[test]"``::

    python docs/python/make_example.py
"""

import contextlib
import io
import tempfile
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
IMAGES = HERE / "images"

# Each step: a title, what it shows, and the code (run in one namespace).
STEPS = [
    ("Load a model", "Any input the CLI reads: a scene, COMGEOM, FLUKA, MCNP, OpenMC.", """
import synthavision as sv
model = sv.load("examples/helicopter/helicopter.sv")
print(model)
print([r.name for r in model.regions[:6]], model.bounding_box[1])
"""),
    ("Render", "A numpy picture with its region ids; `_repr_png_` shows it in Jupyter.", """
camera = sv.Camera(eye=(-20, -30, 12), at=(0, 0, 2), fov=35)
image = model.render(camera=camera, size=(320, 240))
print(image.rgb.shape, image.rgb.dtype, image.region.dtype, sorted(set(image.region.ravel().tolist()))[:5])
image.save("IMAGES/render.png")
"""),
    ("Colour by material", "An MCNP input given as text: a fuel sphere in a water box.", """
reactor = sv.load('''tiny core
1 1 -10.5 -1 imp:n=1
2 2 -1.0 1 -2 imp:n=1
3 0 2 imp:n=0

1 so 5
2 rpp -10 10 -10 10 -10 10

m1 92235.80c 1
m2 1001.80c 2 8016.80c 1
''')
print(reactor.materials, [r.material for r in reactor.regions])
cut = reactor.render(az=30, el=25, size=(320, 240), color_by="material", transparent=["2"])
cut.save("IMAGES/material.png")
ids = reactor.id_map(origin=(0, 0, 0), width=(24, 24), pixels=(24, 24))
print(ids[12, ::3, 0], ids[12, ::3, 1])
"""),
    ("Slice with a legend", "OpenMC's `plot`: a section, matplotlib, a legend.", """
ax = model.plot(plane="z=3", size=(400, 300))
ax.figure.savefig("IMAGES/slice.png", dpi=80, bbox_inches="tight")
section = model.slice(plane="z=3", size=(400, 300))
print([(e["label"], round(e["area"], 2)) for e in section.legend[:4]])
"""),
    ("Find overlaps", "The CLI's `check --json` as a dict.", """
spheres = sv.load('''BODY a SPH (0,0,0) 1
BODY b SPH (1.5,0,0) 1
REGION A = +a
REGION B = +b
''')
report = spheres.check()
overlap = report["overlaps"][0]
print(overlap["regions"], round(overlap["volume"], 3), report["grid_rays"])
"""),
    ("Compute volumes", "The CLI's `volume --json` as a dict.", """
volumes = model.volume(rel_error=0.01)
print([(r["region"], round(r["volume"], 2)) for r in volumes["regions"][:4]])
"""),
    ("A film on a LocalCluster", "Two worker processes on loopback; the frames are the CLI's, byte for byte.", """
script = TMP / "spin.svs"
script.write_text('''SCENE "REPO/examples/helicopter/helicopter.sv"
FPS 8
SIZE 160 120
CAMERA EYE (-30,-42,9) AT (0,0,3) UP (0,0,1) FOV 40
OBJECT MAINROTOR REGIONS hub blade_a blade_b
AXIS MAST POINT (0,0,0) DIR (0,0,1)
SPIN MAINROTOR (AXIS MAST, 10) PER FRAME
HOLD 16
''')
report = sv.dask.render_film(script, TMP / "film", chunk=4, mp4=False)
print(len(report["rendered"]), "frames;", report["gif"].name, report["contact_sheet"].name)
import shutil; shutil.copy(report["contact_sheet"], "IMAGES/contact.png")
"""),
]


def main():
    tmp = Path(tempfile.mkdtemp())
    namespace = {"TMP": tmp}
    lines = [
        "# SynthaVision from Python: a walk-through",
        "",
        "Made by `docs/python/make_example.py` (run from the repository root);",
        "every output below is what the code printed. `TMP` is a scratch folder,",
        "`REPO` the repository.",
        "",
    ]
    for title, words, code in STEPS:
        code = textwrap.dedent(code).strip()
        shown = code.replace("IMAGES/", "")
        runnable = code.replace("IMAGES/", f"{IMAGES}/").replace("REPO", str(REPO))
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(runnable, title, "exec"), namespace)
        lines += [f"## {title}", "", words, "", "```python", shown, "```", ""]
        if printed.getvalue().strip():
            lines += ["```", printed.getvalue().strip(), "```", ""]
        for name in ("render", "material", "slice", "contact"):
            if f'"IMAGES/{name}.png"' in code:
                lines += [f"![{title}](images/{name}.png)", ""]
    (HERE / "example.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
