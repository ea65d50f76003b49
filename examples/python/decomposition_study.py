"""Decomposition study: how many convex pieces, and how fast, as a body gets more notches.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/decomposition_study.py [OUT_DIR]

A comb (a bar with n teeth, turned 15 degrees so no plane is axis-aligned) is split into
convex pieces by hedra's exact plane splitting, with and without the merge pass, by the
floating-point variant and by CGAL's Nef decomposition. Prints a table and draws
OUT_DIR/decomposition-study.png (python3-matplotlib).
"""

import pathlib
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import hedra  # noqa: E402

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)


def comb(teeth):
    """A bar 1 deep with `teeth` teeth 1 wide and 2 high, gaps of 1 between them."""
    outline = [(0.0, 0.0), (2.0 * teeth - 1, 0.0)]
    for i in reversed(range(teeth)):
        x = 2.0 * i
        outline += [(x + 1, 3.0), (x, 3.0)] if i == teeth - 1 else [(x + 1, 1.0), (x + 1, 3.0), (x, 3.0)]
        if i > 0:
            outline.append((x, 1.0))
    return hedra.prism(outline, z=(0, 1)).rotated((0, 0, 1), 15)


methods = [("planes", {}), ("planes", {"merge": True}), ("float", {}), ("cgal", {})]
# CGAL's method takes no thread count; hedra's run on one thread here for steady timings.
labels = ["planes (exact)", "planes + merge", "float", "CGAL Nef"]
teeth = [2, 4, 8, 16, 32]
pieces = {label: [] for label in labels}
millis = {label: [] for label in labels}

print(f"{'teeth':>5} " + " ".join(f"{label:>16}" for label in labels))
for n in teeth:
    body = comb(n)
    row = []
    for (method, options), label in zip(methods, labels):
        ms = float("inf")
        for _ in range(3):  # best of three: the machine may be busy
            t0 = time.perf_counter()
            parts = hedra.decompose(body, method=method, threads=1, **options)
            ms = min(ms, 1000 * (time.perf_counter() - t0))
        assert all(p.is_convex for p in parts)
        assert abs(sum(p.volume for p in parts) - body.volume) <= 1e-9 * body.volume
        pieces[label].append(len(parts))
        millis[label].append(ms)
        row.append(f"{len(parts):5d} in {ms:6.1f} ms")
    print(f"{n:5d} " + " ".join(f"{cell:>16}" for cell in row))

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
styles = [("o", "-"), ("s", "--"), ("^", ":"), ("D", "-")]  # the first three coincide in pieces
for label, (marker, line) in zip(labels, styles):
    a.plot(teeth, pieces[label], marker=marker, linestyle=line, label=label)
    b.plot(teeth, millis[label], marker=marker, linestyle=line, label=label)
a.set(xlabel="teeth of the comb", ylabel="convex pieces", title="Pieces", xscale="log", yscale="log")
b.set(xlabel="teeth of the comb", ylabel="time (ms)", title="Time", xscale="log", yscale="log")
for ax in (a, b):
    ax.set_xticks(teeth, [str(t) for t in teeth])
    ax.grid(True, which="both", alpha=0.3)
a.legend()
fig.suptitle("hedra.decompose on a comb with n teeth")
fig.tight_layout()
fig.savefig(out / "decomposition-study.png", dpi=100)
print("wrote", out / "decomposition-study.png")
