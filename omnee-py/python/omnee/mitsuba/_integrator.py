"""The ``omnee_volpath`` integrator: Mitsuba's volumetric path tracer with
two more ways to reach a finite light from a medium vertex, all combined by
MIS.

The path tracer is volpath's (free-flight sampling with null collisions and
spectral MIS, next event estimation at surface and medium vertices, BSDF and
phase sampling, Russian roulette, ``max_depth``, ``rr_depth``,
``hide_emitters``), run as a wavefront: one Python iteration per bounce,
over the paths still alive (the others are dropped), so that the omnee core
can draw from numpy arrays in between. At every vertex ``x2`` (surface or
medium) it adds **OMNEE**: a point ``x0`` on a finite light, the vertex
``x1`` between them drawn by the omnee core (angle first, then the
circumcircle arc), and two shadow rays through null interfaces. On the ray
legs where OMNEE does not start (from the camera, a delta surface, a medium
it does not serve) it adds **equiangular sampling** at the start of every
medium segment: ``x0`` first, then the distance along the segment drawn by
the core towards it. Paths ``… x2 → x1 → x0`` that several strategies make
are weighted by the power heuristic over the densities of :mod:`._mis`;
every other path keeps volpath's two-strategy weights.
"""

from __future__ import annotations

from typing import Any, Dict, List, Tuple

import drjit as dr
import mitsuba as mi

from . import _bridge, _lights, _mis, _transport
from ._scene import SceneInfo, analyse
from ._transport import mean_channels

# A wavefront is compacted when fewer than this fraction of its lanes live.
_COMPACT = 0.85

# What BSDFs, emitters and spawned rays read of a surface interaction (no
# derivatives of the normal or of the UVs: no ray differentials here).
_SURFACE_FLAGS = mi.RayFlags.Minimal | mi.RayFlags.UV | mi.RayFlags.dPdUV | mi.RayFlags.ShadingFrame


def index_spectrum(spec: Any, channel: Any) -> Any:
    """Channel ``channel`` of an RGB spectrum (the first otherwise), as
    volpath's hero-channel free flight reads it."""
    m = spec[0]
    if mi.is_rgb:
        m = dr.select(channel == 1, spec[1], m)
        m = dr.select(channel == 2, spec[2], m)
    return m


class Lanes:
    """Per-lane arrays that live together: ``compact(index)`` keeps the
    lanes ``index`` of every field."""

    __slots__: Tuple[str, ...] = ()

    def compact(self, index: Any) -> None:
        for name in self.__slots__:
            value = getattr(self, name)
            setattr(self, name, dr.gather(type(value), value, index))

    def fields(self) -> List[Any]:
        return [getattr(self, name) for name in self.__slots__]


class Leg(Lanes):
    """The ray leg from the last scattering vertex ``x2`` (or the camera),
    as the MIS densities need it."""

    __slots__ = (
        "origin", "direction", "t", "tau", "pdf", "omnee", "group",
        "seg_t0", "seg_t1", "seg_tau0", "seg_eq",
    )

    def __init__(self, ray: Any, n: int, groups: int) -> None:
        self.origin = mi.Point3f(ray.o)
        """``x2``: where the leg starts."""
        self.direction = mi.Vector3f(ray.d)
        """``ω21``: its direction."""
        self.t = dr.zeros(mi.Float, n)
        """Distance from ``origin`` to the current ray's origin."""
        self.tau = dr.zeros(mi.Float, n)
        """Optical-depth proxy from ``origin`` to the current ray's origin."""
        self.pdf = dr.full(mi.Float, 1.0, n)
        """``p_ω``: the density of ``direction`` at ``x2`` (1 for the camera,
        whose factor every strategy shares)."""
        self.omnee = dr.zeros(mi.Bool, n)
        """Whether OMNEE ran at ``origin`` (so it can draw vertices on this leg)."""
        self.group = dr.full(mi.UInt32, groups, n)
        """The group whose phase function OMNEE used at ``origin``."""
        self.seg_t0 = dr.zeros(mi.Float, n)
        """The current medium segment along the leg: its start,"""
        self.seg_t1 = dr.zeros(mi.Float, n)
        """its end,"""
        self.seg_tau0 = dr.zeros(mi.Float, n)
        """the proxy at its start,"""
        self.seg_eq = dr.zeros(mi.Bool, n)
        """and whether equiangular sampling ran on it: on the medium segments
        of legs where OMNEE did not start, so that each once-more vertex has
        one of the two once-more strategies besides volpath's."""

    def restart(self, mask: Any, origin: Any, direction: Any, pdf: Any, omnee: Any, group: Any) -> None:
        """A new leg from a scattering vertex, on the lanes of ``mask``."""
        self.origin[mask] = origin
        self.direction[mask] = direction
        self.t[mask] = 0.0
        self.tau[mask] = 0.0
        self.pdf[mask] = pdf
        self.omnee[mask] = omnee
        self.group[mask] = group
        self.seg_eq[mask] = False


