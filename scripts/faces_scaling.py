#!/usr/bin/python3
"""Faces scaling (issue 15), the whole-process half: runs `hedra info`, `hlr`, `shadows` and
`render --shadows exact` on one scene at chordal tolerance t = 1e-2 ... 1e-5 (quick: ... 1e-4)
and on a scene holding a 1 M-triangle mesh file (full run only), and records for each run the
CPU time (user + system, so that a shared machine's load inflates it less than wall time), the
wall time and the peak resident memory of the process. Writes RESULTS_DIR/faces_scaling.json;
scripts/faces_report.py turns it (with faces_bench.json) into docs/benchmarks.md's section.

Usage: faces_scaling.py HEDRA RESULTS_DIR [--quick] [--only CASE]

Scene (kept in step with bench/faces_bench.cpp): a slab [-4, 4]^2 x [-0.5, 0], a sphere of
radius 1.5 about (-1.5, 0, 1.5), a cylinder of radius 0.8 and height 2.5 at (2, 1, 0); parallel
view along (-1, -1, -1); one point light at (6, 4, 10).
"""
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

CAMERA = {"projection": "parallel", "direction": [-1, -1, -1], "up": [0, 0, 1]}
LIGHTS = [{"type": "point", "position": [6, 4, 10], "intensity": 1.0}]
IMAGE = {"width": 800, "height": 600, "background": [1, 1, 1]}
SLAB = {"name": "slab", "box": {"min": [-4, -4, -0.5], "max": [4, 4, 0]}}
MAX_FACES = 2000000
TIMEOUT_S = 900
# The triangulated sphere is not exactly convex (its quads are planar only within rounding, so
# many diagonals are a few ulps reflex); it occludes by its faces, and each command on it gets
# this long.
MESH_TIMEOUT_S = 120


def scene(t):
    return {"version": 1, "bodies": [
        SLAB,
        {"name": "ball", "sphere": {"center": [-1.5, 0, 1.5], "radius": 1.5, "tolerance": t,
                                    "max_faces": MAX_FACES}},
        {"name": "can", "cylinder": {"radius": 0.8, "z": [0, 2.5], "tolerance": t, "max_faces": MAX_FACES},
         "transform": [{"translate": [2, 1, 0]}]}],
        "camera": CAMERA, "lights": LIGHTS, "image": IMAGE}


def run(cmd):
    """CPU seconds, wall seconds, peak KB and stdout of one command (None on failure)."""
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        return {"error": f"over {TIMEOUT_S} s"}
    wall = time.monotonic() - start
    # communicate() has reaped the child; its usage is the growth of RUSAGE_CHILDREN.
    return {"rc": proc.returncode, "wall_s": wall, "stdout": out, "stderr": err.strip()[-300:]}


def peak_kb(cmd, timeout=TIMEOUT_S):
    """Runs cmd through a fresh Python child that reports the child's own peak memory (the
    peak of RUSAGE_CHILDREN is the largest child so far, so each command gets its own helper);
    a command over `timeout` seconds is killed and reported as such."""
    helper = ("import json,resource,subprocess,sys,time;s=time.monotonic();t=float(sys.argv[1])\n"
              "try:\n p=subprocess.run(sys.argv[2:],capture_output=True,text=True,timeout=t)\n"
              "except subprocess.TimeoutExpired:\n print(json.dumps({'error':'over %g s'%t}));sys.exit()\n"
              "u=resource.getrusage(resource.RUSAGE_CHILDREN)\n"
              "print(json.dumps({'rc':p.returncode,'cpu_s':u.ru_utime+u.ru_stime,'peak_kb':u.ru_maxrss,"
              "'wall_s':time.monotonic()-s,'stdout':p.stdout,'stderr':p.stderr[-300:]}))")
    r = run([sys.executable, "-c", helper, str(timeout)] + cmd)
    if "error" in r:
        return r
    try:
        return json.loads(r["stdout"])
    except json.JSONDecodeError:
        return {"error": "no report: " + r["stderr"]}


def faces_of(hedra, path, timeout):
    r = peak_kb([hedra, "info", path, "--json"], timeout)
    if r.get("rc") != 0:
        return None, r
    try:
        return sum(b["faces"] for b in json.loads(r["stdout"])["bodies"]), r
    except (json.JSONDecodeError, KeyError, TypeError):
        return None, {"error": "unreadable info --json output"}


def commands(hedra, path, work):
    return {
        # No JSON output: writing a million segments or faces as JSON would be measured instead.
        "hlr": [hedra, "hlr", path],
        "shadows": [hedra, "shadows", path],
        "render": [hedra, "render", path, "-o", os.path.join(work, "render.png"), "--shadows", "exact"],
    }


