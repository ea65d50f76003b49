#!/usr/bin/python3
"""The "Clipping" section of docs/benchmarks.md, from bench/clip_bench.cpp's JSON output.

Usage: clip_report.py RESULTS_DIR DOCS_DIR
Reads RESULTS_DIR/clip_bench.json (Google Benchmark, any number of repetitions; medians are
used), writes DOCS_DIR/clip_speed_accuracy.png and replaces the "## Clipping" section of
DOCS_DIR/benchmarks.md (appending it, or creating the page, when there is none).
`clipping(results, docs, quick)` returns the same section, for a report that builds the whole
page from a list of sections.
"""
import json
import os
import statistics

import matplotlib

from bench_common import collect, machine, standalone

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SHAPES = {0: "box (6 faces)", 1: "icosahedron (20 faces)"}
DATASETS = {0: "random segments", 1: "segments through vertices, along edges, in face planes"}
VARIANTS = {0: "Cyrus–Beck, exact decisions", 1: "Cyrus–Beck, plain double", 2: "midpoint subdivision"}
TARGET = 100e6  # segments/s, 2 threads, 6-face body (docs/design.md)


def median(entries, key):
    return statistics.median(e[key] for e in entries)


def fmt_rate(r):
    return f"{r / 1e6:.1f}"


def fmt_err(e):
    return "0" if e == 0 else f"{e:.1e}"


def throughput_table(runs):
    rate = {}
    extra = {}
    for (base, args), entries in runs.items():
        a = dict(args)
        if base in ("BM_Memcpy", "BM_Batch", "BM_PlainScalar", "BM_ExactScalar"):
            name = "BM_Batch0" if base == "BM_Batch" and not a.get("avx2", 1) else base
            rate[(name, a.get("shape", -1), a.get("threads", 1))] = median(entries, "items_per_second")
            if base == "BM_Batch":
                extra[(a["shape"], a["threads"])] = median(entries, "exact_path_fraction")
    lines = ["### Throughput", "",
             f"{int(runs_segments(runs) / 1e6)} M random segments (both ends uniform in [−2, 2]³; the box is "
             "[−1, 1]³, the icosahedron has circumradius 1.2), in M segments/s (median of the "
             "repetitions). *vs scalar*: against the plain scalar loop (the course's algorithm of "
             "docs/algorithms.md §4 in double, one segment at a time) on the same clipper; *of roofline*: against copying the "
             "same six coordinate arrays with the same number of threads (48 bytes read and written "
             "per segment; the batch reads 48 and writes 25).", "",
             "| method | threads | box (6 faces) | vs scalar | of roofline | icosahedron (20 faces) | vs scalar | of roofline |",
             "|---|---|---|---|---|---|---|---|"]
    rows = [("memory copy (roofline)", "BM_Memcpy", 1), ("memory copy (roofline)", "BM_Memcpy", 2),
            ("plain scalar loop (course, double)", "BM_PlainScalar", 1),
            ("exact scalar `clip_segment`", "BM_ExactScalar", 1),
            ("batch `clip_batch` (exact, SSE2 baseline code)", "BM_Batch0", 1),
            ("batch `clip_batch` (exact, AVX2)", "BM_Batch", 1),
            ("batch `clip_batch` (exact, AVX2)", "BM_Batch", 2)]
    for label, base, threads in rows:
        cells = [label, str(threads)]
        for shape in (0, 1):
            key = (base, -1 if base == "BM_Memcpy" else shape, threads)
            r = rate.get(key)
            scalar = rate.get(("BM_PlainScalar", shape, 1))
            roof = rate.get(("BM_Memcpy", -1, threads))
            if r is None:
                cells += ["–", "–", "–"]
                continue
            cells.append(fmt_rate(r))
            cells.append(f"{r / scalar:.1f}×" if scalar and base != "BM_Memcpy" else "–")
            cells.append(f"{100 * r / roof:.0f} %" if roof else "–")
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    box2 = rate.get(("BM_Batch", 0, 2))
    if box2 is not None:
        verdict = "met" if box2 >= TARGET else "not met"
        lines.append(f"Target (docs/design.md): ≥ 100 M segments/s on 2 threads against the 6-face body: "
                     f"**{verdict}** ({fmt_rate(box2)} M/s).")
    if extra:
        worst = round(max(extra.values()) * runs_segments(runs))
        lines.append(f"Segments that went through the exact fallback of the batch: {worst} of "
                     f"{int(runs_segments(runs)):,} at most, on this random data (a segment goes there "
                     "only when a decision is within the rounding bound: an end point on or next to a "
                     "plane, two crossings at one point).")
    lines.append("")
    return lines


def runs_segments(runs):
    for (base, _), entries in runs.items():
        if base == "BM_Batch":
            return entries[0].get("segments", 0)
    return 0


def accuracy(runs):
    rows = {0: [], 1: []}
    for (base, args), entries in runs.items():
        if base != "BM_Accuracy":
            continue
        a = dict(args)
        ns = statistics.median(1e9 / e["items_per_second"] for e in entries)
        rows[a["dataset"]].append({
            "variant": a["variant"], "eps": 10.0 ** -a["neg_log10_eps"] if a["variant"] == 2 else None,
            "ns": ns, "max_error": entries[0]["max_error"], "wrong": int(entries[0]["wrong_decisions"]),
            "worst": entries[0]["worst_wrong_length"]})
    for d in rows:
        rows[d].sort(key=lambda r: (r["variant"], -(r["eps"] or 0)))
    return rows


