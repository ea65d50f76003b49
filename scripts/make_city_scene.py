#!/usr/bin/env python3
"""Writes a scene JSON of a city of N x N box buildings on a ground slab, with a sun light:
the scene of docs/distributed.md's scaling table (40 x 40 = 1600 buildings).

Usage: scripts/make_city_scene.py [--side 40] [--seed 1] OUT.json
Heights, footprints and offsets come from a seeded generator, so the same arguments always
give the same file. Blocks are 12 m apart with 3..9 m footprints and 6..40 m heights.
"""
import argparse
import json
import random


def city(side: int, seed: int) -> dict:
    rnd = random.Random(seed)
    pitch = 12.0
    extent = side * pitch
    bodies = [{"name": "ground",
               "box": {"min": [-pitch, -pitch, -1], "max": [extent + pitch, extent + pitch, 0]}}]
    for i in range(side):
        for j in range(side):
            w, d = rnd.uniform(3, 9), rnd.uniform(3, 9)
            x, y = i * pitch + rnd.uniform(0, pitch - w), j * pitch + rnd.uniform(0, pitch - d)
            h = rnd.uniform(6, 40)
            bodies.append({"name": f"b{i}_{j}",
                           "box": {"min": [round(x, 3), round(y, 3), 0],
                                   "max": [round(x + w, 3), round(y + d, 3), round(h, 3)]}})
    c = extent / 2
    return {"version": 1, "bodies": bodies,
            "camera": {"projection": "perspective", "eye": [-extent, -extent, extent],
                       "target": [c, c, 0], "up": [0, 0, 1], "fov_deg": 40},
            "lights": [{"type": "sun", "latitude": 52.5, "longitude": 13.4,
                        "time": "2026-06-21T10:00:00Z"}]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--side", type=int, default=40, help="buildings per row (default 40)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(city(args.side, args.seed), f)
        f.write("\n")


if __name__ == "__main__":
    main()