class Vertex(Lanes):
    """A medium vertex ``x1`` with its leg, kept until the next vertex so
    that a phase-sampled ray that hits a surface emitter can weigh itself
    against OMNEE and equiangular sampling (only for scenes with surface
    emitters)."""

    __slots__ = ("valid", "t21", "q_ff") + Leg.__slots__

    def __init__(self, n: int, groups: int) -> None:
        self.valid = dr.zeros(mi.Bool, n)
        self.t21 = dr.zeros(mi.Float, n)
        self.q_ff = dr.zeros(mi.Float, n)
        self.origin = dr.zeros(mi.Point3f, n)
        self.direction = dr.zeros(mi.Vector3f, n)
        self.t = dr.zeros(mi.Float, n)
        self.tau = dr.zeros(mi.Float, n)
        self.pdf = dr.zeros(mi.Float, n)
        self.omnee = dr.zeros(mi.Bool, n)
        self.group = dr.full(mi.UInt32, groups, n)
        self.seg_t0 = dr.zeros(mi.Float, n)
        self.seg_t1 = dr.zeros(mi.Float, n)
        self.seg_tau0 = dr.zeros(mi.Float, n)
        self.seg_eq = dr.zeros(mi.Bool, n)

    def keep(self, mask: Any, leg: Leg, q_ff: Any) -> None:
        """Records the vertex reached on ``leg`` (``leg.t`` from its start)."""
        self.valid[mask] = True
        self.t21[mask] = leg.t
        self.q_ff[mask] = q_ff
        for name in Leg.__slots__:
            getattr(self, name)[mask] = getattr(leg, name)


class Paths(Lanes):
    """The wavefront's live paths: volpath's loop state, and the original
    lane of each (its camera sample)."""

    __slots__ = (
        "lane", "ray", "throughput", "result", "eta", "depth", "medium", "active",
        "valid", "specular", "channel", "needs_intersection", "seg_end",
        "last_p", "last_n", "last_pdf",
    )
    lane: Any
    """The camera sample (lane of the wavefront) each path belongs to."""
    ray: Any
    throughput: Any
    result: Any
    """The radiance the path has gathered so far."""
    eta: Any
    depth: Any
    medium: Any
    active: Any
    valid: Any
    specular: Any
    """volpath's ``specular_chain``: an emitter hit counts in full."""
    channel: Any
    """The hero channel of the free flight (RGB)."""
    needs_intersection: Any
    seg_end: Any
    """The distance from the ray's origin to the next surface (in a medium)."""
    last_p: Any
    """The last scattering vertex and its surface normal (0 in a medium),"""
    last_n: Any
    last_pdf: Any
    """and the density of the direction drawn there."""


class Random:
    """The uniform numbers of the live paths: one PCG32 stream per camera
    sample (its sequence the sample's lane in the wavefront, its state from
    one number of Mitsuba's sampler, so that a render is the same for the
    same seed), compacted with the paths. Mitsuba's sampler itself draws for
    the whole wavefront at every call, whatever is left of it."""

    def __init__(self, sampler: Any, seed: Any, lane: Any) -> None:
        self.sampler = sampler
        """Mitsuba's sampler (for the phase functions' context)."""
        state = mi.UInt64(mi.UInt32(mi.Float(seed) * 4294967040.0))
        self.rng = mi.PCG32(dr.width(lane), state, mi.UInt64(lane))

    def compact(self, index: Any) -> None:
        self.rng.state = dr.gather(mi.UInt64, self.rng.state, index)
        self.rng.inc = dr.gather(mi.UInt64, self.rng.inc, index)

    def next_1d(self) -> Any:
        return self.rng.next_float32()

    def next_2d(self) -> Any:
        return mi.Point2f(self.rng.next_float32(), self.rng.next_float32())

    def fields(self) -> List[Any]:
        return [self.rng.state, self.rng.inc]


