"""omnee_volpath against Mitsuba's volpath at equal time, whole images, in
one process, back to back.

    python benches/mitsuba/equal_time.py [--seeds 5] [--res 64] [--figure PNG]

Efficiency is 1 / (mean per-pixel relative variance × CPU time per
sample): the relative variance of a pixel is its per-sample variance (from
Mitsuba's ``moment`` integrator) over the square of the reference's value,
averaged over the pixels whose reference is above 10⁻³ of the image's
mean; CPU time is the process's (both Dr.Jit threads), per camera sample.
volpath's variance is heavy-tailed here (a point light in forward-peaked
fog: its next event estimation has infinite variance), so each integrator
runs ``--seeds`` times and the table gives the median and the range. The
reference is omnee_volpath with ``--reference-spp`` samples per pixel.

Scenes: ``fog`` (examples/mitsuba/fog.xml: a point light inside fog with
g = 0.9) and ``sky`` (the test scene ``envmap_iso``: isotropic fog under an
environment map and no finite light, where OMNEE cannot help).

With ``--figure PNG``: volpath and omnee_volpath of the fog scene at equal
CPU time and the reference, side by side.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENES = {
    "fog": os.path.join(ROOT, "examples", "mitsuba", "fog.xml"),
    "sky": os.path.join(ROOT, "omnee-py", "tests-mitsuba", "scenes", "test_envmap_iso_volpath.xml"),
}


def render(mi, dr, scene_file, integrator, spp, seed, res):
    """(mean, per-sample variance, CPU seconds) of one render."""
    scene = mi.load_file(scene_file, res=res, integrator=integrator)
    moment = mi.load_dict({"type": "moment", "nested": {"type": integrator, "max_depth": 6}})
    mi.render(scene, integrator=moment, spp=1, seed=seed + 10_000)  # compiles the kernels
    dr.sync_thread()
    start = time.process_time()
    mi.render(scene, integrator=moment, spp=spp, seed=seed)
    dr.sync_thread()
    cpu = time.process_time() - start
    named = dict(scene.sensors()[0].film().bitmap(raw=False).split())
    mean = np.array(named["nested"], copy=True).astype(np.float64)
    m2 = np.array(named["m2_nested"], copy=True).astype(np.float64)
    return mean, np.maximum(m2 - mean * mean, 0.0), cpu


def efficiency(variance, reference, cpu, spp):
    """(mean relative variance per sample, CPU time per sample, efficiency)."""
    luminance = reference[..., 1]
    mask = luminance > 1e-3 * luminance.mean()
    relvar = float(np.mean(variance[..., 1][mask] / luminance[mask] ** 2))
    per_sample = cpu / (spp * luminance.size)
    return relvar, per_sample, 1.0 / (relvar * per_sample)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--res", type=int, default=64)
    parser.add_argument("--volpath-spp", type=int, default=1024)
    parser.add_argument("--omnee-spp", type=int, default=128)
    parser.add_argument("--reference-spp", type=int, default=8192)
    parser.add_argument("--scenes", default="fog,sky")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--figure")
    parser.add_argument("--json")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import omnee.mitsuba  # noqa: F401

    rows, report = [], {}
    for name in args.scenes.split(","):
        scene_file = SCENES[name]
        reference, _, _ = render(mi, dr, scene_file, "omnee_volpath", args.reference_spp, 99_999, args.res)
        result = {}
        for integrator, spp in (("volpath", args.volpath_spp), ("omnee_volpath", args.omnee_spp)):
            runs = []
            for seed in range(args.seeds):
                _, variance, cpu = render(mi, dr, scene_file, integrator, spp, seed, args.res)
                runs.append(efficiency(variance, reference, cpu, spp))
                print(f"{name} {integrator} seed {seed}: relvar {runs[-1][0]:.4g}, "
                      f"{runs[-1][1] * 1e6:.3g} us/sample, efficiency {runs[-1][2]:.4g}", file=sys.stderr)
            result[integrator] = runs
        v = np.array([r[2] for r in result["volpath"]])
        o = np.array([r[2] for r in result["omnee_volpath"]])
        ratio = float(np.median(o) / np.median(v))
        report[name] = {k: [list(r) for r in runs] for k, runs in result.items()}
        report[name]["ratio_median"] = ratio
        report[name]["ratio_range"] = [float(o.min() / v.max()), float(o.max() / v.min())]
        for integrator, runs in result.items():
            rv = np.array([r[0] for r in runs])
            ts = np.array([r[1] for r in runs]) * 1e6
            ef = np.array([r[2] for r in runs])
            rows.append(f"| {name} | {integrator} | {np.median(rv):.3g} [{rv.min():.3g}, {rv.max():.3g}] "
                        f"| {np.median(ts):.3g} [{ts.min():.3g}, {ts.max():.3g}] "
                        f"| {np.median(ef):.3g} [{ef.min():.3g}, {ef.max():.3g}] |")
        rows.append(f"| {name} | **omnee_volpath / volpath** | | | **{ratio:.3g}×** "
                    f"[{report[name]['ratio_range'][0]:.3g}, {report[name]['ratio_range'][1]:.3g}] |")
        if args.figure and name == "fog":
            # Equal CPU time: volpath gets the samples omnee_volpath's time buys it.
            t_v = np.median([r[1] for r in result["volpath"]])
            t_o = np.median([r[1] for r in result["omnee_volpath"]])
            spp_v = max(1, int(round(args.omnee_spp * t_o / t_v)))
            a, _, _ = render(mi, dr, scene_file, "volpath", spp_v, 7, args.res * 2)
            b, _, _ = render(mi, dr, scene_file, "omnee_volpath", args.omnee_spp, 7, args.res * 2)
            c, _, _ = render(mi, dr, scene_file, "omnee_volpath", args.reference_spp // 4, 77_777, args.res * 2)
            panels = [mi.Bitmap(x.astype(np.float32), mi.Bitmap.PixelFormat.XYZ).convert(
                mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False) for x in (a, b, c)]
            strip = np.concatenate([np.array(p) for p in panels], axis=1)
            mi.util.write_bitmap(args.figure, strip)
            report[name]["figure_spp"] = {"volpath": spp_v, "omnee_volpath": args.omnee_spp}
            print(f"{args.figure}: volpath {spp_v} spp, omnee_volpath {args.omnee_spp} spp, "
                  f"reference {args.reference_spp // 4} spp", file=sys.stderr)
    print("| scene | integrator | relative variance per sample | CPU µs per sample | efficiency |")
    print("|---|---|---:|---:|---:|")
    print("\n".join(rows))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
