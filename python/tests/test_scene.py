"""Scenes, cameras and lights; hidden lines, shadows, sun studies and rendering, each compared
with the `hedra` command on the same files (JSON equal except the timing field `ms`)."""

import gc
import json
import pickle

import numpy as np
import pytest

import hedra
from conftest import CITY, L_OUTLINE, run_cli


def small_scene():
    s = hedra.Scene()
    s.add("ground", hedra.box((-5, -5, -1), (10, 10, 0)), color=(0.7, 0.7, 0.65))
    s.add("L", hedra.prism(L_OUTLINE, z=(0, 2)), color=(0.8, 0.3, 0.2))
    s.add("ball", hedra.sphere((6, 6, 1), 1.0, tolerance=0.02))
    s.camera = hedra.Camera.perspective((-10, -12, 9), (2, 2, 0), 40)
    s.lights.append(hedra.Light.sun(52.5, 13.4, "2026-06-21T10:00:00Z"))
    return s


def without_ms(text):
    d = json.loads(text)
    d.pop("ms", None)
    return d


def test_scene_api():
    s = small_scene()
    assert len(s) == 3 and "L" in s and list(s.bodies) == ["ground", "L", "ball"]
    assert s.bodies["L"].volume == 12.0
    assert s.material("L").color == (0.8, 0.3, 0.2)
    assert s.camera.projection == "perspective" and s.camera.fov_deg == 40
    s.camera.width = 320  # the camera is the scene's own, not a copy
    assert s.camera.width == 320
    s.lights.append(hedra.Light.directional((-1, -2, -3), 0.5))
    s.lights.append(hedra.Light.point((0, 0, 10)))
    assert [l.type for l in s.lights] == ["sun", "directional", "point"]
    assert s.lights[0].time == "2026-06-21T10:00:00Z"
    s.lights = [hedra.Light.directional((0, 0, -1))]
    assert len(s.lights) == 1
    assert hedra.Camera.parallel((0, 0, -1), up=(0, 1, 0)).projection == "parallel"
    with pytest.raises(hedra.InvalidInput, match="used twice"):
        s.add("L", hedra.box((0, 0, 0), (1, 1, 1)))
    with pytest.raises(hedra.InvalidInput, match="below the horizon"):
        hedra.Light.sun(52.5, 13.4, "2026-06-21T23:00:00Z")


def test_read_write_round_trip(tmp_path):
    s = small_scene()
    hedra.write(s, str(tmp_path / "s.json"))
    t = hedra.read(str(tmp_path / "s.json"))
    assert t.source == str(tmp_path / "s.json")
    for name, b in s.bodies.items():
        assert t.bodies[name].vertices.tobytes() == b.vertices.tobytes()
    hedra.write(s.bodies["L"], tmp_path / "l.off")  # str or os.PathLike
    m = hedra.read(tmp_path / "l.off")
    assert list(m.bodies) == ["l"] and m.bodies["l"].volume == 12.0
    assert m.camera.projection == "parallel" and len(m.lights) == 1


def test_hidden_lines_equal_the_command(city_path, tmp_path):
    out = tmp_path / "hlr.json"
    run_cli("hlr", city_path, "--hidden", "--json", out)
    cli = without_ms(out.read_text())
    r = hedra.hidden_lines(hedra.read(city_path), hidden=True)
    assert without_ms(r.to_json()) == cli
    assert r.visible.shape == (len(cli["visible"]), 6)
    for kind in ("visible", "hidden", "junction"):
        assert np.array_equal(getattr(r, kind), np.array(cli[kind]).reshape(-1, 6))
    assert len(cli["hidden"]) > 0
    svg = r._repr_svg_()
    assert svg.startswith("<?xml") or svg.startswith("<svg")
    assert 'stroke-dasharray' in svg or 'hidden' in svg