class Strategies:
    """The once-more strategies of one wavefront: the scene's groups and
    lights, and what a connection through a medium vertex evaluates."""

    def __init__(self, integrator: Any, info: SceneInfo, scene: Any, random: Random) -> None:
        self.info = info
        self.groups = info.groups
        self.none = len(info.groups)
        self.scene = scene
        self.random = random
        self.mode = integrator.mis

    def sample_light(self, active: Any, time: Any) -> _lights.LightPoint:
        """``x0`` on a finite light, from three uniform numbers."""
        u_emitter = self.random.next_1d()
        u_position = self.random.next_2d()
        return _lights.sample(self.info, u_emitter, u_position, time, active)

    def nee_density(self, it: Any, ds: Any, g0: Any, active: Any) -> Any:
        """Next event estimation's density of ``x0`` (``ds``) from ``it``:
        per area on a surface emitter (``pdf_emitter_direction · g0``), the
        emitter's probability for a delta light."""
        sa = self.scene.pdf_emitter_direction(it, ds, active & ~ds.delta)
        pmf = _lights.nee_pmf(self.info, ds.emitter, active)
        return dr.select(ds.delta, pmf, sa * g0)

    def reach(self, it: Any, medium: Any, target: Any, channel: Any, active: Any) -> Any:
        """The transmittance from the interaction ``it`` (in ``medium``) to
        the point ``target``, through null interfaces: ``(tr, tau, medium at
        the end)``."""
        ray = it.spawn_ray_to(target)
        return _transport.walk(self.scene, self.random.next_1d(), ray, medium, channel, active,
                               length=dr.norm(target - ray.o))

    def light_edge(self, mei1: Any, medium1: Any, x0: _lights.LightPoint, channel: Any, active: Any) -> Any:
        """From a medium vertex ``x1`` to ``x0``: the emission, the scene's
        phase function at ``x1`` (value and density) and the transmittance."""
        em = _lights.emission(mei1, x0, active)
        phase_ctx = mi.PhaseFunctionContext(self.random.sampler)
        phase = medium1.phase_function()
        rho, rho_pdf = phase.eval_pdf(phase_ctx, mei1, em.ds.d, active)
        tr, _, _ = self.reach(mei1, medium1, x0.p, channel, active & (mean_channels(em.value) > 0.0))
        return em, mi.Spectrum(rho), rho_pdf, tr

    def once_more_density(self, x0_pdf: Any, x0p: Any, x1: Any, leg: Any, t21: Any, active: Any) -> Any:
        """The density of the leg's once-more strategy for the path through
        ``x1`` (``t21`` along ``leg``) to ``x0`` (at ``x0p``, density ``x0_pdf``
        under :func:`_lights.sample`): ``q_c`` where OMNEE started the leg,
        ``q_d`` where equiangular sampling ran on ``x1``'s segment, else 0.
        ``leg`` is a :class:`Leg` or a :class:`Vertex`."""
        finite = mi.Bool(active) & (x0_pdf > 0.0)
        by_omnee = finite & leg.omnee & (leg.group < self.none)
        by_eq = finite & leg.seg_eq
        q_c = x0_pdf * _bridge.omnee_pdf(self.groups, leg.group, x0p, leg.origin, x1, by_omnee)
        p_eq = _bridge.equiangular_pdf(x0p, leg.origin, leg.direction, leg.seg_t0, leg.seg_t1, t21, by_eq)
        q_d = x0_pdf * leg.pdf * dr.exp(-leg.seg_tau0) * p_eq / dr.square(t21)
        return dr.select(by_eq, q_d, q_c)

    def weights_split(self, q_a: Any, q_b: Any, q_once: Any, omnee: Any) -> Any:
        """The four weights, ``q_once`` being OMNEE's density where ``omnee``
        holds and equiangular sampling's elsewhere."""
        return _mis.weights(self.mode, q_a, q_b, dr.select(omnee, q_once, 0.0), dr.select(omnee, 0.0, q_once))

    # ------------------------------------------------------------- strategy c

    def omnee_at(self, x2: Any, it: Any, leaving: Any, f2_eval: Any, group: Any, throughput: Any,
                 channel: Any, active: Any) -> Any:
        """OMNEE at the vertices ``x2`` of ``active``: the weighted
        contribution. ``it`` is the vertex's interaction (``spawn_ray_to``),
        ``leaving(direction)`` the medium a ray leaving it in ``direction``
        is in, ``f2_eval(direction, mask)`` its BSDF or phase function
        ``(value, pdf)`` towards ``x1`` (the value with the cosine)."""
        active = mi.Bool(active)  # a copy: Dr.Jit's &= would change the caller's mask
        x0 = self.sample_light(active, it.time)
        u = mi.Point3f(self.random.next_1d(), self.random.next_1d(), self.random.next_1d())
        active &= x0.pdf > 0.0
        dr.eval(x0, u, active)
        x1, pdf, valid = _bridge.omnee_draw(self.groups, group, x0.p, x2, u, active)
        active &= valid & (pdf > 0.0)
        to_x1 = x1 - x2
        d21 = dr.norm(to_x1)
        w21 = to_x1 / d21
        active &= d21 > 0.0
        f2, pdf_dir = f2_eval(w21, active)
        active &= dr.any(mi.UnpolarizedSpectrum(f2) != 0.0)
        tr21, tau, medium1 = self.reach(it, leaving(w21), x1, channel, active)
        group1 = self.info.group_of(medium1)
        active &= (group1 < self.none) & dr.any(tr21 != 0.0)
        mei1 = _transport.medium_interaction(medium1, x1, -w21, it.wavelengths, it.time, active)
        em, rho, rho_pdf, tr10 = self.light_edge(mei1, medium1, x0, channel, active)
        # f_c p(θ)/(d1² d2² pdf): the scene's phase function at x1 in place of
        # omnee's in the closed-form weight θ/(s sin θ) = p(θ)/(d1² d2² pdf).
        k = dr.rcp(dr.square(em.ds.dist) * dr.square(d21) * pdf)
        contribution = (throughput * f2 * tr21 * mi.Spectrum(mei1.sigma_s) * rho * tr10
                        * em.value * (k / x0.pdf))
        q_ff = _mis.free_flight(pdf_dir, mean_channels(mei1.sigma_t), tau, d21)
        q_a = q_ff * self.nee_density(mei1, em.ds, em.g0, active)
        q_b = dr.select(x0.delta, 0.0, q_ff * rho_pdf * em.g0)
        # Equiangular sampling never runs on a leg that OMNEE starts: q_d = 0.
        w = _mis.weights(self.mode, q_a, q_b, x0.pdf * pdf, 0.0)[2]
        return dr.select(active & dr.all(dr.isfinite(contribution)), contribution * w, 0.0)

    # ------------------------------------------------------------- strategy d

    def equiangular_on(self, ray: Any, medium: Any, t_max: Any, throughput: Any, leg: Leg,
                       channel: Any, active: Any) -> Any:
        """Equiangular sampling on the medium segment ``[0, t_max]`` of
        ``ray``, which begins ``leg.t`` along its leg: the weighted
        contribution."""
        active = mi.Bool(active)  # a copy: Dr.Jit's &= would change the caller's mask
        x0 = self.sample_light(active, ray.time)
        u = self.random.next_1d()
        active &= x0.pdf > 0.0
        dr.eval(x0, u, active)
        t, pdf_t, valid = _bridge.equiangular_draw(x0.p, ray.o, ray.d, t_max, u, active)
        active &= valid & (pdf_t > 0.0)
        x1 = ray.o + t * ray.d
        # No surface lies between the segment's start and x1: in a
        # homogeneous medium the transmittance is exp(−σt t); elsewhere
        # ratio tracking along the segment.
        homogeneous = active & medium.is_homogeneous()
        along = mi.Ray3f(ray.o, ray.d, t, ray.time, ray.wavelengths)
        tr01, tau01, _ = _transport.walk(self.scene, self.random.next_1d(), along, medium, channel,
                                         active & ~homogeneous)
        majorant = mi.Spectrum(medium.get_majorant(_transport.medium_interaction_at(ray.o, ray.wavelengths),
                                                   homogeneous))
        tr01[homogeneous] = dr.exp(-majorant * t)
        tau01[homogeneous] = mean_channels(majorant) * t
        mei1 = _transport.medium_interaction(medium, x1, -ray.d, ray.wavelengths, ray.time, active)
        em, rho, rho_pdf, tr10 = self.light_edge(mei1, medium, x0, channel, active)
        # pdf(t) d10² is the equiangular normalisation c, free of the pole at x0.
        c = pdf_t * dr.square(em.ds.dist)
        contribution = (throughput * tr01 * mi.Spectrum(mei1.sigma_s) * rho * tr10 * em.value
                        / (x0.pdf * c))
        t21 = leg.t + t
        q_ff = _mis.free_flight(leg.pdf, mean_channels(mei1.sigma_t), leg.tau + tau01, t21)
        q_a = q_ff * self.nee_density(mei1, em.ds, em.g0, active)
        q_b = dr.select(x0.delta, 0.0, q_ff * rho_pdf * em.g0)
        q_d = x0.pdf * leg.pdf * dr.exp(-leg.tau) * pdf_t / dr.square(t21)
        # OMNEE never starts a leg that equiangular sampling runs on: q_c = 0.
        w = _mis.weights(self.mode, q_a, q_b, 0.0, q_d)[3]
        return dr.select(active & dr.all(dr.isfinite(contribution)), contribution * w, 0.0)


