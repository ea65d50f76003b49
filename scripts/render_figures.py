#!/usr/bin/python3
"""The figures of docs/rendering.md: the shadow methods side by side on a corner of a city.

Usage: render_figures.py [HEDRA_BINARY] [DOCS_DIR]   (defaults: build/hedra, docs)
Writes a 10 × 10 city scene (ground slab [0, 100]², boxes with footprints [0.2p, 0.8p]² in
cells of p = 10, seeded heights p/4 … 9p/8, the sun along (−1, −2, −3)) to a temporary file,
renders it with `hedra render` once per method and puts the same crop of each side by side in
DOCS_DIR/render_methods.png.
"""
import json
import os
import random
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

METHODS = [("exact", "exact"), ("map:512:0", "map:512:0 (acne)"),
           ("map:512:6", "map:512:6 (blocky, pulled back)"), ("rays:16", "rays:16")]
CROP = (250, 450, 230, 430)  # rows, columns of the 640 × 640 picture


def city(n=10):
    p = 100.0 / n
    rng = random.Random(12345)
    bodies = [{"name": "ground", "box": {"min": [0, 0, -1], "max": [100, 100, 0]},
               "material": {"color": [0.75, 0.75, 0.7], "ks": 0}}]
    for i in range(n):
        for j in range(n):
            h = p / 4 + (9 * p / 8 - p / 4) * rng.random()
            bodies.append({"name": f"b{i}_{j}", "box": {"min": [i * p + 0.2 * p, j * p + 0.2 * p, 0],
                                                       "max": [i * p + 0.8 * p, j * p + 0.8 * p, h]}})
    return {"version": 1, "bodies": bodies,
            "camera": {"projection": "perspective", "eye": [140, -35, 85], "target": [50, 50, 0],
                       "up": [0, 0, 1], "fov_deg": 50},
            "lights": [{"type": "directional", "direction": [-1, -2, -3], "intensity": 0.9}],
            "image": {"width": 640, "height": 640, "background": [1, 1, 1]}}


def main():
    hedra = sys.argv[1] if len(sys.argv) > 1 else "build/hedra"
    docs = sys.argv[2] if len(sys.argv) > 2 else "docs"
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "city.json")
        with open(scene, "w") as f:
            json.dump(city(), f)
        fig, axes = plt.subplots(1, len(METHODS), figsize=(4 * len(METHODS), 4.4))
        for ax, (method, title) in zip(axes, METHODS):
            out = os.path.join(tmp, method.replace(":", "_") + ".png")
            subprocess.run([hedra, "render", scene, "-o", out, "--shadows", method], check=True,
                           stdout=subprocess.DEVNULL)
            r0, r1, c0, c1 = CROP
            ax.imshow(mpimg.imread(out)[r0:r1, c0:c1], interpolation="nearest")
            ax.set_title(title, fontsize=11)
            ax.axis("off")
        fig.tight_layout()
        fig.savefig(os.path.join(docs, "render_methods.png"), dpi=80)
        plt.close(fig)


if __name__ == "__main__":
    main()
