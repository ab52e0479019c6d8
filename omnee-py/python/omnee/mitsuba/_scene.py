"""What a scene offers the once-more strategies: its media with the omnee
phase function of each, and its finite emitters with the distribution the
integrator draws the light-side point ``x0`` from.

OMNEE and equiangular sampling need a point ``x0`` on a light (point, spot,
area emitters; environment and directional emitters have none) and a
medium whose phase function omnee can sample and that asks for emitter
sampling (Mitsuba's ``sample_emitters``). A scene with neither is rendered
by Mitsuba's own ``volpath``: the strategies would never fire.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, List, Optional

import drjit as dr
import mitsuba as mi

import omnee

from ._phase import Unsupported, omnee_phase


@dataclass
class Group:
    """A medium whose vertices the once-more strategies serve."""

    medium: Any
    """The Mitsuba medium."""
    phase: omnee.Phase
    """Its phase function as omnee samples it."""


@dataclass
class SceneInfo:
    """The scene as the integrator's strategies see it."""

    groups: List[Group] = field(default_factory=list)
    """Media served by OMNEE and equiangular sampling; a lane's group is its
    index here (``len(groups)``: none)."""
    lights: List[Any] = field(default_factory=list)
    """The finite emitters (a position to connect to)."""
    light_weights: List[float] = field(default_factory=list)
    """Their sampling weights (Mitsuba's ``sampling_weight``)."""
    all_weights: float = 0.0
    """The sum of every emitter's sampling weight: Mitsuba's next event
    estimation picks emitter ``e`` with ``w_e / all_weights``."""
    lights_ptr: Optional[Any] = None
    """``mi.EmitterPtr`` over ``lights``."""
    light_distribution: Optional[Any] = None
    """``mi.DiscreteDistribution`` over ``light_weights``."""
    surface_lights: bool = False
    """Whether any finite emitter is a surface (one a ray can hit)."""
    chromatic: bool = False
    """Whether some medium's extinction differs between the spectrum's
    channels (then ``volpathmis``, not ``volpath``, renders a scene the
    strategies cannot serve)."""
    omnee: bool = True
    """Whether OMNEE runs (the integrator's ``omnee`` parameter)."""
    equiangular: bool = True
    """Whether equiangular sampling runs (``equiangular``)."""

    @property
    def enabled(self) -> bool:
        """Whether any strategy beyond volpath's can fire."""
        return bool(self.groups) and bool(self.lights) and (self.omnee or self.equiangular)

    def group_of(self, medium: Any) -> Any:
        """The group index of each lane's medium (``mi.MediumPtr``), as
        ``mi.UInt32``; ``len(groups)`` where it has none."""
        none = len(self.groups)
        g = dr.full(mi.UInt32, none, dr.width(medium))
        for i, grp in enumerate(self.groups):
            g[medium == mi.MediumPtr(grp.medium)] = i
        return g


def _media(scene: Any) -> List[Any]:
    """Every medium of the scene, once: shape interiors and exteriors, and
    the sensors' media."""
    found: List[Any] = []

    def add(m: Any) -> None:
        if m is not None and not any(m is x for x in found):
            found.append(m)

    for shape in scene.shapes():
        add(shape.interior_medium())
        add(shape.exterior_medium())
    for sensor in scene.sensors():
        add(sensor.get_medium())
    return found


def _is_finite(emitter: Any) -> bool:
    """A light with a position to connect to: a delta position (point, spot,
    projector) or a surface; not an environment or a direction."""
    flags = emitter.flags()
    finite = mi.has_flag(flags, mi.EmitterFlags.DeltaPosition) or mi.has_flag(
        flags, mi.EmitterFlags.Surface
    )
    return finite and not mi.has_flag(flags, mi.EmitterFlags.Infinite)


def _chromatic(medium: Any) -> bool:
    """Whether the majorant of ``medium`` differs between channels, probed
    at the centre of the scene's unit cube with the variant's sample
    wavelengths (a grid's majorant is its maximum)."""
    mei = dr.zeros(mi.MediumInteraction3f, 1)
    if mi.is_spectral:
        mei.wavelengths = mi.Spectrum([450.0], [520.0], [600.0], [680.0])
    majorant = mi.UnpolarizedSpectrum(medium.get_majorant(mei))
    values = [float(dr.ravel(majorant[i])[0]) for i in range(len(majorant))] if dr.size_v(majorant) != 1 else []
    return len(set(values)) > 1


def analyse(scene: Any, omnee: bool = True, equiangular: bool = True) -> SceneInfo:
    """The :class:`SceneInfo` of ``scene`` for the strategies asked for;
    warns once per medium whose phase function omnee cannot represent (that
    medium keeps volpath's strategies)."""
    info = SceneInfo(omnee=omnee, equiangular=equiangular)
    for medium in _media(scene):
        info.chromatic |= _chromatic(medium)
        if not medium.use_emitter_sampling():
            continue
        try:
            phase = omnee_phase(medium.phase_function())
        except Unsupported as e:
            warnings.warn(
                f"omnee_volpath: the phase function of medium {medium.id() or '(unnamed)'} "
                f"has no omnee equivalent ({e}); that medium keeps volpath's strategies only",
                RuntimeWarning,
                stacklevel=3,
            )
            continue
        info.groups.append(Group(medium, phase))
    emitters = scene.emitters()
    info.all_weights = float(sum(emitter.sampling_weight() for emitter in emitters))
    for emitter in emitters:
        if _is_finite(emitter) and emitter.sampling_weight() > 0.0:
            info.lights.append(emitter)
            info.light_weights.append(float(emitter.sampling_weight()))
            info.surface_lights |= mi.has_flag(emitter.flags(), mi.EmitterFlags.Surface)
    if info.lights:
        info.lights_ptr = mi.EmitterPtr(info.lights)
        info.light_distribution = mi.DiscreteDistribution(info.light_weights)
    return info
