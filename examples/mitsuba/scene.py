"""The fog scene of the example, once for Mitsuba and once as the numbers the
OMNEE side needs.

omnee's default scene, made for a camera that sees no fog: a slab of fog
(a homogeneous medium with a forward-peaked Henyey–Greenstein phase
function, 0 ≤ z ≤ 1 m, 60 m wide), a point light in it near its top
(`inside`, z = 0.95 m) or half a metre above it (`above`), and in the fog a
black plate at z = 0.5 m with a 3 × 3 lattice of square holes. Under the
slab, 1 mm below it, lies a translucent screen (a diffuse transmitter, like
frosted glass), and the camera looks at the screen from below, in the clear
air: every camera ray hits the screen before it could reach the fog.

Light reaches a screen point `x2` directly (sharp spots through the holes,
attenuated by the fog) or once more: it scatters once at a point `x1` of the
fog on its way, which blurs the spots into a halo and lights the whole
shadow of the plate. Mitsuba's `volpath` with `max_depth = 3` computes
exactly these two terms here (README.md says why).
"""

from typing import Dict, List, Tuple

import numpy as np

Vec3 = Tuple[float, float, float]
Rect = Tuple[Tuple[float, float], Tuple[float, float]]

# The fog: a box with a null (index-matched) boundary, homogeneous inside.
FOG_LO: Vec3 = (-30.0, -30.0, 0.0)
FOG_HI: Vec3 = (30.0, 30.0, 1.0)
SIGMA_S, SIGMA_A = 0.5, 0.05  # 1/m, as omnee's default scene
G = 0.9  # Henyey–Greenstein g; g > 0 scatters forward in Mitsuba and omnee alike

# A point light of intensity I (W/sr), inside the fog or above it.
LIGHTS: Dict[str, Vec3] = {"inside": (0.0, 0.0, 0.95), "above": (0.0, 0.0, 1.5)}
INTENSITY = 1.0

# The screen: a diffuse transmitter (the plugin of screen_bsdf.py: Mitsuba
# 3.9.1 has none), 1 mm under the fog so that it does not share a plane
# with the fog's boundary.
SCREEN_Z = -0.001
SCREEN_TRANSMITTANCE = 0.5

# The plate: black, at z = 0.5, 0.6 m square, holes of side 0.08 m on a
# 0.2 m lattice centred under the light.
PLATE_Z = 0.5
PLATE_HALF = 0.3
HOLE_CENTERS = (-0.2, 0.0, 0.2)
HOLE_HALF = 0.04

# The camera, 2 m under the screen, looking straight up at it.
CAMERA_ORIGIN: Vec3 = (0.0, 0.0, -2.0)
FOV_Y = 50.0  # degrees, vertical


def fog():
    """The fog of this scene for the OMNEE side (an `omnee_mitsuba.Fog`)."""
    from omnee_mitsuba import Fog

    return Fog(np.array(FOG_LO), np.array(FOG_HI), SIGMA_S, SIGMA_S + SIGMA_A, f"hg:{G}")


def plate_rectangles() -> List[Rect]:
    """The plate as rectangles `((x_min, x_max), (y_min, y_max))` that tile
    its square around the holes: full-width strips between the rows of
    holes, and in each row's band the pieces between its holes."""
    edges = [-PLATE_HALF] + [e for c in HOLE_CENTERS for e in (c - HOLE_HALF, c + HOLE_HALF)] + [PLATE_HALF]
    gaps = [(edges[i], edges[i + 1]) for i in range(0, len(edges), 2)]  # solid intervals along one axis
    bands = [(edges[i], edges[i + 1]) for i in range(1, len(edges) - 1, 2)]  # the rows of holes
    return [((-PLATE_HALF, PLATE_HALF), y) for y in gaps] + [(x, y) for y in bands for x in gaps]


def _rectangle(mi, x: Tuple[float, float], y: Tuple[float, float], z: float, bsdf: dict) -> dict:
    """An axis-aligned rectangle at height z (Mitsuba's `rectangle` is
    [−1, 1]² in the plane z = 0)."""
    T = mi.ScalarTransform4f
    center = [0.5 * (x[0] + x[1]), 0.5 * (y[0] + y[1]), z]
    return {
        "type": "rectangle",
        "to_world": T().translate(center).scale([0.5 * (x[1] - x[0]), 0.5 * (y[1] - y[0]), 1.0]),
        "bsdf": bsdf,
    }


def mitsuba_dict(light: str, width: int, height: int, with_fog: bool = True) -> dict:
    """The scene as a Mitsuba 3 dictionary (for `mi.load_dict`).

    `with_fog=True`: the whole scene with `volpath` (max_depth 3, no Russian
    roulette), for Mitsuba's own render. `with_fog=False`: only the opaque
    shapes, the light and the camera, for the OMNEE side, which asks Mitsuba
    for camera rays, surface hits, BSDF values and shadow rays, and handles
    the fog itself (a `ray_test` would otherwise stop at the fog's boundary).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    black = {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.0}}
    scene = {
        "type": "scene",
        "screen": _rectangle(
            mi, (-30.0, 30.0), (-30.0, 30.0), SCREEN_Z,
            {"type": "screen", "transmittance": SCREEN_TRANSMITTANCE},
        ),
        "light": {"type": "point", "position": list(LIGHTS[light]), "intensity": {"type": "rgb", "value": INTENSITY}},
        "camera": {
            "type": "perspective",
            "fov": FOV_Y,
            "fov_axis": "y",
            "to_world": T().look_at(origin=list(CAMERA_ORIGIN), target=[0.0, 0.0, 0.0], up=[0.0, 1.0, 0.0]),
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                # A box filter: a pixel is the plain mean of the samples in
                # it, as on the OMNEE side.
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
            "sampler": {"type": "independent", "sample_count": 1},
        },
    }
    for k, (x, y) in enumerate(plate_rectangles()):
        scene[f"plate_{k}"] = _rectangle(mi, x, y, PLATE_Z, black)
    if with_fog:
        lo, hi = np.array(FOG_LO), np.array(FOG_HI)
        scene["integrator"] = {
            "type": "volpath",
            # Depth 1: the screen seen by the camera; 2: the direct light at
            # the screen; 3: one scattering vertex in the fog, then the light.
            "max_depth": 3,
            "rr_depth": 1 << 30,  # no Russian roulette
        }
        scene["fog"] = {
            "type": "homogeneous",
            "sigma_t": SIGMA_S + SIGMA_A,
            "albedo": SIGMA_S / (SIGMA_S + SIGMA_A),
            "phase": {"type": "hg", "g": G},
        }
        scene["fog_box"] = {
            "type": "cube",
            "to_world": T().translate(list(0.5 * (lo + hi))).scale(list(0.5 * (hi - lo))),
            "bsdf": {"type": "null"},
            "interior": {"type": "ref", "id": "fog"},
        }
    return scene
