#!/usr/bin/env python3
"""Measures what docs/distributed.md's scaling table reports, on this machine:

- the scheduler's cost per task: 2000 empty tasks on a LocalCluster of 1 and of 2 worker
  processes (one thread each); tasks per second and wall time per task;
- the time of one sun-study step of a city of N x N boxes (scripts/make_city_scene.py), in one
  process: a study of 1 step and one of k + 1 steps, per step = difference / k (so the scene's
  preparation, paid once per task, is reported apart); also for a smaller city, to see how the
  step cost grows with the number of buildings;
- the same city's study on 1 and 2 workers through hedra.distributed.sun_study (steps/s).

Then it projects, from those measured costs, a year of 15-minute steps (35 040) on a district
of 50 000 buildings on 1, 10 and 100 workers, assuming the per-step cost linear in buildings.
Prints a Markdown table; run with PYTHONPATH=build/python /usr/bin/python3.
"""

import argparse
import json
import math
import os
import pickle
import sys
import tempfile
import time

import hedra
import hedra.distributed as hd

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_city_scene import city  # noqa: E402

DAY = "2026-06-21"


def _noop(i):
    return i


def _cpu():
    return time.process_time()


def best_of(n, f):
    """(wall, cpu) seconds of the fastest of n runs of f in this process."""
    best = None
    for _ in range(n):
        w0, c0 = time.perf_counter(), time.process_time()
        f()
        t = (time.perf_counter() - w0, time.process_time() - c0)
        best = t if best is None or t[0] < best[0] else best
    return best


def scheduler_cost(workers, tasks=2000):
    """(tasks/s, wall s per task, scheduler + client CPU s per task, worker CPU s per task)
    of empty tasks. The LocalCluster's scheduler runs in this process, so this process's CPU
    time is the scheduler's and the client's."""
    with hd.local_cluster(workers) as c:
        c.wait_for_workers(workers)
        c.gather(c.map(_noop, range(50), pure=False))  # warm up the connections
        runs = []
        for _ in range(3):
            w_cpu = sum(c.run(_cpu).values())
            w0, c0 = time.perf_counter(), time.process_time()
            c.gather(c.map(_noop, range(tasks), pure=False))
            wall, cpu = time.perf_counter() - w0, time.process_time() - c0
            runs.append((wall, cpu, sum(c.run(_cpu).values()) - w_cpu))
        wall, cpu, wcpu = min(runs)
    return tasks / wall, wall / tasks, cpu / tasks, wcpu / tasks


