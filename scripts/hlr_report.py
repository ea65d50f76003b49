#!/usr/bin/python3
"""The "Hidden lines" section of docs/benchmarks.md, from bench/hlr_bench.cpp's JSON output.

Usage: hlr_report.py RESULTS_DIR DOCS_DIR
Reads RESULTS_DIR/hlr_bench.json (Google Benchmark, any number of repetitions; medians are
used), writes DOCS_DIR/hlr_scaling.png and DOCS_DIR/hlr_speed_accuracy.png and replaces the
"## Hidden lines" section of DOCS_DIR/benchmarks.md (appending it, or creating the page, when
there is none). `hidden_lines(results, docs, quick)` returns the same section, for a report that
builds the whole page from a list of sections (scripts/bench_report.py).
"""
import json
import os

import matplotlib

from bench_common import collect, fmt_times, machine, standalone, times_ms

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENES = {0: "jittered grid", 1: "regular grid", 2: "corner", 3: "bar"}
GROWTH_TARGET = 4.6   # time(N = 40) / time(N = 20), docs/design.md (≈ n^1.1)
SPEEDUP_TARGET = 10   # over OCCT HLRBRep_PolyAlgo at every N
ACCURACY_TARGET = 1e-9


def ms(entries):
    return times_ms(entries)[0]


def ms_range(entries):
    """'median [min–max]' over the repetitions, in ms."""
    return fmt_times(times_ms(entries))


def get(runs, base, **args):
    return runs.get((base, tuple(sorted(args.items()))))


def fmt(x, digits=3):
    return "–" if x is None else f"{x:.{digits}g}"


