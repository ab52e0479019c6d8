#!/usr/bin/env python3
"""omnee's Python batch: ns per sample of `Omnee.sample` against N, one
connection and one connection per row, on all cores and on one; the peak
memory of a call against its output arrays; the ratio to the core's
criterion benchmarks if their results are at hand.

Usage (with omnee installed, e.g. `pip install ./omnee-py`):

    python3 benches/python/batch.py [--quick] [--criterion DIR] [--dtype float32|float64]
                                    [--instructions]
    python3 benches/python/batch.py --gate N CALLS  # benches/gate.py's measurement

Times: wall time (time.perf_counter) and CPU time of the whole process,
all threads (time.process_time), per sample, the best of several calls
(at least 3, and at least 10^7 samples per size). "1 thread" runs in a
child process with RAYON_NUM_THREADS=1, so its CPU time per sample compares
with criterion's CPU time of the core's own loops; "all cores" is what a
user's call takes. Per row: x0 and x2 of shape (N, 3), each row its own
connection, timed with the construction of the technique (what a renderer
pays per batch: it makes one technique per batch of shading points).

Memory: each size in a fresh child process; the inputs are made in place
(no temporaries), one small call warms the pool up, then the peak resident
set of the process (VmHWM in /proc/self/status) before and after one call;
the increase is divided by the bytes of the arrays the call returns (x1,
pdf, weight, valid).

Instructions (--instructions, needs valgrind): user-space instructions per
sample of one call on one thread, counted by callgrind, whatever the load
of the machine (the page faults of fresh arrays are the kernel's, not
counted).

Prints Markdown tables (docs/benchmarks.md has the output of one run).
"""

import argparse
import json
import os
import pathlib
import resource
import subprocess
import sys
import time

import numpy as np

import omnee

PHASE = "hg:0.9"
X0, X2 = (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
SIZES = [10**4, 10**5, 10**6, 10**7]


def inputs(n, dtype, rows):
    """Uniform numbers and, per row, end points made in place (no
    temporaries: the memory run counts every byte). Rows: the light on a
    ring of radius 0.1 about x0 and receivers about x2, never coincident."""
    rng = np.random.default_rng(1)

    def uniform():
        a = np.empty((n, 3), dtype)
        rng.random(out=a, dtype=dtype)
        return a

    u = uniform()
    if not rows:
        return u, X0, X2
    x0, x2 = uniform(), uniform()
    x0 *= 0.1
    x0 += np.asarray(X0, dtype)
    x2 *= 0.1
    x2 -= np.asarray((0.0, 0.0, 0.5), dtype)
    return u, x0, x2


def timed(n, dtype, case, repeats):
    """(wall, CPU, system) seconds per sample: wall and CPU time (of the
    whole process, all threads: time.process_time) the least of `repeats`
    calls; the system part of the CPU time (page faults) over all calls
    (getrusage counts it in clock ticks). `case`: "one" (fresh output
    arrays, as `t.sample(u)` returns them), "out" (into arrays made once,
    `out=`), "rows" (a connection per row, the technique made in the call)."""
    u, x0, x2 = inputs(n, dtype, case == "rows")
    one = omnee.Omnee(X0, X2, PHASE)
    out = None
    if case == "out":
        out = [np.empty((n, *a.shape[1:]), a.dtype) for a in one.sample(u[:1])]
        one.sample(u, out=out)  # the pages of the arrays made once
    best_wall = best_cpu = float("inf")
    system = resource.getrusage(resource.RUSAGE_SELF).ru_stime
    for _ in range(repeats):
        s = None  # the previous call's arrays are freed, as in a user's loop
        c, w = time.process_time(), time.perf_counter()
        if case == "rows":
            s = omnee.Omnee(x0, x2, PHASE).sample(u)
        else:
            s = one.sample(u, out=out)
        w, c = time.perf_counter() - w, time.process_time() - c
        best_wall, best_cpu = min(best_wall, w), min(best_cpu, c)
    system = resource.getrusage(resource.RUSAGE_SELF).ru_stime - system
    del s
    return best_wall / n, best_cpu / n, system / (n * repeats)


CASES = ["one", "out", "rows"]


def repeats_for(n, quick):
    return max(3, (10**6 if quick else 10**7) // n)


def speed(dtype, quick):
    """{(case, n): (wall, user, system)} in this process."""
    return {
        (case, n): timed(n, dtype, case, repeats_for(n, quick)) for case in CASES for n in SIZES
    }


def child(args, env=None):
    """This script with `args` in a child process; its JSON output."""
    cmd = [sys.executable, __file__, *args]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out)


def peak_rss(n, dtype, rows):
    """(increase of the peak RSS over one call, bytes of its outputs)."""
    u, x0, x2 = inputs(n, dtype, rows)
    t = omnee.Omnee(x0, x2, PHASE) if rows else omnee.Omnee(X0, X2, PHASE)
    small = 1000
    if rows:
        omnee.Omnee(x0[:small], x2[:small], PHASE).sample(u[:small])
    else:
        t.sample(u[:small])
    before = peak_rss_bytes()
    s = t.sample(u)
    return peak_rss_bytes() - before, sum(a.nbytes for a in s)


def peak_rss_bytes():
    """The peak resident set of this process's memory (VmHWM; getrusage's
    ru_maxrss would start from the parent's resident set at the fork)."""
    for line in pathlib.Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def instructions(n, dtype, case):
    """Instructions per sample of one call (valgrind's callgrind, which
    counts user-space instructions whatever the load): the difference
    between a child that makes 5 calls and one that makes 1, over 4n."""
    counts = []
    for calls in (1, 5):
        cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable,
               __file__, "--calls-child", str(n), case, str(calls), "--dtype", dtype.name]
        env = dict(os.environ, RAYON_NUM_THREADS="1")
        err = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stderr
        refs = [line for line in err.splitlines() if "refs:" in line][-1]
        counts.append(int(refs.split()[-1].replace(",", "")))
    return (counts[1] - counts[0]) / (4 * n)


