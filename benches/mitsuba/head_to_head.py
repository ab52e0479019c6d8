#!/usr/bin/env python3
"""Head-to-head: Mitsuba 3's `volpath` against `omnee probe` on the once-more
(single-scattered) irradiance at a floor point under a slab of fog lit by a
small sphere light, at equal CPU time, one thread each.

Run it with `bash benches/mitsuba/run.sh` (installs Mitsuba and builds the
`omnee` binary); see benches/mitsuba/README.md for what is computed and why
both sides compute the same quantity.

Each configuration (phase g × light inside/above the slab):
- omnee: `omnee probe --terms once-more --technique T --threads 1` with the
  sample count that fills the budget (from a calibration run); mean and
  standard error from its per-sample moments; CPU seconds from getrusage of
  the child process.
- Mitsuba: `volpath` with max_depth = 2, hide_emitters, no Russian roulette,
  into an `irradiancemeter` on a 1 mm disk at the point; K independent renders
  (seeds 0..K−1) that together fill the budget; mean and standard error over
  the K render means; CPU seconds from time.process_time of this process.
- efficiency = 1 / (stderr² · CPU seconds), independent of the budget;
  z = (omnee − Mitsuba) / √(se_o² + se_m²), the disagreement in standard errors.

`--point-light` replaces the sphere by a point light of the same intensity
(I = π R² L) on both sides and adds the reference value of quadrature.py
(numpy and scipy, independent of both renderers), with each side's
disagreement from it in its own standard errors.
"""

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

# The default scene's medium and light (`omnee default-scene`), no occluder.
SIGMA_S, SIGMA_A = 0.5, 0.05
Z_MIN, Z_MAX = 0.0, 1.0
LIGHT_RADIUS, RADIANCE = 0.01, 10000.0
# The light's centre: the default scene's (inside the slab) and 0.5 m above it.
LIGHTS = {"inside": (0.0, 0.0, 0.95), "above": (0.0, 0.0, 1.5)}
# The receiver: a floor point 1 mm below the slab (so that Mitsuba's meter
# does not sit on the slab's boundary), normal +z.
POINT = (0.25, 0.0, -0.001)
METER_RADIUS = 1e-3
G_VALUES = (0.0, 0.5, 0.9, 0.98)


# The point light of `--point-light`: the sphere's intensity π R² L.
INTENSITY = np.pi * LIGHT_RADIUS**2 * RADIANCE


def scene_toml(g, light, point_light=False):
    """The omnee scene: the default scene's slab and light, the floor at the
    point's height, no occluder."""
    if point_light:
        emitter = f"radius = 0.0\nintensity = {INTENSITY!r}"
    else:
        emitter = f"radius = {LIGHT_RADIUS}\nradiance = {RADIANCE}"
    return f"""[medium]
sigma_s = {SIGMA_S}
sigma_a = {SIGMA_A}
phase = "hg:{g}"
z_min = {Z_MIN}
z_max = {Z_MAX}
[floor]
z = {POINT[2]}
[light]
center = [{light[0]}, {light[1]}, {light[2]}]
{emitter}
[camera]
position = [0.0, -1.1, 2.2]
"""


def mitsuba_scene(mi, g, light, spp, point_light=False):
    """The same scene for Mitsuba: a homogeneous medium inside a 200 m × 200 m
    box z ∈ [0, 1] with an index-matched (null) boundary, the sphere light
    (inside the medium when its centre is), and an irradiance meter on a
    1 mm disk facing +z at the point."""
    T = mi.ScalarTransform4f
    sigma_t = SIGMA_S + SIGMA_A
    sphere = {
        "type": "sphere",
        "center": list(light),
        "radius": LIGHT_RADIUS,
        "emitter": {"type": "area", "radiance": {"type": "rgb", "value": RADIANCE}},
    }
    if Z_MIN < light[2] < Z_MAX:
        sphere["exterior"] = {"type": "ref", "id": "fog"}
    if point_light:
        sphere = {"type": "point", "position": list(light), "intensity": {"type": "rgb", "value": INTENSITY}}
    return mi.load_dict({
        "type": "scene",
        # Depth 1 is the light seen directly (hidden), depth 2 one scattering
        # vertex with next event estimation: exactly the once-more term.
        "integrator": {"type": "volpath", "max_depth": 2, "rr_depth": 1 << 30, "hide_emitters": True},
        "fog": {"type": "homogeneous", "sigma_t": sigma_t, "albedo": SIGMA_S / sigma_t,
                "phase": {"type": "hg", "g": g}},
        "slab": {
            "type": "cube",
            "to_world": T().translate([0, 0, 0.5 * (Z_MIN + Z_MAX)]).scale([100, 100, 0.5 * (Z_MAX - Z_MIN)]),
            "bsdf": {"type": "null"},
            "interior": {"type": "ref", "id": "fog"},
        },
        "light": sphere,
        "meter": {
            "type": "disk",
            "to_world": T().translate(list(POINT)).scale(METER_RADIUS),
            "sensor": {
                "type": "irradiancemeter",
                "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"},
                         "pixel_format": "rgb"},
                "sampler": {"type": "independent", "sample_count": spp},
            },
        },
    })


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_omnee(binary, scene, technique, samples, seed):
    args = [binary, "probe", "--scene", scene, "--point", ",".join(map(str, POINT)), "--normal", "0,0,1",
            "--terms", "once-more", "--technique", technique, "--samples", str(samples), "--seed", str(seed),
            "--threads", "1", "--json"]
    c0, w0 = child_cpu(), time.perf_counter()
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    cpu, wall = child_cpu() - c0, time.perf_counter() - w0
    v = json.loads(out)
    return dict(mean=v["mean"], stderr=v["stderr"], samples=samples, cpu=cpu, wall=wall,
                technique=v["technique"])