def measure_case(hedra, name, t, path, work, timeout=TIMEOUT_S):
    faces, info = faces_of(hedra, path, timeout)
    entry = {"case": name, "t": t, "faces": faces, "runs": {}}
    entry["runs"]["info"] = {k: info.get(k) for k in ("rc", "cpu_s", "wall_s", "peak_kb", "error")}
    for cmd_name, cmd in commands(hedra, path, work).items():
        r = peak_kb(cmd, timeout)
        keep = {k: r.get(k) for k in ("rc", "cpu_s", "wall_s", "peak_kb", "error")}
        if r.get("rc") == 0:
            # The command's own time of the work (hlr, shadows: "...; 1.23e+03 ms").
            m = re.search(r"([0-9.e+-]+) ms", r.get("stdout", ""))
            keep["ms"] = float(m.group(1)) if m else None
        if r.get("rc") not in (0, None):
            keep["stderr"] = r.get("stderr")
        entry["runs"][cmd_name] = keep
        print(f"  {name} t={t:g} faces={faces} {cmd_name}: "
              f"{keep.get('cpu_s') or 0:.2f} s CPU, {(keep.get('peak_kb') or 0) / 1024:.0f} MB"
              f"{'' if keep.get('rc') == 0 else ' FAILED ' + str(keep.get('error') or keep.get('stderr'))}",
              flush=True)
    return entry


STAR_POINTS = [400, 800, 4000]


def star_scene(n):
    """A prism over an n-point star (radii 1 and 0.5, n/2 reflex vertical edges), height 1."""
    import math
    polygon = [[(1.0 if i % 2 == 0 else 0.5) * math.cos(2 * math.pi * i / n),
                (1.0 if i % 2 == 0 else 0.5) * math.sin(2 * math.pi * i / n)] for i in range(n)]
    return {"version": 1, "bodies": [{"name": "star", "prism": {"polygon": polygon, "z": [0, 1]}},
                                      {"name": "ground", "box": {"min": [-3, -3, -0.5], "max": [3, 3, 0]}}],
            "camera": {"projection": "perspective", "eye": [3, -4, 3], "target": [0, 0, 0.5], "fov_deg": 40},
            "lights": LIGHTS, "image": IMAGE}


def measure_star(hedra, n, work):
    """`decompose` (the star alone, --threads 1) and `render --shadows exact` of the scene."""
    path = os.path.join(work, f"star{n}.json")
    with open(path, "w") as f:
        json.dump(star_scene(n), f)
    entry = {"case": "star", "t": n, "faces": n + 2, "runs": {}}
    for name, cmd in (("decompose", [hedra, "decompose", path, "--json", "--threads", "1"]),
                      ("render", [hedra, "render", path, "-o", os.path.join(work, "star.png"),
                                  "--shadows", "exact", "--threads", "1"])):
        r = peak_kb(cmd)
        keep = {k: r.get(k) for k in ("rc", "cpu_s", "wall_s", "peak_kb", "error")}
        if name == "decompose" and r.get("rc") == 0:
            try:
                keep["pieces"] = json.loads(r["stdout"])["pieces"]
            except (json.JSONDecodeError, KeyError, TypeError):
                keep["pieces"] = None
        if r.get("rc") not in (0, None):
            keep["stderr"] = r.get("stderr")
        entry["runs"][name] = keep
        print(f"  star n={n} {name}: {keep.get('cpu_s') or 0:.2f} s CPU", flush=True)
    return entry


def write_mesh(hedra, work):
    """A sphere of about 1 M triangles as an OFF file: hedra's own sphere converted (exact
    doubles), each quad written as two triangles. Its centre's y is 1e-3, off the grid on
    which sphere() snaps a moved sphere exactly planar (docs/primitives.md), so the corners
    are rounded as another tool's export would be: quads planar only within rounding, whose
    triangles do not merge back (about (-1.5, 0, 1.5) they would: an exactly convex sphere)."""
    src = os.path.join(work, "ball.json")
    with open(src, "w") as f:
        json.dump({"version": 1, "bodies": [{"name": "ball", "sphere": {
            "center": [-1.5, 1e-3, 1.5], "radius": 1.5, "tolerance": 1.5e-5, "max_faces": MAX_FACES}}]}, f)
    polys = os.path.join(work, "ball_polys.off")
    subprocess.run([hedra, "convert", src, polys], check=True, capture_output=True)
    with open(polys) as f:
        tokens = [line for line in f.read().splitlines() if line.strip() and not line.startswith("#")]
    assert tokens[0].strip() == "OFF"
    nv, nf, _ = (int(x) for x in tokens[1].split()[:3])
    verts = tokens[2:2 + nv]
    tris = []
    for line in tokens[2 + nv:2 + nv + nf]:
        ids = line.split()
        n = int(ids[0])
        ids = ids[1:1 + n]
        for k in range(1, n - 1):
            tris.append(f"3 {ids[0]} {ids[k]} {ids[k + 1]}")
    path = os.path.join(work, "ball_1m.off")
    with open(path, "w") as f:
        f.write(f"OFF\n{nv} {len(tris)} 0\n")
        f.write("\n".join(verts) + "\n")
        f.write("\n".join(tris) + "\n")
    return path, len(tris)


