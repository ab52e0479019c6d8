#!/usr/bin/env python3
"""Turns criterion's estimates of `cargo bench --bench samplers` into the
ns-per-sample tables of docs/benchmarks.md.

Usage: python3 benches/summarize.py [CRITERION_DIR]
(default: $CARGO_TARGET_DIR/criterion, else target/criterion).

Every samplers benchmark processes BATCH = 256 samples per iteration, so
ns/sample = criterion's mean time per iteration / 256 (the median and the
confidence interval are scaled alike). Prints Markdown tables to stdout.
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


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.environ.get("CARGO_TARGET_DIR", "target"), "criterion")
    data = load(root)
    techs = ["omnee", "equiangular", "distance", "mis"]
    phases = []
    for (g, f, v) in data:
        if g.startswith("technique/") and v not in phases:
            phases.append(v)
    order = ["iso", "hg0", "hg0.9", "hg0.98", "tthg", "ff", "draine", "mie10", "rayleigh"]
    phases.sort(key=lambda p: order.index(p) if p in order else 99)
    for prec in ["f32", "f64"]:
        print(f"\n#### {prec}: ns per sample (sample + pdf), criterion mean [95 % CI]\n")
        print("| phase | " + " | ".join(techs) + " | phase alone | omnee ÷ equiangular |")
        print("|---" * (len(techs) + 3) + "|")
        for p in phases:
            cells = []
            for t in techs:
                d = data.get((f"technique/{prec}", t, p))
                cells.append(f"{d['mean']:.1f} [{d['lo']:.1f}, {d['hi']:.1f}]" if d else "—")
            ph = data.get((f"phase/{prec}", p, None))
            o = data.get((f"technique/{prec}", "omnee", p))
            e = data.get((f"technique/{prec}", "equiangular", p))
            ratio = f"{o['mean'] / e['mean']:.2f}" if o and e else "—"
            alone = f"{ph['mean']:.1f}" if ph else "—"
            print(f"| {p} | " + " | ".join(cells) + f" | {alone} | {ratio} |")
        c = data.get((f"connection/{prec}", "omnee-hg0.9", None))
        if c:
            print(f"\nNew connection per sample (Connection::new + OMNEE hg0.9 sample + pdf): "
                  f"{c['mean']:.1f} ns [{c['lo']:.1f}, {c['hi']:.1f}].")


if __name__ == "__main__":
    main()