def calls(n, dtype, case, k):
    """`k` calls of `case` on the same inputs (the child of `instructions`)."""
    u, x0, x2 = inputs(n, dtype, case == "rows")
    one = omnee.Omnee(X0, X2, PHASE)
    for _ in range(k):
        (omnee.Omnee(x0, x2, PHASE) if case == "rows" else one).sample(u)


# The core's criterion ids and their directories under target/criterion
# (criterion writes a group "batch/f32" as batch_f32).
CORE = {
    "connections_f32/omnee/hg0.9": "connections_f32/omnee/hg0.9",
    "batch/f32/omnee/hg0.9": "batch_f32/omnee/hg0.9",
    "sample/f32/omnee/hg0.9": "sample_f32/omnee/hg0.9",
    "connection/f32/omnee-hg0.9": "connection_f32/omnee-hg0.9",
    "sample/f64/omnee/hg0.9": "sample_f64/omnee/hg0.9",
}


def criterion(directory):
    """ns per sample of the core's benchmarks in `CORE`, those measured:
    the batch over connections (one per lane), the one-connection batch,
    the scalar sampler, a connection made per sample, the f64 scalar
    sampler (256 samples per iteration each)."""
    found = {}
    for name, path in CORE.items():
        path = pathlib.Path(directory, path, "new", "estimates.json")
        if path.is_file():
            found[name] = json.loads(path.read_text())["mean"]["point_estimate"] / 256
    return found


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="fewer repeats")
    p.add_argument("--dtype", default="float32", choices=["float32", "float64"])
    target = os.environ.get("CARGO_TARGET_DIR", "target")
    p.add_argument("--criterion", default=str(pathlib.Path(target, "criterion")))
    p.add_argument("--speed-child", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--memory-child", nargs=2, help=argparse.SUPPRESS)
    p.add_argument("--calls-child", nargs=3, help=argparse.SUPPRESS)
    p.add_argument("--gate", nargs=2, type=int, metavar=("N", "CALLS"),
                   help="print CPU ns per draw of one connection and per row (N draws, "
                        "the least of CALLS calls of each, in turns of five, in this process) "
                        "as JSON")
    p.add_argument("--instructions", action="store_true",
                   help="also count instructions per sample with valgrind (minutes)")
    a = p.parse_args()
    dtype = np.dtype(a.dtype)

    if a.speed_child:
        print(json.dumps([[c, n, *v] for (c, n), v in speed(dtype, a.quick).items()]))
        return
    if a.memory_child:
        n, rows = int(a.memory_child[0]), a.memory_child[1] == "rows"
        print(json.dumps(peak_rss(n, dtype, rows)))
        return
    if a.calls_child:
        calls(int(a.calls_child[0]), dtype, a.calls_child[1], int(a.calls_child[2]))
        return
    if a.gate:
        # The two cases in turns of five calls, so that both see the same
        # load (and each turn's later calls reuse the memory its first
        # call's arrays had); the least CPU time of each.
        n, k = a.gate
        best = {"one": float("inf"), "rows": float("inf")}
        for _ in range(max(1, k // 5)):
            for case in best:
                best[case] = min(best[case], timed(n, dtype, case, 5)[1])
        print(json.dumps({case: cpu * 1e9 for case, cpu in best.items()}))
        return

    flags = ["--dtype", a.dtype] + (["--quick"] if a.quick else [])
    print(f"omnee {omnee.__version__}, numpy {np.__version__}, Python {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at start; "
          f"Omnee({PHASE}), {a.dtype}\n")
    single = dict(os.environ, RAYON_NUM_THREADS="1")
    runs = {"1 thread": {(c, n): tuple(v) for c, n, *v in child(["--speed-child", *flags], single)}}
    runs["all cores"] = speed(dtype, a.quick)
    core = criterion(a.criterion)
    batch = core.get("connections_f32/omnee/hg0.9") if a.dtype == "float32" else None
    scalar = core.get(f"sample/{'f32' if a.dtype == 'float32' else 'f64'}/omnee/hg0.9")
    print("#### ns per sample: wall / CPU of all threads (in parentheses: the system part, page faults, mean over the calls); wall and CPU the least of several calls\n")
    print("| threads | N | one connection | one, into `out=` | per row (made in the call) "
          "| per row ÷ one (CPU) |" + (" one ÷ core scalar (CPU) |" if scalar else "")
          + (" one ÷ core batch (CPU) |" if batch else ""))
    print("|---|---|---|---|---|---|" + ("---|" if scalar else "") + ("---|" if batch else ""))
    cell = lambda v: f"{v[0] * 1e9:.1f} / {v[1] * 1e9:.1f} ({v[2] * 1e9:.1f})"
    for label, r in runs.items():
        for n in SIZES:
            row = f"| {label} | 10^{len(str(n)) - 1} | " + " | ".join(cell(r[(c, n)]) for c in CASES)
            row += f" | {r[('rows', n)][1] / r[('one', n)][1]:.2f} |"
            for reference in (scalar, batch):
                if reference:
                    row += f" {r[('one', n)][1] * 1e9 / reference:.2f} |"
            print(row)
    print()
    for label, r in runs.items():
        for c in CASES:
            wall, cpu = ([r[(c, n)][k] for n in SIZES[1:]] for k in (0, 1))
            print(f"- {label}, {c}: max ÷ min over N = 10^5…10^7: wall {max(wall) / min(wall):.2f}, "
                  f"CPU {max(cpu) / min(cpu):.2f}")
    if core:
        print("- the core (criterion, CPU, ns per sample): "
              + ", ".join(f"`{k}` {v:.1f}" for k, v in core.items()))
    print("\n#### Peak memory of one call (child process per row of the table)\n")
    print("| N | connections | outputs (MB) | peak RSS increase (MB) | ratio |")
    print("|---|---|---|---|---|")
    for n in SIZES[2:]:
        for rows in ("one", "rows"):
            grew, outputs = child(["--memory-child", str(n), rows, *flags])
            print(f"| 10^{len(str(n)) - 1} | {'per row' if rows == 'rows' else 'one'} "
                  f"| {outputs / 1e6:.1f} | {grew / 1e6:.1f} | {grew / outputs:.2f} |")
    if a.instructions:
        print("\n#### Instructions per sample, one thread (callgrind)\n")
        print("| N | one connection | per row (made in the call) | per row ÷ one |")
        print("|---|---|---|---|")
        for n in (10**5,):
            one, rows = instructions(n, dtype, "one"), instructions(n, dtype, "rows")
            print(f"| 10^{len(str(n)) - 1} | {one:.0f} | {rows:.0f} | {rows / one:.2f} |")


if __name__ == "__main__":
    main()