def test_junction_lines_equal_the_command(tmp_path):
    s = hedra.Scene()
    s.add("a", hedra.box((0, 0, 0), (2, 2, 2)))
    s.add("b", hedra.box((1, 0.5, 1), (3, 1.5, 3)))
    s.camera = hedra.Camera.parallel((1, 2, -1.5))
    hedra.write(s, str(tmp_path / "j.json"))
    run_cli("hlr", tmp_path / "j.json", "--json", tmp_path / "j_hlr.json")
    cli = without_ms((tmp_path / "j_hlr.json").read_text())
    r = hedra.hidden_lines(s, hidden=False)
    assert without_ms(r.to_json()) == cli
    assert len(r.junction) > 0 and np.array_equal(r.junction, np.array(cli["junction"]))
    # Junction lines lie on the boundary of both bodies.
    for seg in r.junction:
        for p in (seg[:3], seg[3:], (seg[:3] + seg[3:]) / 2):
            assert s.bodies["a"].classify(p) != "outside" and s.bodies["b"].classify(p) != "outside"


def test_shadows_equal_the_command(city_path, tmp_path):
    for extra, visible in (([], False), (["--visible"], True)):
        out = tmp_path / "sh.json"
        run_cli("shadows", city_path, "--json", out, *extra)
        sh = hedra.shadows(hedra.read(city_path), visible=visible)
        assert without_ms(sh.to_json()) == without_ms(out.read_text())
    assert sh.light_count == 4
    # The records agree with the JSON's numbers.
    cli = json.loads(out.read_text())
    face = cli["lights"][0]["faces"][5]
    rec = sh.faces(0)[5]
    assert (rec["body"], rec["face"], rec["shadow_area"]) == (face["body"], face["face"], face["shadow_area"])


def test_sun_study_equals_the_command(city_path, tmp_path):
    out = tmp_path / "sun.json"
    run_cli("shadows", city_path, "--json", out, "--sun-hours", "06:00", "18:00", "90",
            "--grid", "ground", "5", "10")
    cli = json.loads(out.read_text())["sun_study"]
    st = hedra.sun_study(hedra.read(city_path), "06:00", "18:00", 90, grid=("ground", 5, 10))
    assert json.loads(st.to_json()) == cli
    assert st.times[0] == "2026-06-21T06:00:00Z" and len(st.times) == 9
    assert st.lit_fraction.shape == (9, len(st.faces))
    assert st.hours("ground", 5) == cli["faces"][5]["sun_hours"]
    assert np.array_equal(st.grid_hours, np.array(cli["grid"]["sun_hours"]))
    same = hedra.sun_study(hedra.read(city_path), "06:00", "18:00", 90, grid_body="ground",
                           grid_face=5, grid_spacing=10)
    assert same.to_json() == st.to_json()
    # A study pickles exactly (it travels back from worker processes).
    again = pickle.loads(pickle.dumps(st))
    assert again.to_json() == st.to_json()
    assert again.lit_fraction.tobytes() == st.lit_fraction.tobytes()


def test_sun_study_slices_combine_to_the_whole(city):
    args = (city, "2026-06-21T02:00:00Z", "2026-06-21T20:30:00Z", 60)
    whole = hedra.sun_study(*args, grid=("ground", 5, 10))
    total = hedra.sun_study_steps(*args)
    assert total == len(whole.times) == 20
    parts = [hedra.sun_study(*args, grid=("ground", 5, 10), first_step=first, step_count=count)
             for first, count in ((0, 7), (7, 7), (14, -1))]
    assert [p.first_step for p in parts] == [0, 7, 14]
    assert sum(len(p.times) for p in parts) == total
    # Slices travel between processes as pickles; the join is the whole study bit for bit.
    parts = [pickle.loads(pickle.dumps(p)) for p in parts]
    for joined in (hedra.combine_sun_studies(parts), hedra.SunStudy.combine(parts)):
        assert joined.to_json() == whole.to_json()
        assert joined.sun_hours.tobytes() == whole.sun_hours.tobytes()
        assert joined.grid_hours.tobytes() == whole.grid_hours.tobytes()
    with pytest.raises(hedra.InvalidInput):
        hedra.combine_sun_studies([parts[0], parts[2]])  # a gap


