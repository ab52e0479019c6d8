"""Mitsuba 3's render test (:mod:`rendertest`) of ``omnee_volpath`` on the
scenes of ``scenes/`` against their volpath references, and on Mitsuba's
own participating-media test scenes where ``OMNEE_MITSUBA_DATA`` names a
checkout of mitsuba-data's ``tests/scenes/participating_media`` (that data
carries no licence of its own, so it is not copied here).

``OMNEE_MITSUBA_SCENES`` (comma-separated names, e.g.
``fog_point_hg90,grid_point``) restricts the run to those scenes; CI runs a
pinned few. Each test renders 2·10⁶ samples."""

import os

import pytest

import rendertest
from conftest import VARIANT

HERE = os.path.dirname(os.path.abspath(__file__))


def chosen(files):
    only = os.environ.get("OMNEE_MITSUBA_SCENES")
    if not only:
        return files
    names = [n.strip() for n in only.split(",") if n.strip()]
    picked = [f for f in files if any(f"test_{n}_" in os.path.basename(f) for n in names)]
    missing = [n for n in names if not any(f"test_{n}_" in os.path.basename(f) for f in files)]
    if missing and not os.environ.get("OMNEE_MITSUBA_DATA"):
        raise RuntimeError(f"OMNEE_MITSUBA_SCENES names scenes that do not exist: {missing}")
    return picked


OURS = chosen(rendertest.scenes(os.path.join(HERE, "scenes")))
MITSUBAS = chosen(rendertest.scenes(os.environ["OMNEE_MITSUBA_DATA"])) if os.environ.get("OMNEE_MITSUBA_DATA") else []


def check(mi, scene_file):
    import numpy as np

    outcome = rendertest.run(scene_file, "omnee_volpath", VARIANT)
    ratio = outcome.variance_ratio[np.isfinite(outcome.variance_ratio)]
    print(f"{os.path.basename(scene_file)}: {outcome.fraction:.4%} of pixels above the level "
          f"{outcome.level:.2e} (min p {outcome.min_p:.2e}), {outcome.spp} spp, {outcome.seconds:.1f} s; "
          f"variance / the reference's: median {np.median(ratio):.3g}, "
          f"99th percentile {np.percentile(ratio, 99):.3g}, max {ratio.max():.3g}")
    assert outcome.accepted, (
        f"{os.path.basename(scene_file)}: {outcome.fraction:.4%} of the pixels pass; "
        f"allowed: at least {rendertest.PIXEL_FRACTION:.2%}"
    )


@pytest.mark.parametrize("scene_file", OURS, ids=lambda f: os.path.basename(f)[5:-12])
def test_our_scenes_against_volpath_references(mi, scene_file):
    check(mi, scene_file)


@pytest.mark.parametrize("scene_file", MITSUBAS, ids=lambda f: os.path.basename(f)[5:-4])
def test_mitsubas_own_scenes(mi, scene_file):
    check(mi, scene_file)
