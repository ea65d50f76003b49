#!/usr/bin/python3
"""The "Rendering" section of docs/benchmarks.md, from bench/render_bench.cpp's JSON output.

Usage: render_report.py RESULTS_DIR DOCS_DIR
Reads RESULTS_DIR/render_bench.json (Google Benchmark, any number of repetitions; medians are
used), writes DOCS_DIR/render_speed_accuracy.png and replaces the "## Rendering" section of
DOCS_DIR/benchmarks.md (appending it, or creating the page, when there is none).
`rendering(results, docs, quick)` returns the same section, for a report that builds the whole
page from a list of sections.
"""
import json
import os
import statistics

import matplotlib

from bench_common import collect, machine, standalone, times_ms

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENES = {0: "city N = 10", 1: "city N = 40", 2: "demo scene"}
METHODS = {0: "none", 1: "exact", 2: "map", 3: "rays"}
TARGET_MS = 200  # N = 40, 1024², Phong, exact shadows, 2 threads (docs/design.md)
FLOOR = 1e-6     # errors of 0 are drawn here on the log scale


def ms(entries):
    return times_ms(entries)[0]


def median(entries, key):
    values = [e[key] for e in entries if key in e]
    return statistics.median(values) if values else None


def rows_of(runs):
    rows = []
    for (base, args), entries in runs.items():
        if base != "BM_Render":
            continue
        a = dict(args)
        e = entries[0]
        rows.append({
            "scene": a["scene"], "method": int(e["method"]), "label": e.get("label", ""),
            "resolution": int(e["resolution"]), "bias": e["bias"], "probes": int(e["probes"]),
            "ms": ms(entries), "ms_min": times_ms(entries)[1], "ms_max": times_ms(entries)[2],
            "shadows_ms": median(entries, "shadows_ms"),
            "raster_ms": median(entries, "raster_ms"), "setup_ms": median(entries, "setup_ms"),
            "pixel_error": e.get("pixel_error"), "area_error": e.get("area_error"),
            "exact_area": e.get("exact_area")})
    rows.sort(key=lambda r: (r["scene"], r["method"], r["resolution"], r["bias"], r["probes"]))
    return rows


def fmt_err(x):
    if x is None:
        return "–"
    return "0" if x == 0 else f"{x:.1e}"


