"""Films: frames as Images, films on disk, and the same on a Dask
LocalCluster of two worker processes, each byte for byte as the CLI's."""

import os
import signal
import threading
import time

import pytest

import synthavision as sv
import synthavision.dask
from conftest import HELICOPTER


@pytest.fixture
def cli_film(film_script, run_cli, tmp_path):
    """The CLI's frames of the script, by name."""
    out = tmp_path / "cli"
    run_cli("film", film_script, "-o", out, "--no-mp4")
    return out


def frames_of(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.glob("frame_*.png"))}


def test_frames_are_the_cli_frames(film_script, cli_film, tmp_path):
    film = sv.Film(film_script)
    assert len(film) == 8 and film.fps == 4 and film.frame_size == (96, 72)
    film.frame(5).save(tmp_path / "five.png")
    assert (tmp_path / "five.png").read_bytes() == (cli_film / "frame_000005.png").read_bytes()
    assert [image.width for image in film] == [96] * 8
    assert film[-1].region.shape == (72, 96)
    with pytest.raises(IndexError):
        film.frame(8)


def test_film_render_resumes_what_the_cli_began(film_script, cli_film, tmp_path, run_cli):
    out = tmp_path / "py"
    run_cli("film", film_script, "-o", out, "--frames", "0..3", "--no-mp4")
    report = sv.Film(film_script).render(out, mp4=False)
    assert report["reused"] == [0, 1, 2] and report["rendered"] == [3, 4, 5, 6, 7]
    assert report["gif"] == out / "film.gif"
    assert frames_of(out) == frames_of(cli_film)
    assert (out / "film.gif").read_bytes() == (cli_film / "film.gif").read_bytes()


def test_a_bad_script_is_a_located_parse_error(tmp_path):
    script = tmp_path / "bad.svs"
    script.write_text(f'SCENE "{HELICOPTER}"\nFPS 4\nHOLD x\n')
    with pytest.raises(sv.ParseError) as caught:
        sv.Film(script)
    assert (caught.value.file, caught.value.line) == (str(script), 3)


@pytest.fixture(scope="module")
def client():
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster, Client(cluster) as client:
        yield client


def test_a_film_on_two_workers_is_the_cli_film(film_script, cli_film, tmp_path, client):
    out = tmp_path / "dask"
    report = sv.dask.render_film(film_script, out, client=client, chunk=3, mp4=False)
    assert report["rendered"] == list(range(8)) and report["missing"] == []
    assert frames_of(out) == frames_of(cli_film)
    assert (out / "film.gif").read_bytes() == (cli_film / "film.gif").read_bytes()
    again = sv.dask.render_film(film_script, out, client=client, chunk=3, mp4=False)
    assert again["rendered"] == [] and again["reused"] == list(range(8))


def test_a_killed_workers_frames_are_redone(film_script, tmp_path, client):
    out, local = tmp_path / "killed", tmp_path / "local"
    size = (480, 360)
    sv.Film(film_script).render(local, size=size, mp4=False)
    pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]
    result = {}
    job = threading.Thread(
        target=lambda: result.update(
            sv.dask.render_film(film_script, out, client=client, chunk=1, size=size, mp4=False)
        )
    )
    job.start()
    deadline = time.time() + 60
    while not list(out.glob("frame_*.png")) and time.time() < deadline:
        time.sleep(0.005)
    os.kill(victim, signal.SIGKILL)
    done_when_killed = len(list(out.glob("frame_*.png")))
    job.join(timeout=300)
    assert 0 < done_when_killed < 8
    assert result["missing"] == []
    assert frames_of(out) == frames_of(local)
    assert victim not in client.run(os.getpid).values()


def test_a_check_on_two_workers_is_the_local_check(client):
    model = sv.load(HELICOPTER)
    local = model.check(spacing=0.3, random=2000)
    shared = sv.dask.check(model, client=client, parts=5, spacing=0.3, random=2000)
    local.pop("seconds")
    shared.pop("seconds")
    assert shared == local
