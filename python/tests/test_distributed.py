"""hedra.distributed on real Dask clusters (worker processes, loopback only): the distributed
sun study equals the single-process one bit for bit, its tasks run on every worker, a batch
over files keeps going past a bad file, and a worker that dies mid-study changes nothing.

The reference is always the single-process call of the same module (hedra.sun_study,
hedra.read, hedra.decompose), so each test fails if the distribution changes any result.
"""

import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import hedra
import hedra.distributed as hd

from distributed import Client, LocalCluster, WorkerPlugin, get_task_stream

ROOT = pathlib.Path(__file__).resolve().parents[2]
CITY = ROOT / "examples" / "city-block.json"
# The city's sun is at 52.5 N, 13.4 E (Berlin); a midsummer day, night to night, every 20
# minutes: 55 steps, some before sunrise and after sunset.
START, END, STEP = "2026-06-21T02:00:00Z", "2026-06-21T20:00:00Z", 20


def cluster(workers=2):
    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                        host="127.0.0.1", dashboard_address=None)


@pytest.fixture(scope="module")
def client():
    with cluster() as c, Client(c) as cl:
        cl.wait_for_workers(2)
        yield cl


@pytest.fixture(scope="module")
def city():
    return hedra.read(str(CITY))


@pytest.fixture(scope="module")
def reference(city):
    return hedra.sun_study(city, START, END, STEP)


def test_two_workers_give_the_single_process_study(client, city, reference):
    with get_task_stream(client=client) as stream:
        study = hd.sun_study(city, START, END, STEP, client=client, chunk=4)
    assert study.to_json() == reference.to_json()
    ref = json.loads(reference.to_json())
    # A real sun: day and night steps, and faces with different hours of sun.
    assert any(s["sun_up"] for s in ref["steps"]) and not all(s["sun_up"] for s in ref["steps"])
    assert len({f["sun_hours"] for f in ref["faces"]}) > 3
    tasks = [t for t in stream.data if str(t["key"]).startswith("hedra-sun-study")]
    assert len(ref["steps"]) == 55 and len(tasks) == 14
    workers = set(client.scheduler_info()["workers"])
    assert {t["worker"] for t in tasks} == workers and len(workers) == 2


def test_default_chunks_a_scene_file_and_local_times(client, reference):
    # hh:mm on the date of the scene's sun, as on the command line.
    assert hd.sun_study(str(CITY), "02:00", "20:00", STEP, client=client).to_json() == \
        reference.to_json()


