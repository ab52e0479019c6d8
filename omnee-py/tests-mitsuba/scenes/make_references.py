"""Renders the reference images of the test scenes with Mitsuba's
``volpath``, in the form Mitsuba's own render test reads: for
``test_<name>_volpath.xml``, ``refs/test_<name>_ref_<mode>.exr`` (the mean)
and ``..._var.exr`` (the per-sample variance), RGB, converted from the XYZ
moments of the ``moment`` integrator.

    python make_references.py [--spp N] [--passes P] [--variant V] [scene.xml ...]

Each pass renders N samples per pixel with its own seed (from 10⁶ up, away
from the test's seed 0); the mean and the second moment are averaged over
the passes. The defaults (64 passes of 2048) give the reference 64 times the
samples of a test image, so its own error adds about 1/8 of a test image's
standard deviation. Several hours of CPU for all scenes on two cores.
"""

import argparse
import glob
import os
import time

import mitsuba as mi
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def moments(scene_file: str, spp: int, seed: int):
    scene = mi.load_file(scene_file, integrator="volpath")
    mi.render(scene, spp=spp, seed=seed)
    layers = scene.sensors()[0].film().bitmap(raw=False).split()
    mean = np.array(layers[1][1], copy=True).astype(np.float64)
    m2 = np.array(layers[2][1], copy=True).astype(np.float64)
    return mean, m2


def xyz_to_rgb(image: np.ndarray):
    bitmap = mi.Bitmap(image.astype(np.float32), mi.Bitmap.PixelFormat.XYZ)
    return bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spp", type=int, default=2048)
    parser.add_argument("--passes", type=int, default=64)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("scenes", nargs="*")
    args = parser.parse_args()
    mi.set_variant(args.variant)
    mode = next(m for m in ("mono", "rgb", "spectral") if m in args.variant)
    files = args.scenes or sorted(glob.glob(os.path.join(HERE, "test_*_volpath.xml")))
    os.makedirs(os.path.join(HERE, "refs"), exist_ok=True)
    for f in files:
        start = time.time()
        mean = m2 = None
        for p in range(args.passes):
            a, b = moments(f, args.spp, 1_000_000 + p)
            mean = a if mean is None else mean + a
            m2 = b if m2 is None else m2 + b
        mean /= args.passes
        m2 /= args.passes
        variance = np.maximum(m2 - mean * mean, 0.0)
        stem = os.path.splitext(os.path.basename(f))[0].rsplit("_", 1)[0]
        out = os.path.join(HERE, "refs", f"{stem}_ref_{mode}")
        xyz_to_rgb(mean).write(out + ".exr")
        xyz_to_rgb(variance).write(out + "_var.exr")
        print(f"{os.path.basename(f)}: {args.passes} x {args.spp} spp in {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
