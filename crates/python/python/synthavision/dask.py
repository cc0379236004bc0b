"""Films and checks spread over a Dask cluster.

Frames are pure functions of the frame number, and a check's rays are
numbered: any worker renders any frame, or fires any share of the rays,
bit for bit as one machine would. Workers read the script or the model
themselves (a path they can see, or the text), and write frames into
``out_dir`` atomically beside their hashes, so a job that is stopped and
started again resumes, and a worker that dies has its share redone by
another (Dask reschedules it).

Without a ``client`` a ``LocalCluster`` is started on loopback only, with
no dashboard. On a cluster, pass its client, e.g. from ``dask-jobqueue``::

    from dask_jobqueue import SLURMCluster          # or PBSCluster
    cluster = SLURMCluster(cores=32, memory="16GB")
    cluster.scale(jobs=8)
    sv.dask.render_film("film.svs", "/shared/film", client=Client(cluster))

or from a Kubernetes deployment (``dask-kubernetes``'s ``KubeCluster``).
``out_dir`` (and a script's scenes) must then lie on storage every worker
and the client share.
"""

import contextlib
import os

from . import _native


@contextlib.contextmanager
def _client_or_local(client, workers):
    """``client``, or one of a loopback ``LocalCluster`` of ``workers``
    processes, closed afterwards."""
    if client is not None:
        yield client
        return
    from dask.distributed import Client, LocalCluster

    threads = max(1, (os.cpu_count() or 1) // workers)
    with LocalCluster(
        n_workers=workers,
        threads_per_worker=threads,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster, Client(cluster) as local:
        yield local


def _render_frames(script, out_dir, start, stop, size, shadows, srgb):
    """On a worker: frames ``start..stop`` of the script into ``out_dir``
    (those already there with the same hash are kept)."""
    film = _native.Film(script)
    report = film.render(
        out_dir,
        frames=range(start, stop),
        size=size,
        shadows=shadows,
        srgb=srgb,
        assemble=False,
    )
    return {"rendered": report["rendered"], "reused": report["reused"]}


def render_film(
    script,
    out_dir,
    frames=None,
    client=None,
    chunk=24,
    size=None,
    shadows=True,
    srgb=False,
    gif=True,
    mp4=True,
    workers=2,
):
    """Render the frames of ``script`` (a path; ``frames`` a range, default
    all) in chunks of ``chunk`` frames as Dask tasks, then assemble the GIF,
    MP4 and contact sheet on the client when every frame of the film is
    done. The frames are the CLI's ``film`` frames, byte for byte. Returns
    the report of ``Film.render`` with ``rendered`` listing the frames the
    workers rendered."""
    script = os.path.abspath(os.fspath(script))
    out_dir = os.path.abspath(os.fspath(out_dir))
    film = _native.Film(script)
    wanted = range(len(film)) if frames is None else frames
    if wanted.step != 1 or len(wanted) == 0:
        raise ValueError("frames: a non-empty range with step 1")
    if chunk < 1:
        raise ValueError("chunk must be at least 1")
    stop = min(wanted.stop, len(film))
    starts = list(range(wanted.start, stop, chunk))
    with _client_or_local(client, workers) as active:
        futures = [
            active.submit(
                _render_frames,
                script,
                out_dir,
                start,
                min(start + chunk, stop),
                size,
                shadows,
                srgb,
                pure=False,
            )
            for start in starts
        ]
        shares = active.gather(futures)
    rendered = sorted(f for share in shares for f in share["rendered"])
    report = film.render(
        out_dir,
        frames=range(wanted.start, stop),
        size=size,
        shadows=shadows,
        srgb=srgb,
        gif=gif,
        mp4=mp4,
    )
    report["rendered"] = rendered + report["rendered"]
    report["reused"] = sorted(set(report["reused"]) - set(rendered))
    return report


def _check_part(model, start, stop, options):
    """On a worker: chunks ``start..stop`` of the check's rays, as JSON."""
    return model.check_part((start, stop), **options)


def check(model, client=None, parts=None, workers=2, **options):
    """``model.check(**options)`` with its rays shared out in ``parts``
    (default: four per worker) as Dask tasks, and the shares' findings
    summed in the order a single machine sums them: the same report, bit
    for bit, but for ``seconds``. The model travels to the workers as what
    ``load`` was given (a path they can see, or the text)."""
    chunks = model.check_chunks(**options)
    with _client_or_local(client, workers) as active:
        if parts is None:
            parts = 4 * max(1, len(active.scheduler_info().get("workers", {})))
        parts = max(1, min(int(parts), chunks))
        cuts = [chunks * share // parts for share in range(parts + 1)]
        shared = active.scatter(model, broadcast=True)
        futures = [
            active.submit(_check_part, shared, start, stop, options, pure=False)
            for start, stop in zip(cuts, cuts[1:])
        ]
        found = active.gather(futures)
    return model.check_merge(found, **options)
