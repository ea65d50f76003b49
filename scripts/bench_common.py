"""What every report script of docs/benchmarks.md shares: the machine line, reading Google
Benchmark JSON into repetitions per benchmark and arguments, and splicing one section into the
page when a report script runs on its own.
"""
import os
import platform
import re
import statistics
import sys

UNIT_MS = {"ms": 1, "us": 1e-3, "ns": 1e-6, "s": 1e3}


def machine():
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{os.cpu_count()} cores, {model}, {platform.system()} {platform.release()}"


def parse(name):
    """'BM_Batch/shape:0/threads:2/real_time' -> ('BM_Batch', {'shape': 0, 'threads': 2})."""
    parts = name.split("/")
    args = {}
    for p in parts[1:]:
        m = re.fullmatch(r"(\w+):(-?\d+)", p)
        if m:
            args[m.group(1)] = int(m.group(2))
    return parts[0], args


def collect(data):
    """(benchmark, frozen args) -> list of repetitions (aggregates dropped)."""
    out = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        base, args = parse(b.get("run_name", b["name"]))
        out.setdefault((base, tuple(sorted(args.items()))), []).append(b)
    return out


def by_run_name(data):
    """run name -> list of repetitions (aggregates dropped), for benchmarks named without args."""
    out = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        out.setdefault(b.get("run_name", b["name"]), []).append(b)
    return out


def entry_ms(entry):
    """One repetition's real time in ms."""
    return entry["real_time"] * UNIT_MS[entry["time_unit"]]


def times_ms(entries):
    """(median, min, max) of the repetitions' real times, in ms."""
    ts = [entry_ms(e) for e in entries]
    return statistics.median(ts), min(ts), max(ts)


def fmt_times(t):
    """'median [min–max]' of times_ms()."""
    return f"{t[0]:.3g} [{t[1]:.3g}–{t[2]:.3g}]"


def standalone(section_fn, bench_name, heading):
    """main() of a report script run by itself: RESULTS_DIR DOCS_DIR on the command line; the
    section replaces the one under `heading` in DOCS_DIR/benchmarks.md (or is appended)."""
    results, docs = sys.argv[1], sys.argv[2]
    section = section_fn(results, docs, bool(os.environ.get("HEDRA_BENCH_QUICK")))
    if not section:
        sys.exit(f"{results}/{bench_name}.json not found")
    page = os.path.join(docs, "benchmarks.md")
    text = open(page).read() if os.path.exists(page) else "# Benchmarks\n\n"
    start = text.find(heading)
    if start < 0:
        text = text.rstrip("\n") + "\n\n" + section
    else:
        end = text.find("\n## ", start + 1)
        text = text[:start] + section + ("" if end < 0 else text[end + 1:])
    with open(page, "w") as f:
        f.write(text)
