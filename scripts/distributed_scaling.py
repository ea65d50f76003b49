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


def best_of(n, f):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def scheduler_cost(workers, tasks=2000):
    with hd.local_cluster(workers) as c:
        c.wait_for_workers(workers)
        c.gather(c.map(_noop, range(50), pure=False))  # warm up connections
        wall = best_of(3, lambda: c.gather(c.map(_noop, range(tasks), pure=False)))
    return tasks / wall, wall / tasks


def city_scene(side, folder):
    path = os.path.join(folder, f"city{side * side}.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(city(side, 1), f)
    return hedra.read(path)


def step_cost(scene, k):
    """(seconds per step, seconds of preparation) of a single-process study, daytime steps."""
    start = f"{DAY}T10:00:00Z"
    one = best_of(2, lambda: hedra.sun_study(scene, start, start, 60))
    end = f"{DAY}T{10 + k // 4:02d}:{(k % 4) * 15:02d}:00Z"
    many = best_of(2, lambda: hedra.sun_study(scene, start, end, 15))
    per_step = (many - one) / k
    return per_step, max(0.0, one - per_step)


def distributed_rate(scene, workers, steps):
    start = f"{DAY}T08:00:00Z"
    minutes = 15 * (steps - 1)
    end = f"{DAY}T{8 + minutes // 60:02d}:{minutes % 60:02d}:00Z"
    reference = hedra.sun_study(scene, start, end, 15).to_json()
    with hd.local_cluster(workers) as c:
        c.wait_for_workers(workers)
        t0 = time.perf_counter()
        study = hd.sun_study(scene, start, end, 15, client=c, chunk=max(1, steps // (4 * workers)))
        wall = time.perf_counter() - t0
    assert study.to_json() == reference, "distributed study differs from one process"
    return steps / wall


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
    parser.add_argument("--study-steps", type=int, default=16, help="steps of the 1/2-worker run")
    args = parser.parse_args()

    print(f"machine: {os.cpu_count()} cores; hedra {getattr(hedra, '__version__', '?')}")
    rows = []
    for w in (1, 2):
        rate, per_task = scheduler_cost(w)
        rows.append((w, rate, per_task))
        print(f"empty tasks, {w} worker(s): {rate:.0f} tasks/s, {per_task * 1e3:.2f} ms per task")
    with tempfile.TemporaryDirectory() as folder:
        small = city_scene(args.small_side, folder)
        big = city_scene(args.side, folder)
        n_small, n_big = args.small_side ** 2, args.side ** 2
        s_small, p_small = step_cost(small, args.steps)
        s_big, p_big = step_cost(big, args.steps)
        print(f"one step, {n_small} boxes: {s_small * 1e3:.1f} ms (preparation {p_small * 1e3:.0f} ms)")
        print(f"one step, {n_big} boxes: {s_big * 1e3:.1f} ms (preparation {p_big * 1e3:.0f} ms)")
        exponent = math.log(s_big / s_small) / math.log(n_big / n_small)
        print(f"step cost grows as buildings^{exponent:.2f} between {n_small} and {n_big}")
        for w in (1, 2):
            print(f"{n_big}-box study of {args.study_steps} steps on {w} worker(s): "
                  f"{distributed_rate(big, w, args.study_steps):.2f} steps/s")

    # The projection: linear in buildings from the 1600-box step.
    steps, buildings = 35040, 50000
    step = s_big * buildings / n_big
    prep = p_big * buildings / n_big
    per_task = rows[0][2]
    print(f"\nprojection: {steps} steps x {buildings} buildings; one step {step:.1f} s "
          f"(linear from {n_big} boxes), preparation {prep:.1f} s per task")
    for w in (1, 10, 100):
        chunk = max(1, steps // (4 * w))
        tasks = math.ceil(steps / chunk)
        total = steps * step / w + math.ceil(tasks / w) * prep + tasks * per_task
        print(f"| {w} | {chunk} | {tasks} | {fmt(total)} |")


if __name__ == "__main__":
    main()