def test_render_equals_the_command(city_path, tmp_path):
    out = tmp_path / "r.png"
    run_cli("render", city_path, "-o", out, "--width", "160", "--height", "120", "--shading", "gouraud")
    img = hedra.render(hedra.read(city_path), width=160, height=120, shading="gouraud")
    assert isinstance(img, np.ndarray) and img.shape == (120, 160, 3) and img.dtype == np.uint8
    assert img.to_png() == out.read_bytes()
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


def test_decomposition_equals_the_command(tmp_path):
    b = hedra.prism(L_OUTLINE, z=(0, 2)).rotated((0, 0, 1), 30)
    hedra.write(b, str(tmp_path / "l.off"))
    run_cli("decompose", tmp_path / "l.off", "-o", tmp_path / "pieces")
    files = sorted((tmp_path / "pieces").glob("piece_*.off"))
    pieces = hedra.decompose(hedra.read(str(tmp_path / "l.off")).bodies["l"])
    assert len(pieces) == len(files) == 2
    for p, f in zip(pieces, files):
        q = hedra.read(str(f)).bodies[f.stem]
        assert q.vertices.tobytes() == p.vertices.tobytes()
        assert p.is_convex
    assert abs(sum(p.volume for p in pieces) - b.volume) <= 1e-12 * b.volume
    for method in ("float", "cgal"):
        ps = hedra.decompose(b, method=method, merge=True)
        assert all(p.is_convex for p in ps)
        assert abs(sum(p.volume for p in ps) - b.volume) <= 1e-9 * b.volume
    with pytest.raises(hedra.InvalidInput, match="AGPL"):
        hedra.decompose(b, method="tetgen")
    calls = []
    notched = hedra.subtract(hedra.box((0, 0, 0), (4, 4, 4)), hedra.box((1, 1, 1), (5, 5, 5)))
    with pytest.raises(hedra.Cancelled):
        hedra.decompose(notched, progress=lambda done, open: calls.append((done, open)) or False)
    assert len(calls) == 1
    assert len(hedra.decompose(notched, progress=lambda done, open: True)) >= 2


def test_progress_reports_and_cancels():
    """progress(done) sees fractions rising to 1; returning False raises hedra.Cancelled and
    returns nothing; an exception raised in the callable comes back as itself."""
    s = small_scene()
    for call in (lambda p: hedra.hidden_lines(s, progress=p),
                 lambda p: hedra.shadows(s, visible=True, progress=p),
                 lambda p: hedra.render(s, width=80, height=60, progress=p)):
        seen = []
        call(lambda done: seen.append(done))
        assert seen and seen == sorted(seen) and seen[-1] == 1.0
        with pytest.raises(hedra.Cancelled):
            call(lambda done: False)

        def boom(done):
            raise KeyError("stop")

        with pytest.raises(KeyError):
            call(boom)


def read_clip_output(path):
    rows = [list(map(float, line.split())) for line in open(path) if line.strip()]
    return np.array(rows).reshape(-1, 7)


@pytest.mark.parametrize("outside", [False, True])
@pytest.mark.parametrize("convex", [True, False])
def test_clipping_equals_the_command(tmp_path, outside, convex):
    rng = np.random.default_rng(7)
    segs = rng.uniform(-1, 5, size=(300, 6))
    segs[:20, 2] = segs[:20, 5] = 1.0  # some along a face plane
    body = hedra.box((0, 0, 0), (4, 3, 2)) if convex else hedra.prism(L_OUTLINE, z=(0, 2))
    hedra.write(body, str(tmp_path / "b.off"))
    np.savetxt(tmp_path / "s.txt", segs, fmt="%.17g")
    args = ["clip", "--body", tmp_path / "b.off", "--segments", tmp_path / "s.txt", "-o", tmp_path / "o.txt"]
    run_cli(*args, *(["--outside"] if outside else []))
    cli = read_clip_output(tmp_path / "o.txt")
    cli[:, 6] -= 1  # line numbers → row indices
    out = hedra.clip(body, segs, outside=outside)
    assert out.shape[1] == 7 and len(out) > 0
    assert np.array_equal(out, cli)
    if not outside:  # independent check: midpoints of the parts lie in the body
        mids = (out[:, :3] + out[:, 3:6]) / 2
        assert all(body.classify(m) != "outside" for m in mids)