def _interaction(p: Any, n: Any, ray: Any) -> Any:
    """An ``mi.Interaction3f`` at ``p`` with normal ``n`` (zero in a medium)."""
    it = dr.zeros(mi.Interaction3f, dr.width(p))
    it.p, it.n, it.time, it.wavelengths = p, n, ray.time, ray.wavelengths
    it.t = mi.Float(0.0)
    return it


def render_wavefront(integrator: Any, info: SceneInfo, scene: Any, sampler: Any, seed: Any,
                     lane: Any, ray_: Any, medium_: Any, active_: Any) -> Tuple[Any, Any]:
    """volpath with the once-more strategies over camera rays ``ray_`` (the
    lanes ``lane`` of the wavefront, ``seed`` a uniform number of each):
    ``(radiance, valid)`` per camera ray."""
    max_depth, rr_depth, hide = integrator.max_depth, integrator.rr_depth, integrator.hide_emitters
    width = dr.width(ray_.o)
    groups = len(info.groups)
    surface_lights = info.surface_lights
    random = Random(sampler, seed, lane)
    radiance = dr.zeros(mi.Spectrum, width)
    valid_out = dr.zeros(mi.Bool, width)

    p = Paths()
    p.lane = dr.arange(mi.UInt32, width)
    p.ray = mi.Ray3f(ray_)
    p.active = mi.Bool(active_) | dr.zeros(mi.Bool, width)
    p.medium = dr.zeros(mi.MediumPtr, width)
    if medium_ is not None:
        p.medium[p.active] = mi.MediumPtr(medium_)
    p.throughput = dr.full(mi.Spectrum, 1.0, width)
    p.result = dr.zeros(mi.Spectrum, width)
    p.eta = dr.full(mi.Float, 1.0, width)
    p.depth = dr.zeros(mi.UInt32, width)
    p.valid = dr.full(mi.Bool, (not hide) and scene.environment() is not None, width)
    p.specular = p.active & (not hide)
    p.channel = dr.zeros(mi.UInt32, width)
    if mi.is_rgb:
        p.channel = mi.UInt32(dr.minimum(random.next_1d() * 3, 2))
    p.needs_intersection = dr.full(mi.Bool, True, width)
    p.seg_end = dr.full(mi.Float, dr.inf, width)
    p.last_p = dr.zeros(mi.Point3f, width)
    p.last_n = dr.zeros(mi.Normal3f, width)
    p.last_pdf = dr.full(mi.Float, 1.0, width)
    leg = Leg(p.ray, width, groups)
    vertex = Vertex(width, groups) if surface_lights else None
    s = Strategies(integrator, info, scene, random)
    bsdf_ctx = mi.BSDFContext()

    def flush(mask: Any) -> None:
        """Adds the lanes of ``mask`` to the wavefront's output."""
        dr.scatter_add(radiance, p.result, p.lane, mask)
        dr.scatter(valid_out, True, p.lane, mask & p.valid)

    while True:
        # ---------------------------------------------- termination, as volpath
        throughput, depth = p.throughput, p.depth
        active = p.active & dr.any(mi.UnpolarizedSpectrum(throughput) != 0.0)
        q = dr.minimum(dr.max(mi.UnpolarizedSpectrum(throughput)) * dr.square(p.eta), 0.95)
        perform_rr = depth > rr_depth
        active &= (random.next_1d() < q) | ~perform_rr
        p.throughput[perform_rr] = throughput * dr.rcp(q)
        active &= depth < max_depth
        p.active = active
        dr.eval(p.active, p.throughput)

        # ------------------------------ drop the finished paths, once enough are
        alive = dr.count(p.active)[0]
        n = dr.width(p.active)
        if alive == 0:
            break
        if alive < _COMPACT * n:
            flush(~p.active)
            index = dr.compress(p.active)
            p.compact(index)
            leg.compact(index)
            if vertex is not None:
                vertex.compact(index)
            random.compact(index)
            n = alive
        ray, medium, channel, throughput = p.ray, p.medium, p.channel, p.throughput
        active = mi.Bool(p.active)
        depth = p.depth

        active_medium = active & (medium != None)  # noqa: E711
        active_surface = active & ~active_medium

        # ------------------------- a medium segment begins: its end, and equiangular
        starts = active_medium & p.needs_intersection
        p.seg_end[starts] = scene.ray_intersect_preliminary(ray, False, starts).t
        p.needs_intersection &= ~active_medium
        seg_end = p.seg_end
        leg.seg_t0[starts] = leg.t
        leg.seg_t1[starts] = leg.t + seg_end
        leg.seg_tau0[starts] = leg.tau
        leg.seg_eq[starts] = ((info.group_of(medium) < groups) & (depth + 1 < max_depth)
                              & info.equiangular & ~leg.omnee)
        dr.eval(seg_end, leg.seg_t0, leg.seg_t1, leg.seg_tau0, leg.seg_eq)
        eq = starts & leg.seg_eq
        if dr.any(eq):
            p.result += s.equiangular_on(ray, medium, seg_end, throughput, leg, channel, eq)

        # ----------------------------------------------------- free flight, as volpath
        is_spectral = active_medium & medium.has_spectral_extinction()
        not_spectral = active_medium & ~is_spectral
        mei = medium.sample_interaction(ray, random.next_1d(), channel, active_medium)
        mei.t[active_medium & (seg_end < mei.t)] = dr.inf
        # transmittance_eval_pdf takes the surface's distance from its second argument.
        si_t = dr.zeros(mi.SurfaceInteraction3f, n)
        si_t.t = seg_end
        tr, free_flight_pdf = medium.transmittance_eval_pdf(mei, si_t, is_spectral)
        tr_pdf = index_spectrum(free_flight_pdf, channel)
        throughput[is_spectral] *= dr.select(tr_pdf > 0.0, tr / tr_pdf, 0.0)
        escaped = active_medium & ~mei.is_valid()
        active_medium &= mei.is_valid()
        rate = _transport.extinction_rate(medium, ray.o, ray.wavelengths, active_medium | escaped)
        leg.tau[active_medium] = leg.tau + rate * mei.t
        leg.tau[escaped] = leg.tau + rate * seg_end
        leg.t[active_medium] = leg.t + mei.t

        null_prob = mean_channels(mei.sigma_n / mei.combined_extinction)
        null_scatter = random.next_1d() < null_prob
        act_null = active_medium & null_scatter
        act_scatter = active_medium & ~null_scatter
        throughput[is_spectral & act_null] *= mei.sigma_n / null_prob
        depth[act_scatter] += 1
        active &= depth < max_depth
        act_scatter &= active
        ray.o[act_null] = mei.p
        p.seg_end[act_null] = seg_end - mei.t
        dr.eval(mei, throughput, depth, ray, active_medium, act_scatter, escaped, leg.t, leg.tau)

        # ------------------------------------------------------ a real scattering event
        if dr.any(act_scatter):
            throughput[is_spectral & act_scatter] *= mei.sigma_s / mean_channels(mei.sigma_t / mei.combined_extinction)
            throughput[not_spectral & act_scatter] *= mei.sigma_s / mei.sigma_t
            phase_ctx = mi.PhaseFunctionContext(sampler)
            phase = mei.medium.phase_function()
            group1 = info.group_of(mei.medium)
            served = act_scatter & (group1 < groups)
            q_ff = _mis.free_flight(leg.pdf, mean_channels(mei.sigma_t), leg.tau, leg.t)

            # volpath's next event estimation (strategy a).
            sample_emitters = mei.medium.use_emitter_sampling()
            p.valid |= act_scatter
            p.specular &= ~act_scatter
            p.specular |= act_scatter & ~sample_emitters
            nee = act_scatter & sample_emitters
            ds, emitter_val = scene.sample_emitter_direction(mei, random.next_2d(), False, nee)
            emitter_val[ds.pdf == 0.0] = 0.0
            nee &= ds.pdf != 0.0
            tr_nee, _, _ = s.reach(mei, medium, ds.p, channel, nee)
            phase_val, phase_pdf = phase.eval_pdf(phase_ctx, mei, ds.d, nee)
            finite = nee & served & _lights.is_finite(ds.emitter)
            g0 = dr.select(ds.delta, 1.0, dr.abs(dr.dot(ds.d, ds.n)) * dr.rcp(dr.square(ds.dist)))
            g0 = dr.select(finite, g0, 1.0)
            q_a = q_ff * dr.select(ds.delta, ds.pdf, ds.pdf * g0)
            q_b = dr.select(ds.delta, 0.0, q_ff * phase_pdf * g0)
            x0_pdf = _lights.density(info, ds.emitter, ds, finite)
            q_once = s.once_more_density(x0_pdf, ds.p, mei.p, leg, leg.t, finite)
            w = s.weights_split(q_a, q_b, q_once, leg.omnee)[0]
            p.result[nee] += throughput * mi.Spectrum(phase_val) * tr_nee * emitter_val * w

            # OMNEE with this vertex as x2 (strategy c), with the phase
            # function of its medium, or of the scene's first served one: x1
            # may lie in any served medium.
            sampling_group = dr.select(group1 < groups, group1, 0)
            by_omnee = act_scatter & (depth + 1 < max_depth) & info.omnee
            if dr.any(by_omnee):
                def phase_eval(w21: Any, m: Any, mei: Any = mei, phase: Any = phase, ctx: Any = phase_ctx) -> Any:
                    return phase.eval_pdf(ctx, mei, w21, m)

                p.result += s.omnee_at(mei.p, mei, lambda _w: medium, phase_eval, sampling_group,
                                       throughput, channel, by_omnee)

            # Phase sampling: a new leg.
            if vertex is not None:
                vertex.valid[act_scatter] = False
                vertex.keep(served, leg, q_ff)
            wo, phase_weight, phase_pdf = phase.sample(phase_ctx, mei, random.next_1d(),
                                                       random.next_2d(), act_scatter)
            act_scatter &= phase_pdf > 0.0
            ray[act_scatter] = mei.spawn_ray(wo)
            p.needs_intersection |= act_scatter
            p.last_p[act_scatter] = mei.p
            p.last_n[act_scatter] = mi.Normal3f(0.0)
            p.last_pdf[act_scatter] = phase_pdf
            throughput[act_scatter] *= phase_weight
            leg.restart(act_scatter, mei.p, wo, phase_pdf, by_omnee, sampling_group)

        # --------------------------------------------------------------- surfaces
        active_surface |= escaped
        si = scene.ray_intersect(ray, _SURFACE_FLAGS, False, active_surface)
        if hide:
            skip = active_surface & si.is_valid() & (si.shape.emitter() != None) & (depth == 0)  # noqa: E711
            if dr.any(skip):
                skip_ray = si.spawn_ray(ray.d)
                pi = integrator.skip_area_emitters(scene, skip_ray, True, skip)
                si[skip] = pi.compute_surface_interaction(skip_ray, mi.RayFlags.All, skip)
        dr.eval(si)

        count_direct = (active_surface & (depth == 0)) | p.specular
        emitter = si.emitter(scene)
        hit = active_surface & (emitter != None) & ~((depth == 0) & hide)  # noqa: E711
        if dr.any(hit):
            last = _interaction(p.last_p, p.last_n, ray)
            ds = mi.DirectionSample3f(scene, si, last)
            emitter_pdf = scene.pdf_emitter_direction(last, ds, hit & ~count_direct)
            emitted = emitter.eval(si, hit)
            w = _mis.power_weight(p.last_pdf, emitter_pdf)
            # After a medium vertex, on a surface emitter: strategy b of four.
            if vertex is not None:
                four = hit & ~count_direct & vertex.valid & _lights.is_finite(emitter)
                if dr.any(four):
                    g0 = dr.abs(dr.dot(ds.d, ds.n)) * dr.rcp(dr.square(ds.dist))
                    q_b = vertex.q_ff * p.last_pdf * g0
                    q_a = vertex.q_ff * emitter_pdf * g0
                    x0_pdf = _lights.density(info, emitter, ds, four)
                    q_once = s.once_more_density(x0_pdf, si.p, p.last_p, vertex, vertex.t21, four)
                    w[four] = s.weights_split(q_a, q_b, q_once, vertex.omnee)[1]
            p.result[hit] += throughput * emitted * dr.select(count_direct, 1.0, w)

        # A surface ends the leg's medium segment; through a null interface
        # the leg goes on.
        leg.t[active_surface] = leg.t + si.t
        active_surface &= si.is_valid()
        if dr.any(active_surface):
            bsdf = si.bsdf(ray)
            smooth = mi.has_flag(bsdf.flags(), mi.BSDFFlags.Smooth)

            # volpath's next event estimation at the surface.
            active_e = active_surface & smooth & (depth + 1 < max_depth)
            if dr.any(active_e):
                ds, emitter_val = scene.sample_emitter_direction(si, random.next_2d(), False, active_e)
                emitter_val[ds.pdf == 0.0] = 0.0
                active_e &= ds.pdf != 0.0
                medium_e = dr.select(active_e & si.is_medium_transition(), si.target_medium(ds.d), medium)
                tr_e, _, _ = s.reach(si, medium_e, ds.p, channel, active_e)
                bsdf_val, bsdf_pdf = bsdf.eval_pdf(bsdf_ctx, si, si.to_local(ds.d), active_e)
                w = _mis.power_weight(ds.pdf, dr.select(ds.delta, 0.0, bsdf_pdf))
                p.result[active_e] += throughput * bsdf_val * tr_e * emitter_val * w

            # OMNEE with this surface vertex as x2 (strategy c).
            interior = si.target_medium(-si.n)
            exterior = si.target_medium(si.n)
            side = dr.select(si.is_medium_transition(),
                             dr.select(info.group_of(interior) < groups, interior, exterior), medium)
            # The phase function of the medium on the surface's side (the
            # interior's for a boundary), or of the scene's first served one.
            group2 = info.group_of(side)
            group2 = dr.select(group2 < groups, group2, 0)
            # The surface is vertex depth + 1 of the path, x1 would be depth + 2.
            by_omnee = active_surface & smooth & (depth + 2 < max_depth) & info.omnee
            if dr.any(by_omnee):
                def bsdf_eval(w21: Any, m: Any, si: Any = si, bsdf: Any = bsdf) -> Any:
                    return bsdf.eval_pdf(bsdf_ctx, si, si.to_local(w21), m)

                def leaving(w21: Any, si: Any = si, medium: Any = medium) -> Any:
                    return dr.select(si.is_medium_transition(), si.target_medium(w21), medium)

                p.result += s.omnee_at(si.p, si, leaving, bsdf_eval, group2, throughput, channel, by_omnee)

            # BSDF sampling, as volpath.
            bs, bsdf_weight = bsdf.sample(bsdf_ctx, si, random.next_1d(), random.next_2d(), active_surface)
            throughput[active_surface] *= bsdf_weight
            p.eta[active_surface] *= bs.eta
            ray[active_surface] = si.spawn_ray(si.to_world(bs.wo))
            p.needs_intersection |= active_surface
            non_null = active_surface & ~mi.has_flag(bs.sampled_type, mi.BSDFFlags.Null)
            depth[non_null] += 1
            p.last_p[non_null] = si.p
            p.last_n[non_null] = si.n
            p.last_pdf[non_null] = bs.pdf
            p.valid |= non_null
            delta = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)
            p.specular |= non_null & delta
            p.specular &= ~(active_surface & mi.has_flag(bs.sampled_type, mi.BSDFFlags.Smooth))
            if vertex is not None:
                vertex.valid[non_null] = False
            leg.restart(non_null, si.p, ray.d, bs.pdf, by_omnee & ~delta, group2)
            transition = active_surface & si.is_medium_transition()
            medium[transition] = si.target_medium(ray.d)

        active &= active_surface | active_medium
        p.ray, p.medium, p.throughput, p.depth, p.active = ray, medium, throughput, depth, active
        dr.eval(p.fields(), leg.fields(), random.fields(), [] if vertex is None else vertex.fields())

    flush(dr.full(mi.Bool, True, dr.width(p.lane)))
    radiance = dr.select(dr.all(dr.isfinite(mi.UnpolarizedSpectrum(radiance))), radiance, 0.0)
    return radiance, valid_out


