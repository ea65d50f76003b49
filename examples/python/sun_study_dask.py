"""A sun study on a local Dask cluster: the hours of direct sun on every face of a scene,
the same numbers, bit for bit, as `hedra shadows SCENE --sun-hours START END STEP`.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sun_study_dask.py \
        examples/city-block.json --sun-hours 2026-06-21T02:00:00Z 2026-06-21T20:00:00Z 60

prints the summary line `hedra shadows` prints, then one line per face: body, face, hours
(17 significant digits, so that the numbers can be compared with the command's --json).
To use a cluster of several machines instead, pass --scheduler tcp://HOST:8786
(docs/distributed.md).
"""

import argparse
import json
import pathlib

import hedra
import hedra.distributed

HERE = pathlib.Path(__file__).resolve().parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=str(HERE.parent / "city-block.json"))
    parser.add_argument("--sun-hours", nargs=3, metavar=("START", "END", "STEP"),
                        default=["2026-06-21T02:00:00Z", "2026-06-21T20:00:00Z", "60"])
    parser.add_argument("--workers", type=int, default=2, help="local worker processes")
    parser.add_argument("--scheduler", help="a running scheduler instead (tcp://host:8786)")
    args = parser.parse_args()
    start, end, step = args.sun_hours[0], args.sun_hours[1], float(args.sun_hours[2])

    scene = hedra.read(args.scene)
    if args.scheduler:
        from distributed import Client

        with Client(args.scheduler) as client:
            study = hedra.distributed.sun_study(scene, start, end, step, client=client)
    else:
        study = hedra.distributed.sun_study(scene, start, end, step, workers=args.workers)

    result = json.loads(study.to_json())
    hours = [f["sun_hours"] for f in result["faces"]]
    up = sum(1 for s in result["steps"] if s["sun_up"])
    print(f"  sun study: {len(result['steps'])} steps from {result['start']} to {result['end']}, "
          f"sun up at {up}; hours of direct sun per face from {min(hours):.3g} to "
          f"{max(hours):.3g}")
    for f in result["faces"]:
        print(f"{f['body']} {f['face']} {f['sun_hours']:.17g}")


if __name__ == "__main__":
    main()
