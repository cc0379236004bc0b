"""Sections, id maps, rays, checks and volumes against the CLI's output
for the same inputs; real decks from ../shared/decks."""

import json

import numpy as np
import pytest
from PIL import Image as PILImage

import synthavision as sv
from conftest import HELICOPTER

SPHERES = """BODY a SPH (0,0,0) 1
BODY b SPH (1.5,0,0) 1
REGION A = +a
REGION B = +b
"""


@pytest.fixture(scope="module")
def helicopter():
    return sv.load(HELICOPTER)


def without_seconds(report):
    report = dict(report)
    report.pop("seconds")
    return report


def test_slice_matches_the_cli(helicopter, run_cli, tmp_path):
    out = tmp_path / "cli.png"
    printed = run_cli("slice", HELICOPTER, "--plane", "z=3", "--size", "200x150", "-o", out, "--json")
    legend = json.loads(printed.stdout)
    section = helicopter.slice(plane="z=3", size=(200, 150))
    section.save(tmp_path / "py.png")
    assert (tmp_path / "py.png").read_bytes() == out.read_bytes()
    assert section.legend == legend["regions"]
    assert section.overlaps == legend["overlaps"] and section.void == legend["void"]
    assert list(section.extent) == legend["extent"]
    assert section.region.shape == (150, 200)


def test_id_map_is_the_section_around_its_origin(helicopter):
    section = helicopter.slice(plane="z=3", size=(200, 150), legend=False)
    ids = helicopter.id_map(section.centre, section.extent, (200, 150), basis="xy")
    assert ids.shape == (150, 200, 2) and ids.dtype == np.int32
    same = np.mean(ids[..., 0] == section.region)
    assert same > 0.999, same
    # Moved by a quarter of the width, the picture moves with it.
    width = section.extent[0]
    shifted = (section.centre[0] + width / 4, section.centre[1], section.centre[2])
    moved = helicopter.id_map(shifted, section.extent, (200, 150))
    assert np.mean(moved[:, :150, 0] == ids[:, 50:, 0]) > 0.99


def test_id_map_marks_overlaps_as_openmc_does():
    spheres = sv.load(SPHERES)
    ids = spheres.id_map((0.75, 0, 0), (4, 2), (80, 40))
    assert (ids[20, 40] == [-3, -3]).all()
    assert ids[20, 10, 0] == 0 and ids[20, 70, 0] == 1
    assert ids[1, 1, 0] == -1


def test_shoot_matches_the_cli(helicopter, run_cli):
    printed = run_cli("shoot", HELICOPTER, "--from=-30,0,3", "--dir=1,0,0").stdout.splitlines()
    ray = helicopter.shoot((-30, 0, 3), (1, 0, 0))
    assert printed[0].endswith("in " + (", ".join(ray["start"]) or "no region"))
    rows = [line.split(None, 4) for line in printed[2:]]
    assert len(rows) == len(ray["crossings"]) > 4
    for row, crossing in zip(rows, ray["crossings"]):
        assert row[0] == f"{crossing['t']:.6f}"
        assert row[1:4] == [crossing["event"], crossing["body"], crossing["type"]]
        after = " + ".join(crossing["regions_after"]) or "(outside the geometry)"
        assert row[4].replace("  (overlap)", "") == after


def test_check_matches_the_cli(helicopter, run_cli):
    printed = run_cli("check", HELICOPTER, "--json", "--spacing", "0.25", ok=(0, 1))
    report = helicopter.check(spacing=0.25)
    assert without_seconds(report) == without_seconds(json.loads(printed.stdout))
    spheres = sv.load(SPHERES).check()
    assert spheres["overlaps"][0]["regions"] == ["A", "B"]
    assert spheres["refine"] == 4 and spheres["refine_rays"] > 0
    plain = sv.load(SPHERES).check(refine=0)
    assert plain["refine_rays"] == 0 and plain["smallest_feature"]["at_edges"] is None


def test_volume_matches_the_cli(helicopter, run_cli):
    printed = run_cli("volume", HELICOPTER, "--json", "--rel-error", "0.02")
    report = helicopter.volume(rel_error=0.02)
    assert without_seconds(report) == without_seconds(json.loads(printed.stdout))
    assert {r["region"] for r in report["regions"]} == {r.name for r in helicopter.regions}


def test_plot_draws_the_section_with_a_legend(helicopter):
    import matplotlib

    matplotlib.use("Agg")
    ax = helicopter.plot(plane="z=3", size=(100, 75))
    labels = [text.get_text() for text in ax.get_legend().get_texts()]
    section = helicopter.slice(plane="z=3", size=(100, 75))
    assert labels == [entry["label"] for entry in section.legend]


def test_model_pickles_as_its_source(helicopter):
    import pickle

    again = pickle.loads(pickle.dumps(helicopter))
    assert [r.name for r in again.regions] == [r.name for r in helicopter.regions]
    from_text = pickle.loads(pickle.dumps(sv.load(SPHERES)))
    assert [r.name for r in from_text.regions] == ["A", "B"]


def test_a_real_comgeom_deck_renders_as_the_cli(shared_decks, run_cli, tmp_path):
    deck = shared_decks / "comgeom" / "gift-sample-target-v4.cg"
    model = sv.load(deck)
    assert model.format == "comgeom" and len(model.regions) > 5
    run_cli("render", deck, "--size", "120x90", "--aov", "region", "-o", tmp_path / "c.png")
    image = model.render(size=(120, 90))
    region_png = np.array(PILImage.open(tmp_path / "c.region.png")).astype(np.int32)
    assert np.array_equal(image.region + 1, region_png)


def test_real_mcnp_and_openmc_inputs_agree(shared_decks):
    case = shared_decks / "mcnp-openmc" / "icsbep" / "heu-met-fast-003"
    mcnp = sv.load(case / "mcnp" / "case-1" / "input")
    openmc = sv.load(case / "openmc" / "case-1")
    assert (mcnp.format, openmc.format) == ("mcnp", "openmc")
    assert mcnp.materials and openmc.materials
    for model in (mcnp, openmc):
        ids = model.id_map((0, 0, 0), (30, 30), (60, 60), basis="xz")
        regions, materials = ids[..., 0], ids[..., 1]
        inside = regions >= 0
        assert inside.any()
        expected = np.array(
            [-1 if r.material_index is None else r.material_index for r in model.regions]
        )
        assert np.array_equal(materials[inside], expected[regions[inside]])
    assert np.allclose(mcnp.bounding_box, openmc.bounding_box)
