"""Shared fixtures: the repository, the CLI to compare against, the shared
decks, and a short film script."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
HELICOPTER = REPO / "examples" / "helicopter" / "helicopter.sv"


@pytest.fixture(scope="session")
def cli():
    """The command-line tool: $SV_CLI, or target/debug/synthavision built
    now (a no-op when it is up to date)."""
    given = os.environ.get("SV_CLI")
    if given:
        return Path(given)
    subprocess.run(
        ["cargo", "build", "--quiet", "-p", "synthavision"], cwd=REPO, check=True
    )
    return REPO / "target" / "debug" / "synthavision"


@pytest.fixture(scope="session")
def run_cli(cli):
    """Run the CLI; returns the finished process (output as text)."""

    def run(*args, ok=(0,)):
        done = subprocess.run(
            [str(cli), *map(str, args)], capture_output=True, text=True
        )
        assert done.returncode in ok, done.stderr
        return done

    return run


@pytest.fixture(scope="session")
def shared_decks():
    """../shared/decks beside the repository: missing, the test fails
    (SV_SKIP_SHARED=1 skips it instead, as the Rust tests do)."""
    folder = REPO.parent / "shared" / "decks"
    if not folder.is_dir():
        if os.environ.get("SV_SKIP_SHARED") == "1":
            pytest.skip("SV_SKIP_SHARED=1 and the shared decks are missing")
        pytest.fail(
            f"the shared test decks are missing: {folder} does not exist. The tests "
            "read real inputs from ../shared/decks beside the repository."
        )
    return folder


@pytest.fixture
def film_script(tmp_path):
    """A film of 8 small frames of the helicopter, its main rotor turning."""
    script = tmp_path / "spin.svs"
    script.write_text(
        f'SCENE "{HELICOPTER}"\n'
        "FPS 4\n"
        "SIZE 96 72\n"
        "CAMERA EYE (-30,-42,9) AT (0,0,3) UP (0,0,1) FOV 40\n"
        "OBJECT MAINROTOR REGIONS hub blade_a blade_b\n"
        "AXIS MAST POINT (0,0,0) DIR (0,0,1)\n"
        "SPIN MAINROTOR (AXIS MAST, 10) PER FRAME\n"
        "HOLD 8\n"
    )
    return script