def test_batch_reports_the_bad_file_and_returns_the_others(client, tmp_path):
    box = tmp_path / "box.off"
    box.write_text("OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                   "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n")
    bad = tmp_path / "broken.off"
    bad.write_text("OFF\n8 6 0\n0 0 0\nthis is not a number\n")
    missing = tmp_path / "missing.stl"
    paths = [str(CITY), str(bad), str(box), str(missing)]

    results = hd.map_files("info", paths, client=client)
    assert [r.path for r in results] == paths
    assert [r.ok for r in results] == [True, False, True, False]
    assert str(bad) in results[1].error and str(missing) in results[3].error
    for r in (results[0], results[2]):
        scene = hedra.read(r.path)
        assert [b["name"] for b in r.value] == list(scene.bodies)
        assert [b["volume"] for b in r.value] == [b.volume for b in scene.bodies.values()]
    assert results[2].value[0]["volume"] == 1.0

    pieces = hd.map_files("decompose", [str(bad), str(CITY)], client=client)
    assert not pieces[0].ok and str(bad) in pieces[0].error
    assert pieces[1].ok
    local = {n: hedra.decompose(b) for n, b in hedra.read(str(CITY)).bodies.items()}
    assert list(pieces[1].value) == list(local)
    for name, parts in local.items():
        assert [p.volume for p in pieces[1].value[name]] == [p.volume for p in parts]

    lines = hd.map_files("hidden_lines", [str(CITY), str(missing)], client=client)
    assert lines[0].ok and not lines[1].ok and str(missing) in lines[1].error
    local = hedra.hidden_lines(hedra.read(str(CITY)))
    for part in ("visible", "hidden", "junction"):
        assert np.array_equal(lines[0].value[part], getattr(local, part))
    assert len(lines[0].value["visible"]) > 100

    images = hd.map_files("render", [str(bad), str(CITY)], client=client, width=64, height=48)
    assert not images[0].ok and str(bad) in images[0].error
    local = hedra.render(hedra.read(str(CITY)), width=64, height=48)
    assert np.array_equal(np.asarray(images[1].value), np.asarray(local))

    with pytest.raises(ValueError, match="unknown function"):
        hd.map_files("explode", paths, client=client)


class DieOnFirstStudyTask(WorkerPlugin):
    """Kills the worker process that starts the first sun-study task, once per marker file
    (the file is created atomically, so exactly one worker dies, exactly once)."""

    def __init__(self, marker):
        self.marker = marker

    def transition(self, key, start, finish, **kwargs):
        if finish == "executing" and str(key).startswith("hedra-sun-study"):
            try:
                os.close(os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            except FileExistsError:
                return
            os._exit(1)


def test_a_worker_that_dies_mid_study_changes_nothing(city, reference, tmp_path):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    marker = tmp_path / "died"
    with cluster() as c, Client(c) as cl:
        cl.wait_for_workers(2)
        cl.register_worker_plugin(DieOnFirstStudyTask(str(marker)), name="die-once")
        study = hd.sun_study(city, START, END, STEP, client=cl, chunk=3)
        assert marker.exists()  # a worker did die
        cl.wait_for_workers(2, timeout=30)  # and its nanny started a new one
    assert study.to_json() == reference.to_json()


# ---- The command line: hedra shadows --workers / --scheduler ----

# ctest passes the command it built (HEDRA_BIN); by hand, build/hedra.
CLI = os.environ.get("HEDRA_BIN", str(ROOT / "build" / "hedra"))


def shadows(*args, env=None):
    return subprocess.run([CLI, "shadows", str(CITY), *args], capture_output=True, text=True,
                          env=env, timeout=120)


def test_cli_workers_write_the_same_json(tmp_path, city):
    one, two = tmp_path / "one.json", tmp_path / "two.json"
    # With a grid of sample points on the ground's top face (255 points, 2 m apart).
    hours = ["--sun-hours", START, END, str(STEP), "--grid", "ground", "5", "2"]
    a = shadows(*hours, "--json", str(one))
    b = shadows(*hours, "--workers", "2", "--json", str(two))
    assert a.returncode == 0 and b.returncode == 0, b.stderr
    ja, jb = json.loads(one.read_text()), json.loads(two.read_text())
    reference = hedra.sun_study(city, START, END, STEP, grid=("ground", 5, 2.0))
    assert ja["sun_study"] == jb["sun_study"] == json.loads(reference.to_json())
    assert len(set(ja["sun_study"]["grid"]["sun_hours"])) > 3
    # The same bytes, not just the same numbers (sun_study is the report's last key).
    assert one.read_text().split('"sun_study":')[1] == two.read_text().split('"sun_study":')[1]
    # Everything but the timing is the same report, and so is the printed summary.
    del ja["ms"], jb["ms"]
    assert ja == jb
    assert a.stdout.splitlines()[1:-1] == b.stdout.splitlines()[1:-1]  # not ms, not "wrote"


def test_cli_errors_are_one_line(tmp_path):
    hours = ["--sun-hours", START, END, str(STEP)]
    quick = dict(os.environ, DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="2s")
    dead = shadows(*hours, "--scheduler", "tcp://127.0.0.1:9", "--json", str(tmp_path / "x"),
                   env=quick)
    assert dead.returncode == 3 and len(dead.stderr.strip().splitlines()) == 1
    assert "127.0.0.1:9" in dead.stderr
    assert not (tmp_path / "x").exists()
    # No Dask: a `distributed` package that cannot be imported shadows the real one.
    fake = tmp_path / "nodask" / "distributed"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('No module named distributed')\n")
    env = dict(os.environ, PYTHONPATH=str(fake.parent))
    nodask = shadows(*hours, "--workers", "2", env=env)
    assert nodask.returncode == 3 and len(nodask.stderr.strip().splitlines()) == 1
    assert "distributed" in nodask.stderr
    # No Python at all.
    nopy = shadows(*hours, "--workers", "2", env=dict(os.environ, HEDRA_PYTHON="/nonexistent"))
    assert nopy.returncode == 3 and "/nonexistent" in nopy.stderr
    both = shadows(*hours, "--workers", "2", "--scheduler", "tcp://127.0.0.1:9")
    assert both.returncode == 2
    alone = shadows("--workers", "2")
    assert alone.returncode == 3 and "--sun-hours" in alone.stderr


def test_the_example_prints_the_commands_hours_of_sun(tmp_path):
    report = tmp_path / "one.json"
    hours = ["--sun-hours", START, END, str(STEP)]
    cli = shadows(*hours, "--json", str(report))
    assert cli.returncode == 0, cli.stderr
    example = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / "sun_study_dask.py"), str(CITY),
         *hours, "--workers", "2"], capture_output=True, text=True, timeout=120)
    assert example.returncode == 0, example.stderr
    lines = example.stdout.splitlines()
    assert lines[0] == next(l for l in cli.stdout.splitlines() if "sun study:" in l)
    faces = json.loads(report.read_text())["sun_study"]["faces"]
    assert [(b, int(f), float(h)) for b, f, h in (l.split() for l in lines[1:])] == \
        [(f["body"], f["face"], f["sun_hours"]) for f in faces]