def test_errors_name_file_and_place_as_the_command(tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 0 1\n")
    code, _, err = run_cli("info", bad, check=False)
    assert code == 3
    with pytest.raises(hedra.InvalidInput) as e:
        hedra.read(str(bad))
    assert str(e.value) == err.strip().removeprefix("hedra: error: ")
    assert str(bad) + ":7:" in str(e.value)
    scene = tmp_path / "bad.json"
    scene.write_text('{"version": 1, "bodies": [{"name": "a", "box": {"min": [0, 0, 0], "max": [1, 1]}}]}')
    code, _, err = run_cli("info", scene, check=False)
    with pytest.raises(hedra.InvalidInput) as e:
        hedra.read(str(scene))
    assert code == 3 and str(e.value) == err.strip().removeprefix("hedra: error: ")
    missing = tmp_path / "missing.off"
    code, _, err = run_cli("info", missing, check=False)
    with pytest.raises(hedra.IoError) as e:
        hedra.read(str(missing))
    assert isinstance(e.value, OSError)
    assert code == 3 and str(e.value) == err.strip().removeprefix("hedra: error: ")


def test_lifetime_bodies_and_lights_outlive_their_scene():
    s = small_scene()
    body = s.bodies["L"]
    lights = s.lights
    camera = s.camera
    del s
    gc.collect()
    assert body.volume == 12.0 and hedra.decompose(body)[0].is_convex
    assert lights[0].type == "sun" and camera.fov_deg == 40


def test_scene_pickle_round_trip():
    s = small_scene()
    s.add("hidden", hedra.box((0, 0, 0), (1, 1, 1)), hidden=True)
    t = pickle.loads(pickle.dumps(s))
    assert list(t.bodies) == list(s.bodies) and t.is_hidden("hidden")
    for name in s.bodies:
        assert t.bodies[name].vertices.tobytes() == s.bodies[name].vertices.tobytes()
    assert t.material("L") == s.material("L")
    assert t.camera.eye == s.camera.eye and t.lights[0].direction == s.lights[0].direction
    assert without_ms(hedra.shadows(t).to_json()) == without_ms(hedra.shadows(s).to_json())
    assert without_ms(hedra.hidden_lines(t).to_json()) == without_ms(hedra.hidden_lines(s).to_json())


def test_pickled_scene_keeps_the_exact_solids_of_its_bodies():
    # A plate drilled after both operands were rotated rounds its corners; hidden lines and
    # shadows clip against the pieces of its exact solid. A worker gets the scene as a pickle:
    # the solid travels with the body (Body.__getstate__, version 2), so the worker decides as
    # this process does, bit for bit; a body rebuilt from its vertices alone does not.
    s = small_scene()
    plate = hedra.box((2, -3, 0), (6, 1, 1)).rotated((1, 2, 3), 17, about=(4, -1, 0.5))
    drill = hedra.cylinder(0.5, z=(-1, 2), tolerance=0.01).translated((4, -1, 0)).rotated((1, 2, 3), 17, about=(4, -1, 0.5))
    s.add("plate", hedra.subtract(plate, drill))
    t = pickle.loads(pickle.dumps(s))
    assert t.bodies["plate"].has_exact_solid
    assert without_ms(hedra.shadows(t).to_json()) == without_ms(hedra.shadows(s).to_json())
    assert without_ms(hedra.hidden_lines(t).to_json()) == without_ms(hedra.hidden_lines(s).to_json())
    bare = small_scene()
    bare.add("plate", hedra.Body(s.bodies["plate"].vertices, s.bodies["plate"].faces))
    assert not bare.bodies["plate"].has_exact_solid


def test_threads_call_hedra_concurrently():
    from concurrent.futures import ThreadPoolExecutor
    s = small_scene()
    ref_lines = without_ms(hedra.hidden_lines(s).to_json())
    ref_shadows = without_ms(hedra.shadows(s).to_json())
    ref_pieces = [p.vertices.tobytes() for p in hedra.decompose(s.bodies["L"])]

    def work(i):
        if i % 3 == 0:
            return without_ms(hedra.hidden_lines(s).to_json()) == ref_lines
        if i % 3 == 1:
            return without_ms(hedra.shadows(s, threads=1).to_json()) == ref_shadows
        return [p.vertices.tobytes() for p in hedra.decompose(s.bodies["L"], threads=1)] == ref_pieces

    with ThreadPoolExecutor(max_workers=6) as pool:
        assert all(pool.map(work, range(24)))


def test_long_calls_release_the_gil(city):
    import threading
    import time
    span = {}

    def render():
        span["start"] = time.perf_counter()
        hedra.render(city, width=1600, height=1200, aa=16, threads=1)  # about 1 s: long enough anywhere
        span["end"] = time.perf_counter()

    ticks = []
    t = threading.Thread(target=render)
    t.start()
    while t.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    t.join()
    # Python code ran here while the render was inside C++ (with the GIL held it could not).
    inside = [x for x in ticks if span["start"] + 0.01 < x < span["end"] - 0.01]
    assert span["end"] - span["start"] > 0.05 and len(inside) > 0


def test_hidden_lines_draw_outlines_of_curved_bodies(tmp_path):
    # A unit sphere seen in parallel: no facet edge is drawn, its outline is a circle of
    # length 2π (within the chordal error); smooth=True adds the facet edges as "smooth";
    # crease_angle=0 draws every facet edge as "visible", as without line classes.
    path = tmp_path / "ball.json"
    path.write_text(json.dumps({
        "bodies": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": 1, "tolerance": 1e-3}}],
        "camera": {"projection": "parallel", "direction": [1, 2, -1.5], "up": [0, 0, 1]}}))
    s = hedra.read(str(path))
    d = np.array([1, 2, -1.5]) / np.linalg.norm([1, 2, -1.5])

    def picture_length(segments):
        v = segments[:, 3:] - segments[:, :3]
        return float(np.linalg.norm(v - np.outer(v @ d, d), axis=1).sum())

    r = hedra.hidden_lines(s, hidden=False)
    assert r.visible.shape == (0, 6) and r.smooth.shape == (0, 6)
    assert abs(picture_length(r.outline) - 2 * np.pi) < 5e-3 * 2 * np.pi
    assert r.stats["smooth_edges"] > 0
    assert np.array_equal(pickle.loads(pickle.dumps(s)).bodies["ball"].vertices, s.bodies["ball"].vertices)
    assert without_ms(hedra.hidden_lines(pickle.loads(pickle.dumps(s))).to_json()) == without_ms(r.to_json())
    run_cli("hlr", path, "--smooth", "--json", tmp_path / "ball_hlr.json")
    cli = without_ms((tmp_path / "ball_hlr.json").read_text())
    with_smooth = hedra.hidden_lines(s, hidden=False, smooth=True)
    assert without_ms(with_smooth.to_json()) == cli
    assert np.array_equal(with_smooth.outline, np.array(cli["outline"]).reshape(-1, 6))
    assert len(with_smooth.smooth) > 100 and 'class="smooth"' in with_smooth.svg()
    every_edge = hedra.hidden_lines(s, hidden=False, crease_angle=0)
    assert len(every_edge.outline) == 0 and len(every_edge.visible) > 100
    with pytest.raises(Exception, match="crease angle"):
        hedra.hidden_lines(s, crease_angle=200)
