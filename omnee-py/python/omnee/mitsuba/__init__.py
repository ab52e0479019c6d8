"""OMNEE inside Mitsuba 3: the integrator ``omnee_volpath``.

>>> import mitsuba as mi
>>> mi.set_variant("llvm_ad_rgb")
>>> import omnee.mitsuba                      # registers "omnee_volpath"
>>> scene = mi.load_file("scene.xml", integrator="omnee_volpath")  # doctest: +SKIP
>>> image = mi.render(scene, spp=64, seed=1)                       # doctest: +SKIP

``omnee_volpath`` is Mitsuba's volumetric path tracer ``volpath`` (the same
parameters ``max_depth``, ``rr_depth``, ``hide_emitters`` with the same
meanings and defaults) with two more ways to reach a finite light (point,
spot, area emitters) from a medium vertex: **OMNEE**, once-more scattered
next event estimation, at every surface and medium vertex, whose vertex
``x1`` the omnee core draws angle first; and **equiangular sampling** along
every ray segment in a medium. All strategies that can make a path are
combined by multiple importance sampling (power heuristic), so the image
converges to volpath's. A scene without a finite light, or without a medium
whose phase function omnee can sample (isotropic, hg, rayleigh, tabphase,
blendphase of two hg lobes), is rendered by volpath itself.

Importing the module registers the integrator in the current variant; after
``mi.set_variant(...)`` to another one, call :func:`register` again. It runs
in the JIT variants (``llvm_*``, ``cuda_*``), unpolarized.
"""

from __future__ import annotations

from typing import Any, Optional

import drjit as dr
import mitsuba as mi

from ._integrator import make_class

__all__ = ["register", "NAME"]

NAME = "omnee_volpath"
"""The integrator's name in scene files and dictionaries."""


def _check_variant(variant: Optional[str]) -> None:
    if variant is None:
        raise RuntimeError(
            "omnee_volpath: no Mitsuba variant is set; call mi.set_variant('llvm_ad_rgb') "
            "(or another llvm_* or cuda_* variant) before registering the integrator"
        )
    if not ("llvm" in variant or "cuda" in variant):
        raise RuntimeError(
            f"omnee_volpath: the variant {variant!r} is not supported; allowed: a JIT variant "
            "(llvm_* or cuda_*): the integrator runs a wavefront through the omnee core"
        )
    if "polarized" in variant:
        raise RuntimeError(
            f"omnee_volpath: the variant {variant!r} is not supported; allowed: an unpolarized "
            "llvm_* or cuda_* variant"
        )


def register() -> None:
    """Registers ``omnee_volpath`` in the current Mitsuba variant; raises
    ``RuntimeError`` naming the variant if it is not an unpolarized JIT one."""
    variant = mi.variant()
    _check_variant(variant)
    cls = make_class()
    mi.register_integrator(NAME, lambda props: cls(props))


def _register_on_import() -> None:
    """On import: the current variant gets the integrator; a variant that
    cannot run it gets a factory that raises the reason when a scene asks
    for ``omnee_volpath``."""
    variant = mi.variant()
    try:
        _check_variant(variant)
    except RuntimeError as e:
        if variant is None:
            return
        message = str(e)

        def refuse(props: Any) -> Any:
            raise RuntimeError(message)

        mi.register_integrator(NAME, refuse)
        return
    register()


_register_on_import()
del dr