# Camera rays per wavefront: the live paths' state takes about 1 KiB each.
_CHUNK = 1 << 21


def render_chunks(integrator: Any, info: SceneInfo, scene: Any, sampler: Any, ray: Any,
                  medium: Any, active: Any) -> Tuple[Any, Any]:
    """:func:`render_wavefront` over the camera rays, at most ``_CHUNK`` at a
    time (Mitsuba hands an integrator all the samples of a pass at once)."""
    width = dr.width(ray.o)
    seed = sampler.next_1d()
    sampler.schedule_state()
    dr.eval(seed)
    if width <= _CHUNK:
        lane = dr.arange(mi.UInt32, width)
        return render_wavefront(integrator, info, scene, sampler, seed, lane, ray, medium, active)
    radiance = dr.zeros(mi.Spectrum, width)
    valid = dr.zeros(mi.Bool, width)
    active = mi.Bool(active) | dr.zeros(mi.Bool, width)
    media = dr.zeros(mi.MediumPtr, width)
    if medium is not None:
        media[active] = mi.MediumPtr(medium)
    for start in range(0, width, _CHUNK):
        lane = dr.arange(mi.UInt32, start, min(start + _CHUNK, width))

        def take(x: Any) -> Any:
            return dr.gather(type(x), x, lane)

        chunk = mi.Ray3f(take(ray.o), take(ray.d), take(ray.maxt), take(ray.time), take(ray.wavelengths))
        r, v = render_wavefront(integrator, info, scene, sampler, take(seed), lane, chunk,
                                take(media), take(active))
        dr.scatter(radiance, r, lane)
        dr.scatter(valid, v, lane)
        dr.eval(radiance, valid)
    return radiance, valid


