#!/usr/bin/env python3
"""Turns criterion's estimates of `cargo bench --bench samplers` into the
ns-per-sample tables of docs/benchmarks.md (sample, pdf, phase alone, the
slab renderer's connection).

Usage: python3 benches/summarize.py [CRITERION_DIR]
(default: $CARGO_TARGET_DIR/criterion, else target/criterion).

       python3 benches/summarize.py --compare BEFORE_DIR AFTER_DIR
prints every benchmark id of either directory (of any criterion bench, the
bridges' too) with its median per item in both and after ÷ before.

Every samplers benchmark processes BATCH = 256 samples (or vertices, or
connections) per iteration, so ns per item = criterion's mean time per
iteration / 256 (the median and the confidence interval are scaled alike). Prints Markdown tables to stdout.

Phase functions sampled through a table (ff, draine, mie10, rayleigh,
measured) have their exact sampler's OMNEE sample under `<name>-exact`;
the issue-12 table at the end gives every ratio the issue sets a target for,
from this one run.
"""
import json
import os
import sys
from collections import defaultdict

BATCH = 256


def load(root):
    out = {}
    for dirpath, _, files in os.walk(root):
        if "benchmark.json" not in files or not dirpath.endswith("new"):
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            b = json.load(f)
        with open(os.path.join(dirpath, "estimates.json")) as f:
            e = json.load(f)
        key = (b["group_id"], b.get("function_id"), b.get("value_str"))
        out[key] = {
            "mean": e["mean"]["point_estimate"] / BATCH,
            "lo": e["mean"]["confidence_interval"]["lower_bound"] / BATCH,
            "hi": e["mean"]["confidence_interval"]["upper_bound"] / BATCH,
            "median": e["median"]["point_estimate"] / BATCH,
        }
    return out


def medians(root):
    """{full id: (criterion's median per item, its 95 % CI)}: per item of
    the throughput where the benchmark declares one, else per iteration."""
    out = {}
    for dirpath, _, files in os.walk(root):
        if "benchmark.json" not in files or not dirpath.endswith("new"):
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            b = json.load(f)
        with open(os.path.join(dirpath, "estimates.json")) as f:
            m = json.load(f)["median"]
        items = (b.get("throughput") or {}).get("Elements", 1)
        ci = m["confidence_interval"]
        out[b["full_id"]] = (m["point_estimate"] / items,
                             ci["lower_bound"] / items, ci["upper_bound"] / items)
    return out