def omnee_side(binary, scene, technique, seconds):
    calib = run_omnee(binary, scene, technique, 200_000, seed=999)
    samples = max(200_000, int(200_000 * seconds / max(calib["cpu"], 1e-3)))
    return run_omnee(binary, scene, technique, samples, seed=1)


def render(mi, scene, spp, seed):
    return float(np.array(mi.render(scene, spp=spp, seed=seed))[0, 0, 0])


def mitsuba_side(mi, g, light, seconds, renders, point_light):
    scene = mitsuba_scene(mi, g, light, 1, point_light)
    render(mi, scene, 256, seed=10_000)  # warm-up (compiles kernels on the LLVM variant)
    c0 = time.process_time()
    render(mi, scene, 4096, seed=10_001)
    per_sample = max(time.process_time() - c0, 1e-4) / 4096
    spp = max(64, int(seconds / renders / per_sample))
    values = []
    c0, w0 = time.process_time(), time.perf_counter()
    for k in range(renders):
        values.append(render(mi, scene, spp, seed=k))
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    values = np.array(values)
    return dict(mean=float(values.mean()), stderr=float(values.std(ddof=1) / np.sqrt(renders)),
                samples=spp * renders, cpu=cpu, wall=wall, renders=renders)


def efficiency(side):
    return 1.0 / (side["stderr"] ** 2 * side["cpu"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--omnee", required=True, help="the omnee binary (release build)")
    ap.add_argument("--seconds", type=float, default=4.0, help="CPU seconds per side and configuration")
    ap.add_argument("--renders", type=int, default=32, help="independent Mitsuba renders per configuration")
    ap.add_argument("--variant", default="scalar_rgb", help="Mitsuba variant: scalar_rgb or llvm_ad_rgb")
    ap.add_argument("--technique", default="auto", help="omnee probe --technique")
    ap.add_argument("--g", type=float, nargs="*", default=list(G_VALUES))
    ap.add_argument("--lights", nargs="*", default=list(LIGHTS))
    ap.add_argument("--point-light", action="store_true",
                    help="a point light of the sphere's intensity, with the quadrature reference")
    ap.add_argument("--json", help="also write the rows as JSON lines to this file")
    a = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(a.variant)
    dr.set_thread_count(1)
    load = os.getloadavg()
    print(f"# Mitsuba {mi.__version__} ({a.variant}), Dr.Jit {dr.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} cores, load average {load[0]:.1f} at start; {a.seconds} CPU s per side, "
          f"one thread each, {a.renders} Mitsuba renders", flush=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for where in a.lights:
            light = LIGHTS[where]
            for g in a.g:
                scene = os.path.join(tmp, f"scene-{where}-{g}.toml")
                with open(scene, "w") as f:
                    f.write(scene_toml(g, light, a.point_light))
                o = omnee_side(a.omnee, scene, a.technique, a.seconds)
                m = mitsuba_side(mi, g, light, a.seconds, a.renders, a.point_light)
                z = (o["mean"] - m["mean"]) / np.hypot(o["stderr"], m["stderr"])
                row = dict(light=where, g=g, omnee=o, mitsuba=m, z=z,
                           ratio=efficiency(o) / efficiency(m))
                if a.point_light:
                    from quadrature import once_more_irradiance

                    ref = once_more_irradiance(light, POINT, INTENSITY, SIGMA_S, SIGMA_S + SIGMA_A, g, Z_MIN, Z_MAX)
                    row.update(reference=ref, z_omnee=(o["mean"] - ref) / o["stderr"],
                               z_mitsuba=(m["mean"] - ref) / m["stderr"])
                rows.append(row)
                print(json.dumps(row), file=sys.stderr, flush=True)
    print(f"# load average {os.getloadavg()[0]:.1f} at the end; "
          f"{'point light, I = pi R^2 L' if a.point_light else 'sphere light'}\n")
    print("| light | g | omnee (technique) mean ± se | Mitsuba volpath mean ± se | z | omnee CPU s, samples | "
          "Mitsuba CPU s, samples | efficiency omnee / Mitsuba |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        o, m = r["omnee"], r["mitsuba"]
        print(f"| {r['light']} | {r['g']} | {o['mean']:.5g} ± {o['stderr']:.2g} ({o['technique']}) | "
              f"{m['mean']:.5g} ± {m['stderr']:.2g} | {r['z']:+.1f} | {o['cpu']:.2f}, {o['samples']:.3g} | "
              f"{m['cpu']:.2f}, {m['samples']:.3g} | {r['ratio']:.3g} |")
    if a.point_light:
        print("\n| light | g | quadrature | omnee − quadrature (in se) | Mitsuba − quadrature (in se) |")
        print("|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['light']} | {r['g']} | {r['reference']:.6g} | {r['z_omnee']:+.1f} | {r['z_mitsuba']:+.1f} |")
    if a.json:
        with open(a.json, "w") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
