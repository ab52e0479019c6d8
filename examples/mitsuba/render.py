"""Renders examples/mitsuba/fog.xml with ``omnee_volpath`` (any Mitsuba
scene works the same way) and writes ``fog.exr`` in the current folder:

    python examples/mitsuba/render.py [integrator] [spp]

``integrator`` is ``omnee_volpath`` (the default) or ``volpath``."""

import os
import sys

import mitsuba as mi

mi.set_variant("llvm_ad_rgb")  # or cuda_ad_rgb, llvm_ad_spectral, ...
import omnee.mitsuba  # noqa: E402,F401  (registers the integrator "omnee_volpath")

integrator = sys.argv[1] if len(sys.argv) > 1 else "omnee_volpath"
spp = int(sys.argv[2]) if len(sys.argv) > 2 else 64
scene = mi.load_file(os.path.join(os.path.dirname(__file__), "fog.xml"), integrator=integrator)
mi.Bitmap(mi.render(scene, spp=spp, seed=0)).write("fog.exr")
print(f"fog.exr: {integrator}, {spp} samples per pixel")