def accuracy_table(rows):
    lines = ["### Speed against accuracy", "",
             "20 000 segments per data set, each clipped by every method; errors against exact rational "
             "Cyrus–Beck (CGAL `Exact_rational`). *max error*: the largest distance between a computed "
             "end point and the exact one, over segments where both see a part; *wrong*: segments where "
             "one sees a part and the other none (touching points included); *longest wrong part*: the "
             "length of the longest part missed or invented; *time ÷ exact*: the method's time over exact-decision Cyrus–Beck's on the same data. Random segments against the icosahedron "
             "(circumradius 1.2); built segments against a pyramid with integer coordinates (base "
             "4 × 4, height 4), whose rounded unit-normal body matrix is what plain double works with.", ""]
    for d, title in DATASETS.items():
        lines += [f"**{title}**", "",
                  "| method | ε | ns / segment | time ÷ exact | max error | wrong | longest wrong part |",
                  "|---|---|---|---|---|---|---|"]
        exact_ns = next((r["ns"] for r in rows[d] if r["variant"] == 0), None)
        for r in rows[d]:
            eps = f"{r['eps']:.0e}" if r["eps"] else "–"
            ratio = f"{r['ns'] / exact_ns:.2f}" if exact_ns else "–"
            lines.append(f"| {VARIANTS[r['variant']]} | {eps} | {r['ns']:.0f} | {ratio} | {fmt_err(r['max_error'])} | "
                         f"{r['wrong']} | {fmt_err(r['worst'])} |")
        lines.append("")
    return lines


def chart(rows, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    floor = 1e-18
    for ax, (d, title) in zip(axes, DATASETS.items()):
        mids = [r for r in rows[d] if r["variant"] == 2]
        ax.plot([r["ns"] for r in mids], [max(r["max_error"], floor) for r in mids], "o-",
                color="tab:green", label="midpoint subdivision")
        for r in mids:
            ax.annotate(f"ε={r['eps']:.0e}", (r["ns"], max(r["max_error"], floor)), fontsize=7,
                        textcoords="offset points", xytext=(4, 4))
        for variant, color, marker in ((0, "tab:blue", "s"), (1, "tab:red", "^")):
            for r in rows[d]:
                if r["variant"] != variant:
                    continue
                label = VARIANTS[variant] + (f" ({r['wrong']} wrong)" if r["wrong"] else "")
                ax.plot([r["ns"]], [max(r["max_error"], floor)], marker, color=color, markersize=9,
                        label=label)
                if r["wrong"]:
                    # Where it breaks: the longest part it missed or invented.
                    ax.plot([r["ns"]], [max(r["worst"], floor)], marker, color=color, markersize=9,
                            fillstyle="none", label=VARIANTS[variant] + ": longest wrong part")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time per segment (ns)")
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("max end-point error vs exact")
    fig.suptitle("Clipping: speed against accuracy (errors of 0 drawn at 1e-18)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def throughput_chart(runs, path):
    rate = {}
    for (base, args), entries in runs.items():
        a = dict(args)
        if base in ("BM_Memcpy", "BM_Batch", "BM_PlainScalar", "BM_ExactScalar") and a.get("avx2", 1):
            rate[(base, a.get("shape", -1), a.get("threads", 1))] = median(entries, "items_per_second") / 1e6
    bars = [("plain scalar", "BM_PlainScalar", 1), ("exact scalar", "BM_ExactScalar", 1),
            ("batch, 1 thread", "BM_Batch", 1), ("batch, 2 threads", "BM_Batch", 2)]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    width = 0.38
    for i, (shape, color) in enumerate(((0, "tab:blue"), (1, "tab:orange"))):
        xs = [j + (i - 0.5) * width for j in range(len(bars))]
        ys = [rate.get((base, shape, threads), 0) for _, base, threads in bars]
        ax.bar(xs, ys, width, color=color, label=SHAPES[shape])
        for x, y in zip(xs, ys):
            ax.annotate(f"{y:.0f}", (x, y), ha="center", fontsize=7, textcoords="offset points",
                        xytext=(0, 2))
    for threads, style in ((1, ":"), (2, "--")):
        roof = rate.get(("BM_Memcpy", -1, threads))
        if roof:
            ax.axhline(roof, color="gray", linestyle=style, linewidth=1,
                       label=f"memory copy, {threads} thread{'s' if threads > 1 else ''}")
    ax.axhline(TARGET / 1e6, color="tab:red", linewidth=1, label="target, 6 faces, 2 threads")
    ax.set_xticks(range(len(bars)))
    ax.set_xticklabels([b[0] for b in bars])
    ax.set_ylabel("M segments / s")
    ax.set_title("Batch Cyrus–Beck throughput", fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def clipping(results, docs, quick=False):
    path = os.path.join(results, "clip_bench.json")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        runs = collect(json.load(f))
    rows = accuracy(runs)
    chart(rows, os.path.join(docs, "clip_speed_accuracy.png"))
    throughput_chart(runs, os.path.join(docs, "clip_throughput.png"))
    lines = ["## Clipping", "",
             f"Measured on {machine()}, by `bench/clip_bench.cpp`"
             f"{' (quick run)' if quick else ''}; see docs/clipping.md for the methods."]
    if os.environ.get("HEDRA_BENCH_NOTE"):  # conditions of the run worth knowing
        lines.append(os.environ["HEDRA_BENCH_NOTE"])
    lines.append("")
    lines += throughput_table(runs)
    lines += ["![Clipping: throughput](clip_throughput.png)", ""]
    lines += accuracy_table(rows)
    lines += ["![Clipping: speed against accuracy](clip_speed_accuracy.png)", ""]
    return "\n".join(lines) + "\n"



def main():
    standalone(clipping, "clip_bench", "## Clipping")


if __name__ == "__main__":
    main()
