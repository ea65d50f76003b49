"""The examples in examples/python run and write what they say (the matplotlib one is left to
`make bench-build`'s packages: python3-matplotlib is not a build dependency)."""

import json
import os
import subprocess
import sys

import numpy as np

from conftest import ROOT



def run_example(name, out):
    env = dict(os.environ)
    subprocess.run([sys.executable, str(ROOT / "examples" / "python" / name), str(out)], check=True,
                   env=env, capture_output=True, timeout=120)


def test_scene_example(tmp_path):
    run_example("scene.py", tmp_path)
    png = (tmp_path / "square-render.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    svg = (tmp_path / "square-lines.svg").read_text()
    assert "<svg" in svg and "</svg>" in svg


def test_sun_study_example(tmp_path):
    run_example("sun_study.py", tmp_path)
    study = json.loads((tmp_path / "sun-study.json").read_text())
    grid = np.loadtxt(tmp_path / "sun-grid.csv", delimiter=",", skiprows=1)
    assert grid.shape == (len(study["grid"]["points"]), 4)
    # Hours of sun never exceed the length of the study (17 h) and the grid agrees with the JSON.
    assert (grid[:, 3] >= 0).all() and (grid[:, 3] <= 17).all()
    np.testing.assert_allclose(grid[:, 3], study["grid"]["sun_hours"], rtol=1e-5, atol=1e-9)
