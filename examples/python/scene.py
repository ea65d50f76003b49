"""A small town square built in Python, drawn as a hidden-line SVG and rendered as a PNG.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/scene.py [OUT_DIR]

writes OUT_DIR/square-lines.svg (visible lines, hidden lines dashed) and
OUT_DIR/square-render.png (Phong shading, exact shadows of the sun at 10:00 UTC).
"""

import pathlib
import sys

import hedra

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)

s = hedra.Scene()
s.add("ground", hedra.box((-10, -10, -0.5), (30, 25, 0)), color=(0.72, 0.72, 0.66))
# An L-shaped block, turned 20 degrees and moved into place.
s.add("hall", hedra.prism([[0, 0], [8, 0], [8, 3], [3, 3], [3, 7], [0, 7]], z=(0, 4))
      .rotated((0, 0, 1), 20).translated((2, 2, 0)), color=(0.85, 0.55, 0.35))
# A courtyard house: a box with a box cut out (exact Boolean).
court = hedra.subtract(hedra.box((14, 4, 0), (22, 12, 5)), hedra.box((16, 6, -1), (20, 10, 6)))
s.add("court", court, color=(0.6, 0.65, 0.8))
# A tower with a conical roof, and a ball on a plinth.
s.add("tower", hedra.cylinder(1.5, z=(0, 9), tolerance=0.02).translated((8, 16, 0)), color=(0.8, 0.8, 0.75))
s.add("roof", hedra.cone(1.9, z=(9, 12), tolerance=0.02).translated((8, 16, 0)), color=(0.7, 0.25, 0.2))
s.add("plinth", hedra.box((20, -6, 0), (22, -4, 1)))
s.add("ball", hedra.sphere((21, -5, 2), 1.0, tolerance=0.01), color=(0.9, 0.8, 0.3))

s.camera = hedra.Camera.perspective(eye=(-18, -30, 22), target=(12, 9, 1), fov_deg=40)
s.camera.width, s.camera.height = 960, 640
s.lights.append(hedra.Light.sun(52.52, 13.40, "2026-06-21T10:00:00Z"))

lines = hedra.hidden_lines(s, hidden=True)
(out / "square-lines.svg").write_text(lines.svg(title="hedra: a square built in Python"))
print(f"hidden lines: {len(lines.visible)} visible, {len(lines.hidden)} hidden, "
      f"{len(lines.junction)} junction segments ({lines.ms:.0f} ms)")

img = hedra.render(s, shadows="exact", aa=4)
img.save(out / "square-render.png")
print(f"render: {img.shape[1]} x {img.shape[0]} pixels")

sh = hedra.shadows(s)
ground_top = sh.face("ground", 5)
print(f"shadow on the ground: {ground_top['shadow_area']:.2f} of {ground_top['area']:.0f} m²")
print("wrote", out / "square-lines.svg", "and", out / "square-render.png")
