"""The "Faces scaling" section of docs/benchmarks.md (issue 15) and docs/faces_scaling.png, from
RESULTS_DIR/faces_scaling.json (scripts/faces_scaling.py: whole processes) and
RESULTS_DIR/faces_bench.json (bench/faces_bench.cpp: hedra's and OCCT PolyAlgo's hidden lines in
one process)."""
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from bench_common import UNIT_MS, collect, machine, times_ms  # noqa: E402

COMMANDS = ["info", "hlr", "shadows", "render"]
# The scene's drawn length by ray casting the analytic curves against the analytic solids
# (tests/visibility/line_classes_test.cpp, DrawnLengthOfBodiesHidingEachOtherMatchesRayCasting).
REFERENCE_DRAWN = 56.668


def fmt(x, digits=3):
    if x is None:
        return "–"
    return f"{x:.{digits}g}"


def cpu_ms(entries):
    """Median CPU time of the repetitions, in ms."""
    ts = sorted(e["cpu_time"] * UNIT_MS[e["time_unit"]] for e in entries)
    return ts[len(ts) // 2]


def growth(points):
    """Time factor per 10x faces between consecutive sizes: (T2/T1)^(1/log10(F2/F1))."""
    out = []
    for (f1, t1), (f2, t2) in zip(points, points[1:]):
        if t1 and t2 and f2 > f1 and t1 >= 0.02:  # below 20 ms the process start dominates
            out.append((t2 / t1) ** (1 / math.log10(f2 / f1)))
        else:
            out.append(None)
    return out


def faces_scaling(results, docs, quick=False):
    path = os.path.join(results, "faces_scaling.json")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        data = json.load(f)
    quick = data.get("quick", quick)  # the run that wrote the file, which may be a full one
    scene = sorted((e for e in data["entries"] if e["case"] == "scene"), key=lambda e: -e["t"])
    mesh = [e for e in data["entries"] if e["case"] == "mesh"]
    terrains = sorted((e for e in data["entries"] if e["case"] == "terrain"), key=lambda e: e["t"])
    lines = ["## Faces scaling", "",
             f"Measured on {machine()} by `scripts/faces_scaling.py`{' (quick run)' if quick else ''} "
             "(whole processes of the command) and `bench/faces_bench.cpp` (hidden lines in one "
             "process, beside OCCT). Scene: a slab [−4, 4]² × [−0.5, 0], a sphere (r = 1.5) and a "
             "cylinder (r = 0.8, h = 2.5) at chordal tolerance t, parallel view along (−1, −1, −1), "
             "one point light; `render` is `--shadows exact` at 800 × 600. **CPU** is user + system "
             "seconds of the whole process (scene building and file output included), less "
             "disturbed by a shared machine than wall time; **µs/face** is CPU per face; **growth** "
             "is the CPU factor per 10× faces from the previous row (from 20 ms on); **B/face** is "
             "the peak resident memory per face." +
             (f" Load average during the run: {data['load_average']:.1f}." if data.get("load_average") else ""), ""]
    header = "| t | faces | " + " | ".join(f"`{c}` CPU s | µs/face | growth | peak MB | B/face" for c in COMMANDS) + " |"
    lines += [header, "|---|---|" + "---|---|---|---|---|" * len(COMMANDS)]
    rows = scene + mesh + terrains
    series = {}
    for c in COMMANDS:
        pts = [(e["faces"], (e["runs"].get(c) or {}).get("cpu_s")) for e in scene if e["faces"]]
        series[c] = (pts, growth(pts))
    for i, e in enumerate(rows):
        kind = "mesh" if e["case"] == "mesh" else "open terrain"
        label = f"{e['t']:.0e}" if e["case"] == "scene" else f"{kind} ({e.get('triangles', 0):,} triangles)".replace(",", " ")
        row = [label, f"{e['faces']:,}".replace(",", " ") if e["faces"] else "–"]
        for c in COMMANDS:
            r = e["runs"].get(c) or {}
            ok = r.get("rc") == 0
            cpu = r.get("cpu_s") if ok else None
            peak = r.get("peak_kb") if ok else None
            g = series[c][1][i - 1] if e["case"] == "scene" and i >= 1 else None
            row += [fmt(cpu) if ok else "✗",
                    fmt(1e6 * cpu / e["faces"]) if cpu and e["faces"] else "–",
                    f"{g:.1f}×" if g else "–",
                    f"{peak / 1024:.0f}" if peak else "–",
                    f"{peak * 1024 / e['faces']:.0f}" if peak and e["faces"] else "–"]
        lines.append("| " + " | ".join(row) + " |")
    lines.append("")
    def where(e):
        return f"t = {e['t']:g}" if e["case"] == "scene" else ("the mesh" if e["case"] == "mesh" else f"the terrain of {e.get('triangles', 0)} triangles")

    failures = [f"{where(e)} `{c}`: {(e['runs'].get(c) or {}).get('error') or (e['runs'].get(c) or {}).get('stderr')}"
                for e in rows for c in COMMANDS if (e["runs"].get(c) or {}).get("rc") != 0]
    if failures:
        lines += ["Failed: " + "; ".join(failures) + ".", ""]
    if mesh:
        lines += ["The mesh: hedra's sphere (r = 1.5, t = 1.5e-5, about (−1.5, 0.001, 1.5)) written by "
                  "`hedra convert` as OFF and each quad split into two triangles, in a scene with the slab. "
                  "The centre is off the grid on which a moved sphere is snapped exactly planar "
                  "(docs/primitives.md), so its corners are rounded as another tool's export would be: the "
                  "quads are planar only within rounding, so many of the diagonals are a few ulps reflex: the body "
                  "is exactly non-convex: `info` lists its non-convex faces through the convex hull, and "
                  "`hlr`, `shadows` and `render` let it occlude by its faces, without a decomposition "
                  "(a closed non-convex mesh of more than 4096 faces; docs/hidden-lines.md).", ""]
    if terrains:
        lines += ["The open terrain: a height field over [−4, 4]² (two hills and a ripple) of n × n cells "
                  "of two triangles, an OFF file with boundary edges, so an open surface: one "
                  "two-sided body of its triangles (no two are exactly coplanar) and their other "
                  "sides, which occludes by its faces, receives and casts shadows (docs/io.md); "
                  "`hlr` draws its boundary and outline (line classes across its faces). Until "
                  "2026-12-06 a terrain of 80 000 triangles took 42 s in `info` and 60 s in `hlr` "
                  "(a quadratic step in building the scene, and exact junctions between "
                  "neighbouring faces); then, with each triangle a scene body of its own, 980 000 "
                  "triangles took 7, 17, 10 and 11 s in `info`, `hlr`, `shadows` and `render` "
                  "(1.7–4.9 GB).", ""]

    # Star prisms: decomposition and rendering of many reflex edges.
    stars = sorted((e for e in data["entries"] if e["case"] == "star"), key=lambda e: e["t"])
    if stars:
        lines += ["### Star prisms", "",
                  "A prism over an n-point star (radii 1 and 0.5, n/2 reflex vertical edges) on a "
                  "ground slab, one point light; whole processes with `--threads 1`: `decompose` of "
                  "the scene (the star's exact convex pieces) and `render --shadows exact`. CPU "
                  "seconds, peak MB.", "",
                  "| n | pieces | `decompose` CPU s | peak MB | `render` CPU s | peak MB |",
                  "|---|---|---|---|---|---|"]
        for e in stars:
            d, r = e["runs"].get("decompose", {}), e["runs"].get("render", {})
            def cell(x):
                if x.get("rc") != 0:
                    return "✗ | –"
                return f"{x['cpu_s']:.3g} | {(x.get('peak_kb') or 0) / 1024:.0f}"
            lines.append(f"| {e['t']} | {d.get('pieces', '–')} | {cell(d)} | {cell(r)} |")
        lines.append("")

    # Hidden lines beside OCCT HLRBRep_PolyAlgo at the same chordal tolerance.
    bench_path = os.path.join(results, "faces_bench.json")
    if os.path.exists(bench_path):
        with open(bench_path) as f:
            runs = collect(json.load(f))
        hedra = {dict(a)["t_exp"]: v for (b, a), v in runs.items() if b == "BM_FacesHedraHlr"}
        occt = {dict(a)["t_exp"]: v for (b, a), v in runs.items() if b == "BM_FacesOcctPoly"}
        first = {dict(a)["t_exp"]: v for (b, a), v in runs.items() if b == "BM_FacesHedraHlrFirst"}
        lines += ["### Hidden lines beside OCCT `HLRBRep_PolyAlgo`", "",
                  "The same scene as OCCT shapes (box, sphere and cylinder surfaces) meshed by "
                  "`BRepMesh_IncrementalMesh` at linear deflection t (the same chordal tolerance); "
                  "times in ms, median [min–max] over the repetitions, of `hidden_lines` on hedra's "
                  "bodies and of PolyAlgo's `Update` plus its visible and outline compounds; meshing "
                  "on neither side (OCCT's meshing time apart). OCCT stops at 1e-4: its meshing "
                  "grows about 50× per 10× finer tolerance, so 1e-5 would outlast the whole run.", "",
                  "*CPU* is the CPU time of the calling thread (hedra's hidden lines also run on a "
                  "second thread, OCCT's on one), the fairer figure on a loaded machine. "
                  "`hidden_lines` decides each body's convexity once and keeps the verdict with the "
                  "body, so repeated calls on the same bodies skip it: *first call* is the time on "
                  "freshly built bodies, the one to compare for a single drawing; the ratios are "
                  "of CPU times. The benchmark process sets glibc's allocator as the `hedra` command "
                  "does (blocks up to 32 MB from the heap, freed memory kept; both libraries run "
                  "under it): with glibc's defaults every block over 32 MB is mapped afresh on each "
                  "call, which at 1e-5 cost hedra 258 instead of 110 ms a call on a machine where a "
                  "page fault takes about 10 µs (no difference at 1e-4).", "",
                  "| t | hedra faces | hedra ms | hedra CPU ms | first call CPU ms | OCCT PolyAlgo ms | "
                  "OCCT CPU ms | OCCT meshing ms | OCCT ÷ hedra (repeated / first call) |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for k in sorted(hedra):
            h = hedra[k]
            o = occt.get(k)
            th = times_ms(h)
            to = times_ms(o) if o else None
            fc = cpu_ms(first[k]) if k in first else None
            ratio = (f"{cpu_ms(o) / cpu_ms(h):.2f}× / " + (f"{cpu_ms(o) / fc:.2f}×" if fc else "–")) if to else "–"
            faces = f"{int(h[0]['faces']):,}".replace(",", " ")
            first_cell = f"{fc:.3g}" if fc else "–"
            occt_cells = (f"{to[0]:.3g} [{to[1]:.3g}–{to[2]:.3g}] | {cpu_ms(o):.3g} | {o[0]['mesh_ms']:.3g}"
                          if to else "– | – | –")
            lines.append(f"| 1e-{k} | {faces} | {th[0]:.3g} [{th[1]:.3g}–{th[2]:.3g}] | {cpu_ms(h):.3g} | "
                         f"{first_cell} | {occt_cells} | {ratio} |")
        lines.append("")
        exact = [v for (b, a), v in runs.items() if b == "BM_FacesOcctExact"]
        if exact and all("drawn_2d" in hedra[k][0] for k in hedra):
            occt_len = exact[0][0]["drawn_2d"]
            lines += ["### Drawn length beside OCCT `HLRBRep_Algo`", "",
                      "The length of the drawing in the picture plane (visible sharp edges and "
                      "outlines) against an independent reference: the analytic curves of the "
                      f"drawing sampled and ray-cast against the analytic solids, {REFERENCE_DRAWN:g} "
                      "(`LineClasses.DrawnLengthOfBodiesHidingEachOtherMatchesRayCasting` in "
                      "tests/visibility/line_classes_test.cpp computes it and checks hedra against "
                      "it). hedra's outlines follow the analytic normals, as `hedra hlr` gives them "
                      f"for a scene's primitives. OCCT's exact `HLRBRep_Algo` on the analytic shapes "
                      f"draws {occt_len:.6g} in {times_ms(exact[0])[0]:.3g} ms (no meshing): "
                      f"{100 * (occt_len - REFERENCE_DRAWN) / REFERENCE_DRAWN:+.4f} % from the reference. "
                      "The cylinder is made for OCCT from its surface and sewn, which records its seam "
                      "as C0; `HLRBRep_Algo` then draws the seam as a visible sharp edge (2.041 more, "
                      "+3.6 %, until 2026-12-04). `BRepLib::EncodeRegularity` records every edge's "
                      "continuity from its faces, as OCCT's primitives do, and the seam goes to the smooth "
                      "class, which neither side counts.", "",
                      "| t | hedra faces | hedra drawn 2D | hedra − reference | hedra − OCCT `HLRBRep_Algo` | OCCT − reference |",
                      "|---|---|---|---|---|---|"]
            for k in sorted(hedra):
                d = hedra[k][0]["drawn_2d"]
                faces = f"{int(hedra[k][0]['faces']):,}".replace(",", " ")
                lines.append(f"| 1e-{k} | {faces} | {d:.6g} | {100 * (d - REFERENCE_DRAWN) / REFERENCE_DRAWN:+.3f} % | "
                             f"{100 * (d - occt_len) / occt_len:+.3f} % | "
                             f"{100 * (occt_len - REFERENCE_DRAWN) / REFERENCE_DRAWN:+.4f} % |")
            lines.append("")

    # Chart: CPU time against faces, log-log, one line per command.
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for c in COMMANDS:
        pts = [(f, t) for f, t in series[c][0] if t]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=f"hedra {c} (process CPU)")
    if os.path.exists(bench_path):
        for name, label, style in (("BM_FacesHedraHlr", "hedra hidden_lines (in process, CPU)", "--"),
                                   ("BM_FacesOcctPoly", "OCCT PolyAlgo (in process, CPU, meshing apart)", ":")):
            pts = []
            for k, v in sorted((dict(a)["t_exp"], v) for (b, a), v in runs.items() if b == name):
                faces = hedra.get(k, [{}])[0].get("faces")
                if faces:
                    pts.append((faces, cpu_ms(v) / 1000))
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker="s", label=label)
    if scene:
        f0 = scene[0]["faces"]
        xs = [f0, scene[-1]["faces"]]
        ax.plot(xs, [1e-3 * x / f0 for x in xs], color="grey", alpha=0.4, label="linear (slope 1)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("faces (log)")
    ax.set_ylabel("seconds (log)")
    ax.set_title("Faces scaling: slab + sphere + cylinder at t = 1e-2 … 1e-5", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(docs, "faces_scaling.png"), dpi=110)
    plt.close(fig)
    lines += ["![faces scaling: CPU time against faces](faces_scaling.png)", ""]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    from bench_common import standalone
    standalone(faces_scaling, "faces_scaling", "## Faces scaling")
