"""Sun study: hours of direct sun on a courtyard's floor and on the street, 21 June in Berlin.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sun_study.py [OUT_DIR]

Prints the sun's path and the hours of sun of chosen faces, and writes OUT_DIR/sun-study.json
(the `sun_study` object of `hedra shadows --json --sun-hours`) and OUT_DIR/sun-grid.csv
(hours of sun at sample points of the courtyard floor).
"""

import pathlib
import sys

import numpy as np

import hedra

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)

s = hedra.Scene()
s.add("street", hedra.box((-20, -20, -1), (40, 40, 0)))
# A block of 8 m around a 10 × 10 m courtyard, 15 m high; the courtyard floor is its own body.
block = hedra.subtract(hedra.box((0, 0, 0), (26, 26, 15)), hedra.box((8, 8, -1), (18, 18, 16)))
s.add("block", block)
s.add("yard", hedra.box((8, 8, -0.5), (18, 18, 0)))
s.add("tower", hedra.box((30, 0, 0), (36, 6, 40)))
s.lights.append(hedra.Light.sun(52.52, 13.40, "2026-06-21T12:00:00Z"))

st = hedra.sun_study(s, start="03:00", end="20:00", step_minutes=30, grid=("yard", 5, 1.0))

print("time (UTC)            elevation  azimuth")
for t, e, a, up in zip(st.times, st.elevation_deg, st.azimuth_deg, st.sun_up):
    if t.endswith(":00:00Z"):
        print(f"{t}  {e:8.2f}° {a:8.2f}°{'' if up else '  (below the horizon)'}")

faces = st.faces
hours = st.sun_hours
print(f"\nhours of direct sun ({st.times[0]} to {st.times[-1]}, every {st.step_minutes:g} min):")
for name, face in [("street", 5), ("yard", 5), ("tower", 5), ("tower", 2)]:
    print(f"  {name:6s} face {face}: {st.hours(name, face):5.2f} h")
print(f"  most sun of any face: {hours.max():.2f} h ({faces[int(hours.argmax())]})")
g = st.grid_hours
print(f"\ncourtyard floor, {len(g)} points 1 m apart: {g.min():.1f} to {g.max():.1f} h, mean {g.mean():.2f} h")

(out / "sun-study.json").write_text(st.to_json() + "\n")
np.savetxt(out / "sun-grid.csv", np.column_stack([st.grid_points, g]), delimiter=",",
           header="x,y,z,sun_hours", comments="", fmt="%.6g")
print("wrote", out / "sun-study.json", "and", out / "sun-grid.csv")