def compare(before, after):
    """Every id of either run, before and after side by side."""
    a, b = medians(before), medians(after)
    cell = lambda d: f"{d[0]:.1f} [{d[1]:.1f}, {d[2]:.1f}]" if d else "–"
    print("| criterion id | before | after | after ÷ before |")
    print("|---|---|---|---|")
    for key in sorted(set(a) | set(b)):
        x, y = a.get(key), b.get(key)
        ratio = f"{y[0] / x[0]:.2f}" if x and y else "–"
        print(f"| `{key}` | {cell(x)} | {cell(y)} | {ratio} |")


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        return compare(sys.argv[2], sys.argv[3])
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.environ.get("CARGO_TARGET_DIR", "target"), "criterion")
    data = load(root)
    techs = ["omnee", "equiangular", "distance", "mis"]
    phases = []
    for (g, f, v) in data:
        if g.startswith("sample/") and v not in phases:
            phases.append(v)
    order = ["iso", "hg0", "hg0.9", "hg0.98", "tthg", "ff", "draine", "mie10", "rayleigh",
             "measured"]
    exact = [p for p in phases if p.endswith("-exact")]
    phases = [p for p in phases if not p.endswith("-exact")]
    phases.sort(key=lambda p: order.index(p) if p in order else 99)

    def cell(d):
        return f"{d['mean']:.1f} [{d['lo']:.1f}, {d['hi']:.1f}]" if d else "—"

    for prec in ["f32", "f64"]:
        for what, title in [("sample", "sample (x1 with its pdf and weight)"),
                            ("pdf", "pdf(x1) at a sampled vertex")]:
            print(f"\n#### {prec}: ns per {title}, criterion mean [95 % CI]\n")
            extra = " | phase alone (sample_pdf) | omnee ÷ equiangular |" if what == "sample" else " | omnee ÷ equiangular |"
            print("| phase | " + " | ".join(techs) + extra)
            print("|---" * (len(techs) + (3 if what == "sample" else 2)) + "|")
            for p in phases:
                cells = [cell(data.get((f"{what}/{prec}", t, p))) for t in techs]
                o = data.get((f"{what}/{prec}", "omnee", p))
                e = data.get((f"{what}/{prec}", "equiangular", p))
                ratio = f"{o['mean'] / e['mean']:.2f}" if o and e else "—"
                row = f"| {p} | " + " | ".join(cells)
                if what == "sample":
                    ph = data.get((f"phase/{prec}", p, None))
                    row += f" | {ph['mean']:.1f}" if ph else " | —"
                print(row + f" | {ratio} |")
        c = data.get((f"connection/{prec}", "omnee-hg0.9", None))
        if c:
            print(f"\nNew connection per sample (Connection::new + OMNEE hg0.9 sample): "
                  f"{c['mean']:.1f} ns [{c['lo']:.1f}, {c['hi']:.1f}].")
    for prec in ["f32", "f64"]:
        if not exact:
            break
        print(f"\n#### {prec}: OMNEE sample with the exact sampler against the table, ns\n")
        print("| phase | exact sampler | table | exact ÷ table |")
        print("|---|---|---|---|")
        for p in sorted(exact, key=lambda p: order.index(p[:-6]) if p[:-6] in order else 99):
            e = data.get((f"sample/{prec}", "omnee", p))
            t = data.get((f"sample/{prec}", "omnee", p[:-6]))
            if e and t:
                print(f"| {p[:-6]} | {cell(e)} | {cell(t)} | {e['mean'] / t['mean']:.1f} |")
    targets(data)
    slab = [(t, data.get(("slab", t, None))) for t in techs]
    if any(d for _, d in slab):
        print("\n#### One once-more connection of the slab renderer (default scene), ns, criterion mean [95 % CI]\n")
        print("| " + " | ".join(techs) + " |")
        print("|---" * len(techs) + "|")
        print("| " + " | ".join(cell(d) for _, d in slab) + " |")

def targets(data):
    """The speed ratios the project tracks (docs/benchmarks.md §7), from this run (f32)."""
    get = lambda g, f, v=None: data.get((g, f, v))
    hg = get("sample/f32", "omnee", "hg0.9")
    eq = get("sample/f32", "equiangular", "hg0.9")
    if not (hg and eq):
        return
    print("\n#### Tracked ratios (f32, this run)\n")
    print("| quantity | measured | target |")
    print("|---|---|---|")
    for v in ["iso", "hg0", "hg0.9", "hg0.98"]:
        o, e = get("sample/f32", "omnee", v), get("sample/f32", "equiangular", v)
        if o and e:
            print(f"| OMNEE ÷ equiangular, {v} | {o['mean']:.1f} / {e['mean']:.1f} = "
                  f"{o['mean'] / e['mean']:.2f} | ≤ 0.35 (HG) |")
    for v in ["ff", "draine", "mie10", "rayleigh", "measured", "tthg"]:
        o = get("sample/f32", "omnee", v)
        if o:
            print(f"| OMNEE {v} ÷ OMNEE hg0.9 | {o['mean']:.1f} / {hg['mean']:.1f} = "
                  f"{o['mean'] / hg['mean']:.2f} | ≤ 1.5 |")
    for v in ["hg0", "hg0.9", "hg0.98"]:
        b, o = get("batch/f32", "omnee", v), get("sample/f32", "omnee", v)
        if b and o:
            print(f"| batch ÷ scalar OMNEE, {v} | {b['mean']:.1f} / {o['mean']:.1f} = "
                  f"{b['mean'] / o['mean']:.2f} | ≤ 0.5 |")


if __name__ == "__main__":
    main()
