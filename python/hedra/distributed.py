"""Sun studies and batch jobs on a Dask cluster, with the results of one process.

hedra grows no cluster code of its own: this module runs the Python module's functions as
Dask tasks (``python3-distributed``). Two entry points:

- :func:`sun_study` splits the time steps of a sun study into slices, ships the scene to every
  worker once (``client.scatter(..., broadcast=True)``), runs ``hedra.sun_study`` on each slice
  and joins the slices with ``hedra.combine_sun_studies`` in step order, so the result is the
  single-process ``hedra.sun_study`` bit for bit (the hours of sun are summed by the combine in
  the same order as in one process, never by whichever slice finishes first).
- :func:`map_files` runs ``"decompose"``, ``"render"``, ``"hidden_lines"`` or ``"info"`` over
  many files; results come back in input order, one :class:`FileResult` per file, a failing
  file never losing the others.

With ``client=None`` both start a :class:`distributed.LocalCluster` of worker processes on
this machine (loopback only) and close it afterwards. To use a cluster of several machines,
pass ``distributed.Client("tcp://scheduler:8786")`` (docs/distributed.md).

Cost: one task per slice of ``chunk`` steps; each task prepares the scene (convex pieces,
once per task), costs what the same steps cost in one process, and returns its slice (a
pickled SunStudy, which carries the scene) for the client to combine. The scheduler adds
about a millisecond per task (docs/distributed.md has the measured numbers).

``python3 -m hedra.distributed shadows SCENE --sun-hours START END STEP [--workers N |
--scheduler ADDRESS] --out FILE`` is what ``hedra shadows --workers/--scheduler`` runs: it
writes the ``sun_study`` part of the ``hedra shadows --json`` report.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime
import math
import os
import sys
import uuid
from typing import Any, Callable, Iterator, Sequence

import hedra

__all__ = ["sun_study", "map_files", "FileResult", "local_cluster", "main"]

# ---- Times ----

def _iso(time) -> str:
    """A datetime as ISO 8601 UTC text; text (ISO 8601 or hh:mm on the date of the scene's
    sun) as it is: the kernel parses it."""
    if isinstance(time, datetime.datetime):
        if time.tzinfo is not None:
            time = time.astimezone(datetime.timezone.utc).replace(tzinfo=None)
        return time.isoformat() + "Z"
    return str(time)


# ---- Clusters ----

@contextlib.contextmanager
def local_cluster(workers: int | None = None, threads_per_worker: int = 1) -> Iterator[Any]:
    """A Client on a LocalCluster of `workers` processes (default: one per core) listening on
    127.0.0.1 only, without a dashboard; closed on exit."""
    from distributed import Client, LocalCluster

    n = workers if workers else (os.cpu_count() or 1)
    cluster = LocalCluster(n_workers=n, threads_per_worker=threads_per_worker, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    try:
        with Client(cluster) as client:
            yield client
    finally:
        cluster.close()


@contextlib.contextmanager
def _client_or_local(client, workers: int | None) -> Iterator[Any]:
    if client is not None:
        yield client
    else:
        with local_cluster(workers) as c:
            yield c


def _thread_count(client) -> int:
    info = client.scheduler_info().get("workers", {})
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.values()))


# ---- Sun study ----

def _study_slice(scene, start: str, end: str, step_minutes: float, first: int, count: int,
                 options: dict):
    """One task: steps [first, first + count) of the study (count -1: to the end)."""
    return hedra.sun_study(scene, start, end, step_minutes, first_step=first, step_count=count,
                           **options)


def _slices(total: int, chunk: int) -> list[tuple[int, int]]:
    """(first, count) per task; the last slice runs to the end (count -1)."""
    out = [(first, chunk) for first in range(0, total, chunk)]
    out[-1] = (out[-1][0], -1)
    return out


def sun_study(scene, start, end, step_minutes: float, client=None, chunk: int | None = None, *,
              workers: int | None = None, retries: int = 2, **options):
    """The sun study of `scene` (a hedra.Scene or a scene file) on a Dask cluster: the same
    SunStudy as ``hedra.sun_study(scene, start, end, step_minutes, **options)``, bit for bit.

    options: those of hedra.sun_study (latitude, longitude, grid=(body, face, spacing),
    threads: kernel threads per task, default 1). chunk: steps per task (default: about four
    tasks per worker thread). client: a
    distributed.Client; None starts a LocalCluster of `workers` processes (default: one per
    core) and closes it after. retries: how often a task that raised is run again (a worker
    that dies is replaced by its nanny and its tasks rescheduled by Dask in any case).
    Cost: steps / chunk tasks, each the steps' single-process cost plus one preparation of
    the scene and ~1 ms of scheduling.
    \\throw hedra.InvalidInput for times out of order, a step <= 0 or a bad scene.
    """
    if isinstance(scene, (str, os.PathLike)):
        scene = hedra.read(os.fspath(scene))
    # One kernel thread per task: a worker process is one core (dask worker --nthreads 1);
    # the result does not depend on it.
    options.setdefault("threads", 1)
    start_text, end_text = _iso(start), _iso(end)
    # The kernel's count of the schedule's steps (it also checks the times and the step).
    total = hedra.sun_study_steps(scene, start_text, end_text, float(step_minutes))
    with _client_or_local(client, workers) as c:
        if chunk is None:
            chunk = max(1, math.ceil(total / (4 * _thread_count(c))))
        if int(chunk) < 1:
            raise hedra.InvalidInput(f"sun study: chunk must be at least 1 step, got {chunk}")
        chunk = int(chunk)
        shared = c.scatter(scene, broadcast=True)
        run = uuid.uuid4().hex[:12]
        futures = [
            c.submit(_study_slice, shared, start_text, end_text, float(step_minutes), first,
                     count, options, key=f"hedra-sun-study-{run}-{i:06d}", retries=retries,
                     pure=False)
            for i, (first, count) in enumerate(_slices(total, chunk))
        ]
        parts = c.gather(futures)  # in submission order, i.e. step order
        del futures, shared
    return hedra.combine_sun_studies(parts)


# ---- Batch jobs over files ----

@dataclasses.dataclass
class FileResult:
    """The outcome of one file of map_files: `value` when ok, else `error` (one line that
    names the file)."""

    path: str
    ok: bool
    value: Any = None
    error: str | None = None

    def __repr__(self) -> str:
        what = type(self.value).__name__ if self.ok else self.error
        return f"FileResult({self.path!r}, ok={self.ok}, {what})"


def _info(path: str, **options) -> list[dict]:
    scene = hedra.read(path, **options)
    out = []
    for name, body in scene.bodies.items():
        out.append({"name": name, "vertices": len(body.vertices), "faces": len(body.faces),
                    "volume": body.volume, "area": body.area, "convex": body.is_convex})
    return out


def _decompose(path: str, **options) -> dict:
    scene = hedra.read(path)
    return {name: hedra.decompose(body, **options) for name, body in scene.bodies.items()}


def _render(path: str, **options):
    return hedra.render(hedra.read(path), **options)


def _hidden_lines(path: str, **options) -> dict:
    r = hedra.hidden_lines(hedra.read(path), **options)
    out = {}
    for part in ("visible", "hidden", "junction", "outline"):
        if hasattr(r, part):
            out[part] = getattr(r, part)
    return out


_FUNCTIONS: dict[str, Callable[..., Any]] = {
    "info": _info, "decompose": _decompose, "render": _render, "hidden_lines": _hidden_lines,
}


def _one_line(path: str, e: BaseException) -> str:
    text = " ".join(str(e).split()) or type(e).__name__
    return text if path in text else f"{path}: {text}"


def _run_file(function_name: str, path: str, options: dict) -> FileResult:
    """One task: never raises for a bad file, so that the others are not lost."""
    try:
        return FileResult(path, True, _FUNCTIONS[function_name](path, **options))
    except Exception as e:  # noqa: BLE001 - every failure is the file's result
        return FileResult(path, False, error=_one_line(path, e))


def map_files(function_name: str, paths: Sequence[str | os.PathLike], client=None, *,
              workers: int | None = None, retries: int = 1, **options) -> list[FileResult]:
    """Runs `function_name` ("decompose", "render", "hidden_lines" or "info") on every file
    as one Dask task each. Returns one FileResult per path, in input order: value = the list
    of body records ("info"), {body name: [convex pieces]} ("decompose"), the image
    ("render"), {"visible", "hidden", "junction", ...: segment arrays} ("hidden_lines").
    A file that fails, or whose worker dies more often than Dask allows, gets ok=False and a
    one-line error naming it; the others are unaffected. options go to the hedra function.
    Paths must be readable by the workers (a shared file system on a multi-machine cluster).
    \\throw ValueError for an unknown function name.
    """
    if function_name not in _FUNCTIONS:
        raise ValueError(f"map_files: unknown function '{function_name}' "
                         f"(one of {', '.join(sorted(_FUNCTIONS))})")
    names = [os.fspath(p) for p in paths]
    if not names:
        return []
    with _client_or_local(client, workers) as c:
        run = uuid.uuid4().hex[:12]
        futures = [
            c.submit(_run_file, function_name, p, options,
                     key=f"hedra-{function_name}-{run}-{i:06d}", retries=retries, pure=False)
            for i, p in enumerate(names)
        ]
        results = []
        for p, f in zip(names, futures):
            try:
                results.append(f.result())
            except Exception as e:  # noqa: BLE001 - e.g. KilledWorker: this file's result
                results.append(FileResult(p, False, error=_one_line(p, e)))
        return results


# ---- The command line behind `hedra shadows --workers/--scheduler` ----

def _quiet_dask() -> None:
    import logging

    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


def _shadows(args) -> int:
    import json

    scene = hedra.read(args.scene)
    options = {}
    if args.grid:
        body, face, spacing = args.grid
        options["grid"] = (body, int(face), float(spacing))
    if args.scheduler:
        from distributed import Client

        timeout = {} if args.timeout is None else {"timeout": args.timeout}
        with Client(args.scheduler, **timeout) as client:
            study = sun_study(scene, args.start, args.end, args.step, client=client,
                              chunk=args.chunk, **options)
    else:
        study = sun_study(scene, args.start, args.end, args.step, workers=args.workers,
                          chunk=args.chunk, **options)
    text = study.to_json()
    json.loads(text)  # the caller parses it: fail here, with a message, if it is not JSON
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(text)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """`python3 -m hedra.distributed shadows ...`; exit 0, 2 (usage) or 3 (any failure, one
    line on stderr)."""
    import argparse

    parser = argparse.ArgumentParser(prog="python3 -m hedra.distributed")
    sub = parser.add_subparsers(dest="command", required=True)
    sh = sub.add_parser("shadows", help="a sun study on a Dask cluster; writes its JSON")
    sh.add_argument("scene")
    sh.add_argument("--sun-hours", nargs=3, metavar=("START", "END", "STEP"), required=True)
    sh.add_argument("--grid", nargs=3, metavar=("BODY", "FACE", "SPACING"))
    where = sh.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, help="local cluster of N processes")
    where.add_argument("--scheduler", help="address of a running scheduler (tcp://host:8786)")
    sh.add_argument("--chunk", type=int, default=None, help="steps per task")
    sh.add_argument("--timeout", type=float, default=None,
                    help="seconds to reach the scheduler (default: Dask's "
                    "distributed.comm.timeouts.connect, 30 s)")
    sh.add_argument("--out", required=True, help="where the sun_study JSON goes")
    args = parser.parse_args(argv)
    args.start, args.end = args.sun_hours[0], args.sun_hours[1]
    try:
        args.step = float(args.sun_hours[2])
    except ValueError:
        parser.error(f"--sun-hours: the step '{args.sun_hours[2]}' is not a number of minutes")
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    _quiet_dask()
    try:
        return _shadows(args)
    except Exception as e:  # noqa: BLE001 - one line for the command line, exit 3
        where = f" (scheduler {args.scheduler})" if args.scheduler else ""
        text = " ".join(str(e).split()) or type(e).__name__
        if args.scene not in text:
            text = f"{args.scene}: distributed sun study{where}: {text}"
        sys.stderr.write(text + "\n")
        return 3


if __name__ == "__main__":
    sys.exit(main())