def _boolean(props: Any, name: str) -> bool:
    """The boolean parameter ``name`` (default true); another type raises
    ``ValueError`` naming it."""
    value = props.get(name, True)
    if not isinstance(value, bool):
        raise ValueError(f'"{name}" = {value!r} is not supported; allowed: true or false')
    return value


def make_class() -> Any:
    """The integrator class for the current Mitsuba variant."""

    class OmneeVolpathIntegrator(mi.SamplingIntegrator):  # type: ignore[misc]
        """``omnee_volpath``: Mitsuba's ``volpath`` with OMNEE and equiangular
        sampling towards finite lights, combined by MIS (module docs)."""

        def __init__(self, props: Any) -> None:
            super().__init__(props)
            max_depth = props.get("max_depth", -1)
            rr_depth = props.get("rr_depth", 5)
            hide = props.get("hide_emitters", False)
            self.omnee = _boolean(props, "omnee")
            self.equiangular = _boolean(props, "equiangular")
            self.mis = props.get("mis", "power")
            if self.mis not in ("power",) + _mis.STRATEGIES:
                raise ValueError(
                    f'"mis" = "{self.mis}" is not supported; allowed: '
                    + ", ".join(f'"{m}"' for m in ("power",) + _mis.STRATEGIES)
                )
            # volpath checks the parameters and raises Mitsuba's own errors;
            # it and volpathmis render the scenes the strategies cannot serve.
            parameters = {"max_depth": max_depth, "rr_depth": rr_depth, "hide_emitters": hide}
            self._volpath = mi.load_dict({"type": "volpath", **parameters})
            self._volpathmis = mi.load_dict({"type": "volpathmis", **parameters})
            self.max_depth = 2**32 - 1 if max_depth == -1 else int(max_depth)
            self.rr_depth = int(rr_depth)
            self.hide_emitters = bool(hide)
            self._scenes: Dict[int, Tuple[Any, SceneInfo]] = {}

        def scene_info(self, scene: Any) -> SceneInfo:
            """The analysis of ``scene`` (once per scene)."""
            key = id(scene)
            cached = self._scenes.get(key)
            if cached is None or cached[0] is not scene:
                cached = (scene, analyse(scene, self.omnee, self.equiangular))
                self._scenes = {key: cached}
            return cached[1]

        def sample(self, scene: Any, sampler: Any, ray: Any, medium: Any = None, active: Any = True) -> Any:
            info = self.scene_info(scene)
            if not info.enabled:
                # Nothing for OMNEE or equiangular sampling to do: Mitsuba's own
                # integrator, with spectral MIS where the extinction is chromatic.
                fallback = self._volpathmis if info.chromatic else self._volpath
                return fallback.sample(scene, sampler, ray, medium, active)
            return (*render_chunks(self, info, scene, sampler, ray, medium, active), [])

        def aov_names(self) -> List[str]:
            return []

        def to_string(self) -> str:
            return (f"OmneeVolpathIntegrator[max_depth = {self.max_depth}, "
                    f"rr_depth = {self.rr_depth}, hide_emitters = {self.hide_emitters}]")

    return OmneeVolpathIntegrator
