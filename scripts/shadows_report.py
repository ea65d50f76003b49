#!/usr/bin/python3
"""The "Shadows" section of docs/benchmarks.md, from bench/shadows_bench.cpp's JSON output.

Usage: shadows_report.py RESULTS_DIR DOCS_DIR
Reads RESULTS_DIR/shadows_bench.json (Google Benchmark, any number of repetitions; medians are
used), writes DOCS_DIR/shadows_speed_accuracy.png and replaces the "## Shadows" section of
DOCS_DIR/benchmarks.md (appending it, or creating the page, when there is none).
`shadows(results, docs, quick)` returns the same section, for a report that builds the whole
page from a list of sections.
"""
import json
import os

import matplotlib

from bench_common import collect, machine, standalone
from bench_common import fmt_times as fmt_ms, times_ms as med_ms

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TARGET_MS = 20.0      # N = 40 (docs/design.md)
TARGET_ERROR = 1e-9   # ground fraction against the CGAL exact union
FLOOR = 1e-17         # errors of 0 are drawn here on the log scale


def fmt_err(e):
    return "0" if e == 0 else f"{e:.1e}"


def find(runs, base, **want):
    for (b, args), entries in runs.items():
        if b == base and all(dict(args).get(k) == v for k, v in want.items()):
            return entries
    return None


def chart(runs, ns, path):
    fig, axes = plt.subplots(1, len(ns), figsize=(5.5 * len(ns), 4.2), sharey=True, squeeze=False)
    for ax, n in zip(axes[0], ns):
        rays = sorted(((dict(a)["resolution"], e) for (b, a), e in runs.items()
                       if b == "BM_RaySampling" and dict(a).get("n") == n), key=lambda x: x[0])
        if rays:
            xs = [med_ms(e)[0] for _, e in rays]
            ys = [max(e[0]["fraction_error"], FLOOR) for _, e in rays]
            ax.plot(xs, ys, "o-", color="tab:green", label="ray sampling (own caster, 2 threads)")
            for (res, _), x, y in zip(rays, xs, ys):
                ax.annotate(f"{res}²", (x, y), fontsize=7, textcoords="offset points", xytext=(4, 4))
        for base, threads, colour, marker, label in (
                ("BM_HedraExact", 2, "tab:red", "*", "hedra exact, 2 threads"),
                ("BM_HedraExact", 1, "tab:orange", "*", "hedra exact, 1 thread"),
                ("BM_CgalUnion", None, "tab:blue", "s", "CGAL exact union (ground only)")):
            e = find(runs, base, n=n, **({"threads": threads} if threads else {}))
            if e:
                ax.plot([med_ms(e)[0]], [max(e[0]["fraction_error"], FLOOR)], marker, color=colour,
                        markersize=12 if marker == "*" else 8, label=label)
        if n == 40:
            ax.axvline(TARGET_MS, color="gray", linestyle="--", linewidth=1, label="target 20 ms")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time (ms, log)")
        ax.set_title(f"N = {n} ({n * n} boxes)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("error of the ground's shadowed fraction")
    fig.suptitle("Shadows: speed against accuracy (errors of 0 drawn at 1e-17)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def shadows(results, docs, quick=False):
    path = os.path.join(results, "shadows_bench.json")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        runs = collect(json.load(f))
    ns = sorted({dict(a)["n"] for (b, a) in runs if b == "BM_HedraExact"})
    lines = ["## Shadows", "",
             f"Measured on {machine()}, by `bench/shadows_bench.cpp`"
             f"{' (quick run)' if quick else ''}; see docs/shadows.md for the method. The city of "
             "docs/design.md (\"Targets\"): a ground slab [0, 100]² and an N × N grid of boxes (footprints 0.2p … 0.8p "
             "of each cell p = 100/N, heights p/4 … 9p/8 from a fixed seed), the sun along "
             "(−1, −2, −3). *hedra exact*: `compute_shadows`, shadow polygons and areas on every "
             "face (ground, facades, roofs), scene preparation included. *CGAL*: the exact union "
             "(Epeck `Polygon_set_2`) of the ground shadows alone, each box's the hull of its base "
             "and its top projected along the sun, clipped to the ground — the exact reference. "
             "*Error*: |ground fraction − CGAL's|. Times in ms: median [min–max] over the "
             "repetitions."]
    if os.environ.get("HEDRA_BENCH_NOTE"):
        lines.append(os.environ["HEDRA_BENCH_NOTE"])
    lines += ["", "| N | boxes | hedra, 2 threads | hedra, 1 thread | CGAL union | CGAL ÷ hedra | "
              "ground fraction | error vs CGAL |",
              "|---|---|---|---|---|---|---|---|"]
    verdicts = []
    for n in ns:
        h2 = find(runs, "BM_HedraExact", n=n, threads=2)
        h1 = find(runs, "BM_HedraExact", n=n, threads=1)
        cg = find(runs, "BM_CgalUnion", n=n)
        ratio = f"{med_ms(cg)[0] / med_ms(h2)[0]:.1f}×" if cg and h2 else "—"
        ref = h2 or h1
        lines.append(f"| {n} | {n * n} | {fmt_ms(med_ms(h2)) if h2 else '—'} | "
                     f"{fmt_ms(med_ms(h1)) if h1 else '—'} | {fmt_ms(med_ms(cg)) if cg else '—'} | "
                     f"{ratio} | {ref[0]['ground_fraction']:.12f} | {fmt_err(ref[0]['fraction_error'])} |")
        if n == 40 and h2:
            t = med_ms(h2)[0]
            err = h2[0]["relative_error"]
            verdicts.append(f"Target (docs/design.md): N = 40 in ≤ {TARGET_MS:g} ms with the ground fraction "
                            f"equal to CGAL's to {TARGET_ERROR:g}: time **{'met' if t <= TARGET_MS else 'not met'}** "
                            f"({t:.3g} ms median, {med_ms(h2)[1]:.3g} ms best), accuracy "
                            f"**{'met' if err <= TARGET_ERROR else 'not met'}** (relative error {fmt_err(err)}).")
    lines += [""] + verdicts + [""]
    lines += ["### Ray sampling", "",
              "The ground's shadowed fraction from rays towards the sun from one jittered point in each "
              "cell of an R × R grid (stratified sampling; own ray caster over a uniform grid of the boxes, 2 threads), against the exact fraction.", "",
              "| N | R | ms | error | hedra exact is faster by |", "|---|---|---|---|---|"]
    for n in ns:
        h2 = find(runs, "BM_HedraExact", n=n, threads=2)
        rays = sorted(((dict(a)["resolution"], e) for (b, a), e in runs.items()
                       if b == "BM_RaySampling" and dict(a).get("n") == n), key=lambda x: x[0])
        for res, e in rays:
            faster = f"{med_ms(e)[0] / med_ms(h2)[0]:.1f}×" if h2 else "—"
            lines.append(f"| {n} | {res} | {fmt_ms(med_ms(e))} | {fmt_err(e[0]['fraction_error'])} | {faster} |")
    chart(runs, ns, os.path.join(docs, "shadows_speed_accuracy.png"))
    lines += ["", "![Shadows: speed against accuracy](shadows_speed_accuracy.png)", ""]
    return "\n".join(lines) + "\n"



def main():
    standalone(shadows, "shadows_bench", "## Shadows")


if __name__ == "__main__":
    main()
