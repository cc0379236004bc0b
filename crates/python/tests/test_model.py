"""Loading, pictures and errors, each against the CLI on the same input."""

import threading

import numpy as np
import pytest
from PIL import Image as PILImage

import synthavision as sv
from conftest import HELICOPTER


@pytest.fixture(scope="module")
def helicopter():
    return sv.load(HELICOPTER)


def test_regions_and_bounds(helicopter):
    names = [r.name for r in helicopter.regions]
    assert names[:3] == ["fuselage", "door", "window"]
    assert len(names) == 24
    assert [r.index for r in helicopter.regions] == list(range(24))
    lo, hi = helicopter.bounding_box
    assert all(a < b for a, b in zip(lo, hi))
    for region in helicopter.regions:
        r_lo, r_hi = region.bounds
        assert all(lo[i] - 1e-9 <= r_lo[i] <= r_hi[i] <= hi[i] + 1e-9 for i in range(3))
    assert helicopter.format == "sv"


def test_text_loads_as_the_file(helicopter):
    from_text = sv.load(HELICOPTER.read_text())
    assert [r.name for r in from_text.regions] == [r.name for r in helicopter.regions]
    assert from_text.bounding_box == helicopter.bounding_box


def test_render_matches_the_cli(helicopter, run_cli, tmp_path):
    out = tmp_path / "cli.png"
    run_cli("render", HELICOPTER, "--size", "160x120", "--aov", "region,depth", "-o", out)
    image = helicopter.render(size=(160, 120))
    assert image.rgb.shape == (120, 160, 3) and image.rgb.dtype == np.float32
    assert image.region.dtype == np.int32
    region_png = np.array(PILImage.open(tmp_path / "cli.region.png")).astype(np.int32)
    assert np.array_equal(image.region + 1, region_png)
    assert (image.region == -1).any() and (image.region >= 0).any()
    assert np.isinf(image.depth[image.region == -1]).all()
    image.save(tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == out.read_bytes()
    assert image._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


def test_camera_matches_the_cli_eye_and_at(helicopter, run_cli, tmp_path):
    out = tmp_path / "cli.png"
    run_cli(
        "render", HELICOPTER, "--size", "120x90", "--eye=-20,-30,12", "--at=0,0,2",
        "--fov", "35", "--aov", "region", "-o", out,
    )
    camera = sv.Camera(eye=(-20, -30, 12), at=(0, 0, 2), fov=35)
    image = helicopter.render(camera=camera, size=(120, 90))
    region_png = np.array(PILImage.open(tmp_path / "cli.region.png")).astype(np.int32)
    assert np.array_equal(image.region + 1, region_png)
    image.save(tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == out.read_bytes()


def test_transparent_lights_and_colours(helicopter):
    plain = helicopter.render(size=(80, 60))
    see_through = helicopter.render(size=(80, 60), transparent=["fuselage"])
    fuselage = 0
    assert (plain.region == fuselage).any()
    assert not (see_through.region == fuselage).any()
    with pytest.raises(ValueError, match="did you mean `fuselage`"):
        helicopter.render(size=(8, 6), transparent=["fuselag"])
    lit = helicopter.render(size=(80, 60), lights=[sv.Light.parallel((0, 0, -1), 0.5)])
    assert not np.array_equal(lit.rgb, plain.rgb)
    bare = helicopter.render(size=(80, 60), aovs=False)
    assert np.array_equal(bare.rgb, plain.rgb) and bare.region is None
    by_region = helicopter.render(size=(80, 60), color_by="region")
    assert np.array_equal(by_region.region, plain.region)
    assert not np.array_equal(by_region.rgb, plain.rgb)


def test_bad_input_raises_parse_error_located_as_the_cli(run_cli, tmp_path):
    deck = tmp_path / "bad.sv"
    deck.write_text("BODY a SPH (0,0,0) 1\nREGION r = +a\nBODY b SHP (0,0,0) 1\n")
    with pytest.raises(sv.ParseError) as caught:
        sv.load(deck)
    error = caught.value
    assert (error.file, error.line, error.column) == (str(deck), 3, 8)
    assert "SHP" in error.message
    cli = run_cli("info", deck, ok=(2,))
    assert str(error).replace("nothing was loaded", "nothing was written") == cli.stderr.rstrip()


def test_a_geometry_rule_is_a_parse_error_too(run_cli, tmp_path):
    deck = tmp_path / "negative.sv"
    deck.write_text("BODY a SPH (0,0,0) -1\nREGION r = +a\n")
    with pytest.raises(sv.ParseError) as caught:
        sv.load(deck)
    error = caught.value
    assert isinstance(error, ValueError)
    # Located at the body's card, as every reader locates body rules.
    assert (error.file, error.line) == (str(deck), 1)
    assert "radius" in error.message
    cli = run_cli("render", deck, "-o", tmp_path / "n.png", ok=(2,))
    assert str(error).replace("nothing was loaded", "nothing was written") == cli.stderr.rstrip()


def test_missing_file_and_bad_options():
    with pytest.raises(OSError):
        sv.load("no-such-file.sv")
    with pytest.raises(ValueError, match="unknown format"):
        sv.load(HELICOPTER, format="step")
    with pytest.raises(ValueError, match="fov"):
        sv.Camera(eye=(1, 0, 0), at=(0, 0, 0), fov=200)


def test_rendering_releases_the_gil(helicopter):
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)

    counter = threading.Thread(target=count)
    counter.start()
    before = len(ticks)
    helicopter.render(size=(640, 480), samples=2)
    during = len(ticks) - before
    stop.set()
    counter.join()
    assert during > 1000, during