def city_scene(side, folder):
    path = os.path.join(folder, f"city{side * side}.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(city(side, 1), f)
    return hedra.read(path)


def step_cost(scene, k):
    """Per step and for the preparation (paid once per task): (wall, cpu) seconds of a
    single-process, single-thread study of daytime 15-minute steps: 1 step against k + 1."""
    start = f"{DAY}T10:00:00Z"
    minutes = 15 * k
    end = f"{DAY}T{10 + minutes // 60:02d}:{minutes % 60:02d}:00Z"
    one = best_of(3, lambda: hedra.sun_study(scene, start, start, 15, threads=1))
    many = best_of(3, lambda: hedra.sun_study(scene, start, end, 15, threads=1))
    per_step = tuple((m - o) / k for m, o in zip(many, one))
    prep = tuple(max(0.0, o - p) for o, p in zip(one, per_step))
    return per_step, prep


def distributed_rate(scene, workers, steps):
    """(steps/s wall, CPU s per step on the workers, CPU s per step in this process: client and
    scheduler) of hedra.distributed.sun_study on `workers` processes, checked against the
    single-process study."""
    start = f"{DAY}T08:00:00Z"
    minutes = 15 * (steps - 1)
    end = f"{DAY}T{8 + minutes // 60:02d}:{minutes % 60:02d}:00Z"
    reference = hedra.sun_study(scene, start, end, 15).to_json()
    with hd.local_cluster(workers) as c:
        c.wait_for_workers(workers)
        w_cpu = sum(c.run(_cpu).values())
        t0, c0 = time.perf_counter(), time.process_time()
        study = hd.sun_study(scene, start, end, 15, client=c)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        w_cpu = sum(c.run(_cpu).values()) - w_cpu
    assert study.to_json() == reference, "distributed study differs from one process"
    tasks = math.ceil(steps / math.ceil(steps / (4 * workers)))  # hedra.distributed's default
    return steps / wall, w_cpu / steps, cpu / steps, tasks


def fmt(seconds):
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} days"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=40, help="city of SIDE x SIDE boxes")
    parser.add_argument("--small-side", type=int, default=20)
    parser.add_argument("--steps", type=int, default=8, help="steps timed per city")
    parser.add_argument("--study-steps", type=int, default=32, help="steps of the 1/2-worker run")
    args = parser.parse_args()

    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}; "
          f"hedra {getattr(hedra, '__version__', '?')}")
    sched = {}
    for w in (1, 2):
        rate, wall, cpu, wcpu = scheduler_cost(w)
        sched[w] = (rate, wall, cpu, wcpu)
        print(f"empty tasks, {w} worker(s): {rate:.0f} tasks/s, {wall * 1e3:.2f} ms wall per task, "
              f"scheduler+client CPU {cpu * 1e3:.2f} ms, worker CPU {wcpu * 1e3:.2f} ms per task")
    with tempfile.TemporaryDirectory() as folder:
        small = city_scene(args.small_side, folder)
        big = city_scene(args.side, folder)
        n_small, n_big = args.small_side ** 2, args.side ** 2
        print(f"scene of {n_big} boxes: {len(pickle.dumps(big)) / 1e6:.2f} MB pickled")
        costs = {}
        for n, scene in ((n_small, small), (n_big, big)):
            (sw, sc), (pw, pc) = step_cost(scene, args.steps)
            costs[n] = (sc, pc)
            print(f"one step, {n} boxes: {sw * 1e3:.1f} ms wall, {sc * 1e3:.1f} ms CPU; "
                  f"preparation {pw * 1e3:.0f} ms wall, {pc * 1e3:.0f} ms CPU")
        exponent = math.log(costs[n_big][0] / costs[n_small][0]) / math.log(n_big / n_small)
        print(f"step CPU cost grows as buildings^{exponent:.2f} between {n_small} and {n_big}")
        per_task_worker, per_task_client = [], []
        for w in (1, 2):
            rate, wcpu, ccpu, tasks = distributed_rate(big, w, args.study_steps)
            n = args.study_steps
            per_task_worker.append(max(0.0, (wcpu - costs[n_big][0]) * n / tasks))
            per_task_client.append(ccpu * n / tasks)
            print(f"{n_big}-box study of {n} steps on {w} worker(s), {tasks} tasks: {rate:.2f} "
                  f"steps/s; per step {wcpu * 1e3:.1f} ms CPU on the workers, "
                  f"{ccpu * 1e3:.1f} ms in the client and scheduler; per task "
                  f"{per_task_worker[-1] * 1e3:.0f} ms worker CPU beyond the steps, "
                  f"{per_task_client[-1] * 1e3:.0f} ms client CPU")

    # The projection: CPU costs linear in buildings from the 1600-box city; one core per
    # worker; about four tasks per worker (hedra.distributed's default chunk), run in rounds.
    steps, buildings = 35040, 50000
    scale = buildings / n_big
    step = costs[n_big][0] * scale
    task_worker = max(per_task_worker) * scale  # the scene in, preparation, the slice out
    task_client = max(per_task_client) * scale  # slices unpickled (each carries the scene)
    per_task = sched[1][2]
    faces = 6 * buildings
    print(f"\nprojection: {steps} steps x {buildings} buildings; one step {step:.2f} s CPU "
          f"(linear from {n_big} boxes), {task_worker:.2f} s worker CPU and {task_client:.2f} s "
          f"client CPU per task, scheduler {per_task * 1e3:.2f} ms per task; lit fractions "
          f"{faces * 8 / 1e6:.1f} MB per step")
    print("| workers | steps per task | tasks | rounds | workers' time | client's time | total |")
    print("|---|---|---|---|---|---|---|")
    for w in (1, 10, 100):
        chunk = math.ceil(steps / (4 * w))
        tasks = math.ceil(steps / chunk)
        rounds = math.ceil(tasks / w)
        work = rounds * (chunk * step + task_worker)
        client = tasks * (task_client + per_task)  # serial, overlapping the work
        print(f"| {w} | {chunk} | {tasks} | {rounds} | {fmt(work)} | {fmt(client)} | "
              f"{fmt(max(work, client) + task_client)} |")

if __name__ == "__main__":
    main()