# Open terrains: n x n cells of two triangles (quick: 80 000 triangles; full: also 980 000).
TERRAIN_CELLS = [200, 700]


def write_terrain(work, n):
    """An open height-field terrain over [-4, 4]^2 of n x n cells, each two triangles: two hills
    and a ripple, every triangle a face of its own (no two exactly coplanar), as OFF. Open: hlr,
    shadows and render take it as two-sided faces (docs/io.md)."""
    import math
    path = os.path.join(work, f"terrain{n}.off")
    with open(path, "w") as f:
        f.write(f"OFF\n{(n + 1) ** 2} {2 * n * n} 0\n")
        for j in range(n + 1):
            for i in range(n + 1):
                x, y = -4 + 8 * i / n, -4 + 8 * j / n
                z = (0.8 * math.exp(-((x - 1) ** 2 + (y - 0.7) ** 2) / 1.4)
                     + 0.5 * math.exp(-((x + 1.6) ** 2 + (y + 1.3) ** 2) / 0.9) + 0.12 * math.sin(1.5 * x))
                f.write(f"{x:.17g} {y:.17g} {z:.17g}\n")
        at = lambda i, j: j * (n + 1) + i
        for j in range(n):
            for i in range(n):
                f.write(f"3 {at(i, j)} {at(i + 1, j)} {at(i + 1, j + 1)}\n")
                f.write(f"3 {at(i, j)} {at(i + 1, j + 1)} {at(i, j + 1)}\n")
    return path


def main():
    hedra, results = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    os.makedirs(results, exist_ok=True)
    out_path = os.path.join(results, "faces_scaling.json")
    entries = []
    # --only NAME reruns one case into an earlier run's file, which keeps its own quick flag
    # (the 980 000-triangle terrain added to a quick run: --only terrain700).
    record_quick = quick
    if only and os.path.exists(out_path):
        with open(out_path) as f:
            earlier = json.load(f)
        entries = [e for e in earlier["entries"] if e["case"] + str(e["t"]) != only]
        record_quick = earlier.get("quick", quick)
    with tempfile.TemporaryDirectory() as work:
        tolerances = [1e-2, 1e-3, 1e-4] + ([] if quick else [1e-5])
        for t in tolerances:
            if only and only != f"scene{t}":
                continue
            path = os.path.join(work, "scene.json")
            with open(path, "w") as f:
                json.dump(scene(t), f)
            entries.append(measure_case(hedra, "scene", t, path, work))
            save(out_path, record_quick, entries)
        if not only or only.startswith("star"):
            for n in STAR_POINTS:
                entries.append(measure_star(hedra, n, work))
                save(out_path, record_quick, entries)
        for n in TERRAIN_CELLS[:1] if quick and not only else TERRAIN_CELLS:
            if only and only != f"terrain{n}":
                continue
            mesh = write_terrain(work, n)
            path = os.path.join(work, f"terrain_scene{n}.json")
            with open(path, "w") as f:
                json.dump({"version": 1, "bodies": [{"name": "terrain", "mesh": os.path.basename(mesh)}],
                           "camera": CAMERA, "lights": LIGHTS, "image": IMAGE}, f)
            e = measure_case(hedra, "terrain", n, path, work, MESH_TIMEOUT_S)
            e["triangles"] = 2 * n * n
            entries.append(e)
            save(out_path, record_quick, entries)
        if not quick and (not only or only.startswith("mesh")):
            try:
                mesh, triangles = write_mesh(hedra, work)
                path = os.path.join(work, "mesh_scene.json")
                with open(path, "w") as f:
                    json.dump({"version": 1, "bodies": [SLAB, {"name": "ball", "mesh": os.path.basename(mesh)}],
                               "camera": CAMERA, "lights": LIGHTS, "image": IMAGE}, f)
                e = measure_case(hedra, "mesh", 0, path, work, MESH_TIMEOUT_S)
                e["triangles"] = triangles
            except (OSError, subprocess.CalledProcessError, AssertionError, ValueError) as err:
                e = {"case": "mesh", "t": 0, "faces": None, "runs": {"info": {"error": str(err)[-300:]}}}
            entries.append(e)
    save(out_path, record_quick, entries)


def save(path, quick, entries):
    """Written after every case, so that a later failure keeps the earlier results; with the
    load average (a shared machine inflates wall times, CPU times much less)."""
    with open(path, "w") as f:
        json.dump({"quick": quick, "load_average": os.getloadavg()[1], "entries": entries}, f, indent=1)


if __name__ == "__main__":
    main()