def scaling_section(runs):
    lines = ["### Jittered grid of boxes: time against N", "",
             "Time per call in ms: median [min–max] over the repetitions. *tests/edge*: Cyrus–Beck clips per drawn edge (it rises towards a "
             "constant as the share of edges at the grid's border, which fewer boxes can hide, falls); *vs reference*: |hedra − ray-cast reference| / reference for the total visible "
             "length (tests/testing/hlr_reference.h: 256 samples per edge, transitions bisected). OCCT times exclude "
             "BRepMesh meshing (given apart) and are for the parallel view only; *÷ hedra* is OCCT's time "
             "over hedra's parallel time.", "",
             "| N | boxes | hedra parallel | hedra perspective | tests/edge | vs reference (par / persp) | "
             "OCCT PolyAlgo | ÷ hedra | meshing | OCCT Algo (exact) | ÷ hedra |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    times = {}
    tests_count = {}  # (n, perspective) -> occlusion tests of the whole call
    ratios = []
    worst_error = 0
    for n in (5, 10, 20, 30, 40):
        par = get(runs, "BM_Hedra", scene=0, n=n, perspective=0)
        per = get(runs, "BM_Hedra", scene=0, n=n, perspective=1)
        if not par:
            continue
        tp, tq = ms(par), ms(per) if per else None
        times[(n, 0)] = tp
        if tq is not None:
            times[(n, 1)] = tq
        e = par[0]
        tests = e["occlusion_tests"] / e["edges"]
        tests_count[(n, 0)] = e["occlusion_tests"]
        if per:
            tests_count[(n, 1)] = per[0]["occlusion_tests"]
        errors = [par[0]["reference_rel_error"]] + ([per[0]["reference_rel_error"]] if per else [])
        worst_error = max([worst_error] + errors)
        poly = get(runs, "BM_OcctPoly", scene=0, n=n)
        algo = get(runs, "BM_OcctAlgo", scene=0, n=n)
        tpoly = ms(poly) if poly else None
        talgo = ms(algo) if algo else None
        if tpoly:
            ratios.append((n, tpoly / tp))
        lines.append(f"| {n} | {n * n} | {ms_range(par)} | {ms_range(per) if per else '–'} | {tests:.2f} | "
                     f"{' / '.join(f'{x:.1e}' for x in errors)} | {fmt(tpoly)} | "
                     f"{fmt(tpoly / tp if tpoly else None)}{'×' if tpoly else ''} | "
                     f"{fmt(poly[0]['mesh_ms']) if poly else '–'} | {fmt(talgo)} | "
                     f"{fmt(talgo / tp if talgo else None)}{'×' if talgo else ''} |")
    lines.append("")
    verdicts = []
    for persp, label in ((0, "parallel"), (1, "perspective")):
        if (20, persp) in times and (40, persp) in times:
            g = times[(40, persp)] / times[(20, persp)]
            work = ""
            if (20, persp) in tests_count and (40, persp) in tests_count:
                work = (f", the occlusion tests {tests_count[(40, persp)] / tests_count[(20, persp)]:.2f}×"
                        f" for 4× the boxes")
            verdicts.append(f"time growth N = 20 → 40, {label}: **{g:.2f}×** "
                            f"({'met' if g <= GROWTH_TARGET else 'not met'}; target ≤ {GROWTH_TARGET}×{work})")
    if ratios:
        worst = min(r for _, r in ratios)
        verdicts.append(f"speed over OCCT PolyAlgo: **{worst:.1f}× at worst** "
                        f"({'met' if worst >= SPEEDUP_TARGET else 'not met'} at every N; target ≥ {SPEEDUP_TARGET}×)")
    verdicts.append(f"visible length against the ray-cast reference: worst relative difference "
                    f"**{worst_error:.1e}** ({'met' if worst_error <= ACCURACY_TARGET else 'not met'}; "
                    f"target ≤ {ACCURACY_TARGET:.0e})")
    lines += ["Targets (docs/design.md): " + "; ".join(verdicts) + ".", ""]
    return lines, times


def other_scenes(runs):
    lines = ["### Other scenes", "",
             "Time in ms, median [min–max]; *vs reference*: hedra's relative difference from the ray-cast "
             "reference's visible length.", "",
             "| scene | view | hedra ms | visible length | junction segments | vs reference |",
             "|---|---|---|---|---|---|"]
    for scene, n in ((1, 20), (2, 1), (3, 1)):
        for persp in (0, 1):
            r = get(runs, "BM_Hedra", scene=scene, n=n, perspective=persp)
            if not r:
                continue
            e = r[0]
            name = SCENES[scene] + (f" N = {n}" if scene == 1 else "")
            lines.append(f"| {name} | {'perspective' if persp else 'parallel'} | {ms_range(r)} | "
                         f"{e['visible_length']:.6g} | {int(e['junction_segments'])} | {e['reference_rel_error']:.1e} |")
    reg = get(runs, "BM_OcctPoly", scene=1, n=20)
    if reg:
        lines.append("")
        lines.append(f"On the regular grid (edges aligned in the picture) OCCT PolyAlgo's visible 2D length differs "
                     f"from hedra's by {100 * reg[0]['rel_diff_vs_hedra']:+.2f} %; on the jittered N = 20 grid by "
                     f"{100 * get(runs, 'BM_OcctPoly', scene=0, n=20)[0]['rel_diff_vs_hedra']:+.2f} %."
                     if get(runs, "BM_OcctPoly", scene=0, n=20) else "")
    lines.append("")
    return lines


def zbuffer_section(runs, docs):
    lines = ["### Image space: z-buffer against exact", "",
             "Faces rasterized into a z-buffer of R × R pixels; each edge sampled every half pixel and kept "
             "where its depth is within a small bias of the farthest depth in the 3 × 3 pixels around it. "
             "*missed* / *extra*: visible length it drops / invents, as fractions of hedra's exact visible "
             "length (3D, sampled). Jittered grid N = 20 and regular grid N = 20, parallel. *÷ hedra*: the "
             "z-buffer's time over hedra's exact Roberts on the same scene; hedra's own error against the "
             "ray-cast reference is in the tables above (≤ 1e-9).", "",
             "| scene | R | ms | ÷ hedra | missed | extra | hedra ms |", "|---|---|---|---|---|---|---|"]
    points = {}
    for scene in (0, 1):
        hedra = get(runs, "BM_Hedra", scene=scene, n=20, perspective=0)
        for res in (512, 1024, 2048):
            r = get(runs, "BM_ZBuffer", scene=scene, n=20, perspective=0, res=res)
            if not r:
                continue
            e = r[0]
            points.setdefault(scene, []).append((ms(r), e["missed_fraction"] + e["extra_fraction"], res))
            ratio = f"{ms(r) / ms(hedra):.2g}×" if hedra else "–"
            lines.append(f"| {SCENES[scene]} | {res} | {ms_range(r)} | {ratio} | {100 * e['missed_fraction']:.2f} % | "
                         f"{100 * e['extra_fraction']:.2f} % | {ms_range(hedra) if hedra else '–'} |")
    lines.append("")
    if points:
        fig, ax = plt.subplots(figsize=(7, 4.2))
        for scene, colour in ((0, "tab:blue"), (1, "tab:orange")):
            pts = sorted(points.get(scene, []))
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=colour,
                    label=f"z-buffer, {SCENES[scene]} N = 20")
            for t, err, res in pts:
                ax.annotate(f"{res}²", (t, err), fontsize=7, textcoords="offset points", xytext=(4, 4))
            hedra = get(runs, "BM_Hedra", scene=scene, n=20, perspective=0)
            if hedra:
                err = max(hedra[0]["reference_rel_error"], 1e-16)
                ax.plot([ms(hedra)], [err], "*", color=colour, markersize=14,
                        label=f"hedra Roberts (exact), {SCENES[scene]}: vs ray-cast reference")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time per picture (ms)")
        ax.set_ylabel("missed + extra visible length (fraction)")
        ax.set_title("Hidden lines: speed against accuracy (hedra's error: vs the reference, floor 1e-16)",
                     fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(docs, "hlr_speed_accuracy.png"), dpi=110)
        plt.close(fig)
        lines += ["![Hidden lines: speed against accuracy](hlr_speed_accuracy.png)", ""]
    return lines


