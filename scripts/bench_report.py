#!/usr/bin/python3
"""Writes docs/benchmarks.md and its charts from Google Benchmark JSON files.

Usage: bench_report.py RESULTS_DIR DOCS_DIR
       bench_report.py --perturbation RESULTS_DIR DOCS_DIR  (that section of docs/benchmarks.md only)
Each benchmark binary writes RESULTS_DIR/<name>.json; every section below reads the file it
knows and is skipped when the file is missing. Ratios carry the conclusions: each table says
how much faster (or how many fewer pieces) hedra is than each peer in the same run.
"""
import datetime
import json
import math
import os
import subprocess
import sys

import matplotlib

from bench_common import by_run_name as runs, fmt_times as fmt_ms, machine, times_ms as ms
from clip_report import clipping
from faces_report import faces_scaling
from hlr_report import hidden_lines
from lod_report import lod
from render_report import rendering
from shadows_report import shadows

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(results, name):
    path = os.path.join(results, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def geomean(xs):
    xs = [x for x in xs if x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def decomposition(results, docs, quick):
    data = load(results, "decompose_bench")
    if data is None:
        return ""
    r = runs(data)
    shapes = []
    table = {}
    for name, entries in r.items():
        parts = name.split("/")
        if parts[0] != "decompose":
            continue
        method, shape = parts[1], parts[2]
        if shape not in shapes:
            shapes.append(shape)
        table[(shape, method)] = (ms(entries), int(entries[0]["pieces"]), int(entries[0]["failed"]),
                                  int(entries[0]["faces"]))
    methods = [m for m in ["planes", "float", "cgal", "tetgen"] if any(k[1] == m for k in table)]
    lines = ["## Convex decomposition", "",
             "Time per decomposition in ms: median [min–max] over the repetitions; pieces. "
             "hedra `planes` is the exact method (single thread); `float` its floating-point variant "
             "(ε = 1e-9 × size); CGAL is `convex_decomposition_3` including the Nef polyhedron "
             "construction; TetGen is `-pQ` (tetrahedra). ✗ marks a failure.", "",
             "| shape | faces | " + " | ".join(f"{m} pieces | {m} ms" for m in methods) +
             " | CGAL ÷ planes time | CGAL ÷ planes pieces |",
             "|---|---|" + "---|---|" * len(methods) + "---|---|"]
    ratios, piece_ok, piece_total = [], 0, 0
    for shape in shapes:
        row = [shape, str(next(v[3] for k, v in table.items() if k[0] == shape))]
        for m in methods:
            v = table.get((shape, m))
            if v is None:
                row += ["not run", "not run"]
            elif v[2]:
                row += ["✗", fmt_ms(v[0])]
            else:
                row += [str(v[1]), fmt_ms(v[0])]
        p, c = table.get((shape, "planes")), table.get((shape, "cgal"))
        if p and c and not p[2]:
            ratio = c[0][0] / p[0][0]
            ratios.append(ratio)
            row += [f"{ratio:.1f}×", f"{c[1] / p[1]:.2f}"]
            piece_total += 1
            piece_ok += p[1] <= c[1]
        else:
            row += ["—", "—"]
        lines.append("| " + " | ".join(row) + " |")
    rotation_same = all(
        table[(s, "planes")][1] == table[(s + " rotated", "planes")][1]
        for s in shapes if not s.endswith("rotated") and (s + " rotated", "planes") in table)
    lines += ["",
              f"**hedra is {geomean(ratios):.1f}× faster than CGAL** (geometric mean over the {len(ratios)} "
              f"shapes CGAL ran), with at most CGAL's piece count on {piece_ok} of {piece_total} shapes; "
              f"hedra's piece count is {'the same' if rotation_same else 'NOT the same'} before and after "
              "rotation on every shape. CGAL is not run on the rotated comb 64 and the rotated plate 10×10: "
              "each takes CGAL minutes, longer than this whole run (docs/decomposition.md).", "",
              "![decomposition: time against pieces](decomposition.png)", ""]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    colours = {"planes": "tab:red", "float": "tab:orange", "cgal": "tab:blue", "tetgen": "tab:green"}
    for m in methods:
        xs = [v[0][0] for k, v in table.items() if k[1] == m and not v[2]]
        ys = [v[1] for k, v in table.items() if k[1] == m and not v[2]]
        label = {"planes": "hedra exact (planes)", "float": "hedra float", "cgal": "CGAL Nef",
                 "tetgen": "TetGen tetrahedra"}[m]
        ax.scatter(xs, ys, label=label, c=colours[m], marker="*" if m == "planes" else "o",
                   s=90 if m == "planes" else 30, alpha=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per decomposition (ms, log)")
    ax.set_ylabel("pieces (log)")
    ax.set_title("Decomposition suite: one point per shape and method")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "decomposition.png"), dpi=110)
    plt.close(fig)

    lines += perturbation(r, docs)
    return "\n".join(lines) + "\n"


METHOD_LABELS = {"planes": "hedra exact", "tolerance": "hedra exact after `--tolerance` (D = 1e-5)",
                 "float": "hedra float (ε = 1e-9)"}


def perturbation(r, docs):
    """The "Under perturbation" section (lines) and its chart, from decompose_bench's perturbed/ runs."""
    pert = {}
    for name, entries in r.items():
        parts = name.split("/")
        if parts[0] != "perturbed":
            continue
        e = entries[0]
        pert.setdefault(parts[1], []).append((e["delta"], e["failure_rate"], ms(entries)[0] / e["inputs"],
                                              e.get("pieces", float("nan")), int(e["inputs"])))
    if not pert:
        return []
    methods = [m for m in ["planes", "tolerance", "float"] if m in pert] + sorted(set(pert) - set(METHOD_LABELS))
    inputs = max(x[4] for v in pert.values() for x in v)
    lines = ["### Under perturbation",
             f"Suite shapes ({inputs} inputs per δ: rotated, triangulated) with every vertex moved by up to δ × size. "
             "*planes*: the exact method on the triangle soup; *tolerance*: the same after the command's "
             "`--tolerance D` merge (D = 1e-5 × size; time includes the merge); *float*: the floating-point "
             "variant. A failure is an exception or a broken result: a piece that is not convex by the exact "
             "test, piece volumes off the input's by more than 1e-9, and for planes and tolerance also a failed "
             "exact verification (every exact piece convex, exact volumes summing exactly to the input's) or a "
             "gap or overlap found by 200 sample points per input; all checked outside the timing. "
             "Time and pieces are per input.", "",
             "| δ | " + " | ".join(f"{m} failure rate | {m} ms | {m} pieces" for m in methods) + " |",
             "|---|" + "---|---|---|" * len(methods)]
    deltas = sorted({d for v in pert.values() for d, *_ in v})
    for d in deltas:
        row = [f"{d:.0e}"]
        for m in methods:
            hit = [x for x in pert[m] if x[0] == d]
            row += [f"{hit[0][1]:.0%}", f"{hit[0][2]:.3g}", f"{hit[0][3]:.1f}"] if hit else ["—", "—", "—"]
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", "![decomposition under perturbation](decomposition_perturbation.png)", ""]
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for m in methods:
        pts = sorted(pert[m])
        xs, ys = [p[2] for p in pts], [100 * p[1] for p in pts]
        ax.plot(xs, ys, marker="*" if m == "planes" else "o", markersize=12 if m == "planes" else 6,
                label=METHOD_LABELS.get(m, m))
        for d, rate, t, *_ in pts:
            ax.annotate(f"δ={d:.0e}", (t, 100 * rate), fontsize=6, textcoords="offset points", xytext=(3, 3))
    ax.set_xscale("log")
    ax.set_xlabel("time per decomposition (ms, log)")
    ax.set_ylabel("failure rate (%)")
    ax.set_title("Perturbed inputs: failure rate against time, one point per method and δ", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "decomposition_perturbation.png"), dpi=110)
    plt.close(fig)
    return lines