def table(rows):
    """One row per scene and method; *÷ exact*: the method's time over the exact method's on the
    same scene (below 1: faster than exact, at the error shown)."""
    exact_ms = {r["scene"]: r["ms"] for r in rows if r["method"] == 1}
    lines = ["| scene | method | ms [min–max] | ÷ exact | of which shadows | raster | pixels differing from exact | "
             "ground area error |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = f"{r['ms'] / exact_ms[r['scene']]:.2f}" if r["scene"] in exact_ms else "–"
        lines.append(f"| {SCENES[r['scene']]} | `{r['label']}` | {r['ms']:.1f} [{r['ms_min']:.1f}–{r['ms_max']:.1f}] | "
                     f"{ratio} | {r['shadows_ms']:.1f} | "
                     f"{r['raster_ms']:.1f} | {fmt_err(r['pixel_error'])} | {fmt_err(r['area_error'])} |")
    return lines


def chart(rows, path):
    scenes = sorted({r["scene"] for r in rows})
    fig, axes = plt.subplots(2, len(scenes), figsize=(4.6 * len(scenes), 7.5), squeeze=False)
    for col, scene in enumerate(scenes):
        mine = [r for r in rows if r["scene"] == scene]
        for row, key, ylabel in ((0, "pixel_error", "pixels whose shadow state differs from exact"),
                                 (1, "area_error", "relative error of the shadowed ground area")):
            ax = axes[row][col]
            exact = [r for r in mine if r["method"] == 1]
            for r in exact:
                ax.plot([r["ms"]], [max(r[key] or 0, FLOOR)], "*", color="tab:red", markersize=14,
                        label="exact (shadow polygons)")
            biases = sorted({r["bias"] for r in mine if r["method"] == 2})
            cmap = plt.get_cmap("viridis")
            for i, bias in enumerate(biases):
                pts = sorted((r for r in mine if r["method"] == 2 and r["bias"] == bias),
                             key=lambda r: r["resolution"])
                ax.plot([r["ms"] for r in pts], [max(r[key] or 0, FLOOR) for r in pts], "o-",
                        color=cmap(i / max(1, len(biases) - 1)), label=f"map, bias {bias:g} texels")
                if i == len(biases) - 1:
                    for r in pts:
                        ax.annotate(f"{r['resolution']}²", (r["ms"], max(r[key] or 0, FLOOR)), fontsize=6,
                                    textcoords="offset points", xytext=(3, 3))
            pts = sorted((r for r in mine if r["method"] == 3), key=lambda r: r["probes"])
            ax.plot([r["ms"] for r in pts], [max(r[key] or 0, FLOOR) for r in pts], "s-", color="tab:orange",
                    label="rays")
            for r in pts:
                ax.annotate(f"{r['probes']}", (r["ms"], max(r[key] or 0, FLOOR)), fontsize=6,
                            textcoords="offset points", xytext=(3, -8))
            none = [r for r in mine if r["method"] == 0]
            for r in none:
                ax.axvline(r["ms"], color="gray", linestyle=":", linewidth=1, label="no shadows (time)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="both", alpha=0.3)
            if row == 0:
                ax.set_title(SCENES[scene], fontsize=10)
            if row == 1:
                ax.set_xlabel("time per 1024² image (ms, 2 threads)")
            if col == 0:
                ax.set_ylabel(ylabel, fontsize=8)
            if row == 0 and col == 0:
                ax.legend(fontsize=6)
    fig.suptitle(f"Shadows in the raster renderer: speed against accuracy (errors of 0 drawn at {FLOOR:g}; "
                 "numbers: map resolution, ray probes per pixel)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def rendering(results, docs, quick=False):
    path = os.path.join(results, "render_bench.json")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        runs = collect(json.load(f))
    rows = rows_of(runs)
    if not rows:
        return ""
    chart(rows, os.path.join(docs, "render_speed_accuracy.png"))
    target = {}
    for (base, args), entries in runs.items():
        if base == "BM_Target":
            target[dict(args)["threads"]] = (ms(entries), median(entries, "shadows_ms"), median(entries, "raster_ms"))
    lines = ["## Rendering", "",
             f"Measured on {machine()}, by `bench/render_bench.cpp`{' (quick run)' if quick else ''}; "
             "see docs/rendering.md for the methods. Every image is 1024 × 1024 (the demo scene "
             "1024 × 768), Phong shading, one sample per pixel, 2 threads; times are medians over the "
             "repetitions of the whole render() call (for `exact`, including the exact shadow polygons of "
             "hedra/visibility/shadows.h; *shadows* is that part, or building the maps or the BVH). "
             "*Pixels differing*: the fraction of visible pixels whose shadow state (shadowed when at "
             "least half of the pixel's probes are blocked) differs from the exact method's at the same "
             "pixel. *Ground area error*: the shadowed ground area measured in a 1024² top view (the "
             "shadowed fraction of the visible ground times its exact area, plus the footprints), "
             "against the exact area of hedra/visibility/shadows.h; for `exact` it is the sampling error of the "
             "raster alone."]
    if os.environ.get("HEDRA_BENCH_NOTE"):
        lines.append(os.environ["HEDRA_BENCH_NOTE"])
    lines.append("")
    if 2 in target:
        t, s, r = target[2]
        verdict = "met" if t <= TARGET_MS else "not met"
        one = f"; on 1 thread {target[1][0]:.0f} ms" if 1 in target else ""
        lines += [f"Target (docs/design.md): N = 40, 1024², Phong, exact shadows in ≤ {TARGET_MS} ms on 2 threads: "
                  f"**{verdict}** ({t:.0f} ms, of which {s:.0f} ms exact shadow polygons and {r:.0f} ms "
                  f"the tiles{one}).", ""]
    lines += table(rows)
    lines += ["", "![Rendering: speed against accuracy](render_speed_accuracy.png)", ""]
    return "\n".join(lines) + "\n"



def main():
    standalone(rendering, "render_bench", "## Rendering")


if __name__ == "__main__":
    main()