def scaling_chart(runs, times, docs):
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ns = [5, 10, 20, 30, 40]
    for persp, style in ((0, "o-"), (1, "s--")):
        pts = [(n * n, times[(n, persp)]) for n in ns if (n, persp) in times]
        if pts:
            ax.plot(*zip(*pts), style, color="tab:red",
                    label=f"hedra Roberts, {'perspective' if persp else 'parallel'}")
    for base, colour, label in (("BM_OcctPoly", "tab:blue", "OCCT HLRBRep_PolyAlgo (no meshing)"),
                                ("BM_OcctAlgo", "tab:purple", "OCCT HLRBRep_Algo (exact)")):
        pts = [(n * n, ms(r)) for n in ns if (r := get(runs, base, scene=0, n=n))]
        if pts:
            ax.plot(*zip(*pts), "^-", color=colour, label=label)
    pts = [(n * n, ms(r)) for n in ns if (r := get(runs, "BM_ZBuffer", scene=0, n=n, perspective=0, res=1024))]
    if pts:
        ax.plot(*zip(*pts), "d:", color="tab:green", label="z-buffer 1024², parallel")
    if (20, 0) in times:
        x = [400, 1600]
        ax.plot(x, [times[(20, 0)], times[(20, 0)] * GROWTH_TARGET], color="gray", linewidth=1,
                label="target growth n^1.1 from N = 20")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("boxes (N²)")
    ax.set_ylabel("time (ms)")
    ax.set_title("Hidden lines on the jittered grid of boxes", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "hlr_scaling.png"), dpi=110)
    plt.close(fig)


def hidden_lines(results, docs, quick=False):
    path = os.path.join(results, "hlr_bench.json")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        runs = collect(json.load(f))
    lines = ["## Hidden lines", "",
             f"Measured on {machine()}, by `bench/hlr_bench.cpp`{' (quick run)' if quick else ''}; "
             "see docs/hidden-lines.md for the method."]
    if not any(k[0].startswith("BM_Occt") for k in runs):
        lines.append("OCCT was not found in this build (Debian's libocct-*-dev packages; `make bench` installs "
                     "them): its columns are empty.")
    if os.environ.get("HEDRA_BENCH_NOTE"):
        lines.append(os.environ["HEDRA_BENCH_NOTE"])
    lines.append("")
    scaling, times = scaling_section(runs)
    lines += scaling
    scaling_chart(runs, times, docs)
    lines += ["![Hidden lines: time against N](hlr_scaling.png)", ""]
    lines += other_scenes(runs)
    lines += zbuffer_section(runs, docs)
    return "\n".join(lines) + "\n"



def main():
    standalone(hidden_lines, "hlr_bench", "## Hidden lines")


if __name__ == "__main__":
    main()