def replace_perturbation(results, docs):
    """Rewrites only the "Under perturbation" section of docs/benchmarks.md (and its chart) from
    RESULTS_DIR/decompose_bench.json, keeping the rest of the page."""
    data = load(results, "decompose_bench")
    if data is None:
        sys.exit(f"{results}/decompose_bench.json: missing")
    lines = perturbation(runs(data), docs)
    if not lines:
        sys.exit(f"{results}/decompose_bench.json: no perturbed/ runs")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    # A quick page may carry a full faces-scaling run (scripts/faces_scaling.py and faces_bench
    # run on their own at the same commit, into the same results): say so.
    faces_full = False
    faces_path = os.path.join(results, "faces_scaling.json")
    if quick and os.path.exists(faces_path):
        with open(faces_path) as f:
            faces_full = not json.load(f).get("quick", True)
    lines.insert(1, f"This section alone was rerun on {datetime.date.today().isoformat()} at commit "
                    f"{commit or 'unknown'} (`scripts/run-bench.sh --perturbation`, machine as above; "
                    f"{'quick' if os.environ.get('HEDRA_BENCH_QUICK') else 'full'} run; times are wall-clock, load average "
                    f"{os.getloadavg()[0]:.1f} on this machine when the run ended).")
    path = os.path.join(docs, "benchmarks.md")
    with open(path) as f:
        page = f.read().split("\n")
    begin = page.index("### Under perturbation")
    end = next(i for i in range(begin + 1, len(page)) if page[i].startswith("## ") or page[i].startswith("### "))
    page[begin:end] = lines
    with open(path, "w") as f:
        f.write("\n".join(page))


SECTIONS = [decomposition, clipping, hidden_lines, shadows, rendering, lod, faces_scaling]


def main():
    if sys.argv[1] == "--perturbation":
        replace_perturbation(sys.argv[2], sys.argv[3])
        return
    results, docs = sys.argv[1], sys.argv[2]
    quick = bool(os.environ.get("HEDRA_BENCH_QUICK"))
    body = "".join(section(results, docs, quick) for section in SECTIONS)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    # A quick page may carry a full faces-scaling run (scripts/faces_scaling.py and faces_bench
    # run on their own at the same commit, into the same results): say so.
    faces_full = False
    faces_path = os.path.join(results, "faces_scaling.json")
    if quick and os.path.exists(faces_path):
        with open(faces_path) as f:
            faces_full = not json.load(f).get("quick", True)
    head = ["# Benchmarks", "",
            f"Machine: {machine()}. Generated by `make {'bench-quick' if quick else 'bench'}` on "
            f"{datetime.date.today().isoformat()} at commit {commit or 'unknown'}; every number on this page "
            + ("comes from that one run" if not faces_full else
               "comes from that one run, except the faces scaling section, which comes from full runs of "
               "scripts/faces_scaling.py and bench/faces_bench.cpp at the same commit")
            + ". Regenerate with `make bench` (full) or `make bench-quick` (< 5 min)."
            + (" Every process, hedra's and its peers', ran with glibc's heaps on transparent huge pages "
               "(`GLIBC_TUNABLES=glibc.malloc.hugetlb=1`, set by scripts/run-bench.sh; the hedra command "
               "sets it for itself)." if "glibc.malloc.hugetlb=1" in os.environ.get("GLIBC_TUNABLES", "") else ""),
            ""]
    with open(os.path.join(docs, "benchmarks.md"), "w") as f:
        f.write("\n".join(head) + "\n" + body)


if __name__ == "__main__":
    main()
