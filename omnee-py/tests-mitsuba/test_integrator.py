"""omnee_volpath in Mitsuba: registration, parameters and their errors,
scene files, nesting in ``moment``, determinism, the fallback to volpath,
the phase-function mapping, finite output on hostile scenes, and the two
once-more strategies against closed forms: OMNEE at a fixed vertex against
the core's quadrature of the point-to-point integral, equiangular sampling
along a fixed ray against a 1-D quadrature."""

import math
import os

import numpy as np
import pytest

import omnee

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")


def fog_box(mi, integrator, phase=None, light="point", res=8, emitter_extra=None, medium_extra=None):
    """A small scene: fog in a null-bounded box, a light, a floor."""
    T = mi.ScalarTransform4f
    medium = {"type": "homogeneous", "sigma_t": 0.8, "albedo": 0.9,
              "phase": phase or {"type": "hg", "g": 0.9}}
    medium.update(medium_extra or {})
    scene = {
        "type": "scene",
        "integrator": integrator,
        "sensor": {"type": "perspective", "fov": 40,
                   "to_world": T().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}}},
        "box": {"type": "cube", "bsdf": {"type": "null"}, "interior": medium},
        "floor": {"type": "rectangle", "to_world": T().translate([0, -1.2, 0]).rotate([1, 0, 0], -90).scale(3),
                  "bsdf": {"type": "diffuse"}},
    }
    if light == "point":
        scene["light"] = {"type": "point", "position": [0.2, 0.3, 0.1], "intensity": 1.0}
    elif light == "area":
        scene["light"] = {"type": "rectangle", "to_world": T().translate([0, 0.5, 0]).rotate([1, 0, 0], 90).scale(0.2),
                          "emitter": {"type": "area", "radiance": 5.0}}
    elif light == "envmap":
        scene["light"] = {"type": "constant", "radiance": 0.5}
    scene["light"].update(emitter_extra or {})
    return scene


def render(mi, scene, spp=16, seed=0):
    return np.array(mi.render(mi.load_dict(scene), spp=spp, seed=seed))


def test_registered_and_loaded_from_dicts_and_files(mi):
    integrator = mi.load_dict({"type": "omnee_volpath", "max_depth": 5})
    assert "max_depth = 5" in str(integrator)
    xml = os.path.join(SCENES, "test_fog_point_hg90_volpath.xml")
    scene = mi.load_file(xml, integrator="omnee_volpath", res=4)
    assert "OmneeVolpath" in str(scene.integrator()) or "omnee" in str(scene.integrator()).lower()
    image = np.array(mi.render(scene, spp=4, seed=0))
    assert np.isfinite(image).all() and image[..., :3].sum() > 0


@pytest.mark.parametrize(
    "parameters, message",
    [
        ({"max_depth": -2}, "max_depth"),
        ({"rr_depth": 0}, "rr_depth"),
        ({"mis": "balance"}, '"mis" = "balance" is not supported; allowed: "power", "volpath", "omnee", "equiangular"'),
        ({"omnee": "yes"}, "\"omnee\" = 'yes' is not supported; allowed: true or false"),
        ({"max_dept": 3}, "unreferenced property"),
    ],
)
def test_bad_parameters_raise_mitsubas_errors_naming_them(mi, parameters, message):
    with pytest.raises(Exception, match=message):
        mi.load_dict({"type": "omnee_volpath", **parameters})


def test_scalar_variants_get_a_clear_error(mi):
    import omnee.mitsuba

    current = mi.variant()
    try:
        mi.set_variant("scalar_rgb")
        with pytest.raises(RuntimeError, match="'scalar_rgb' is not supported; allowed: a JIT variant"):
            omnee.mitsuba.register()
    finally:
        mi.set_variant(current)
    omnee.mitsuba.register()


def test_deterministic_for_a_seed_and_nested_in_moment(mi):
    scene = fog_box(mi, {"type": "moment", "nested": {"type": "omnee_volpath", "max_depth": 4}})
    a, b = render(mi, scene, seed=3), render(mi, scene, seed=3)
    c = render(mi, scene, seed=4)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    # The moment integrator's layers: the image, its mean and second moment.
    assert a.shape[-1] >= 9 and np.isfinite(a).all()
    mean, m2 = a[..., 3:6], a[..., 6:9]
    assert (m2 >= mean * mean * (1 - 1e-4) - 1e-7).all()


def test_scenes_without_a_finite_light_are_volpaths(mi):
    """No finite light: the integrator is Mitsuba's volpath, the same
    samples (to the rounding of a kernel compiled apart)."""
    ours = render(mi, fog_box(mi, {"type": "omnee_volpath", "max_depth": 6}, light="envmap"), seed=2)
    theirs = render(mi, fog_box(mi, {"type": "volpath", "max_depth": 6}, light="envmap"), seed=2)
    np.testing.assert_allclose(ours, theirs, rtol=1e-5, atol=1e-7)


def test_unrepresentable_phase_functions_warn_once_and_keep_volpath(mi):
    phase = {"type": "blendphase", "weight": 0.5, "phase1": {"type": "hg", "g": 0.5},
             "phase2": {"type": "rayleigh"}}
    scene = fog_box(mi, {"type": "omnee_volpath", "max_depth": 4}, phase=phase)
    with pytest.warns(RuntimeWarning, match="no omnee equivalent.*keeps volpath's strategies only"):
        ours = render(mi, scene, seed=5)
    theirs = render(mi, fog_box(mi, {"type": "volpath", "max_depth": 4}, phase=phase), seed=5)
    np.testing.assert_allclose(ours, theirs, rtol=1e-5, atol=1e-7)


def test_phase_functions_map_to_omnees(mi):
    from omnee.mitsuba._phase import omnee_phase

    ctx = mi.PhaseFunctionContext(None)
    theta = np.linspace(0.0, math.pi, 181)
    cases = {
        "hg": ({"type": "hg", "g": 0.93}, "hg:"),
        "iso": ({"type": "isotropic"}, "iso"),
        "rayleigh": ({"type": "rayleigh"}, "rayleigh"),
        "blend": ({"type": "blendphase", "weight": 0.3, "phase1": {"type": "hg", "g": 0.9},
                   "phase2": {"type": "hg", "g": -0.4}}, "tthg:"),
    }
    for name, (d, prefix) in cases.items():
        phase = mi.load_dict(d)
        ours = omnee_phase(phase)
        assert ours.spec.startswith(prefix), (name, ours.spec)
        # Mitsuba's phase function of the deflection θ: ωi points back along
        # the incoming ray, so ωo = −ωi is straight on (θ = 0).
        mei = mi.MediumInteraction3f()
        mei.wi = mi.Vector3f(0, 0, -1)
        mei.sh_frame = mi.Frame3f(mei.wi)
        wo = mi.Vector3f(np.sin(theta), 0 * theta, np.cos(theta))
        value, _ = phase.eval_pdf(ctx, mei, wo)
        value = np.array(value, dtype=np.float64)
        value = np.broadcast_to(value[0] if value.ndim == 2 else value, theta.shape)
        np.testing.assert_allclose(ours.eval(theta), value, rtol=2e-5, err_msg=name)


def test_tabulated_phase_functions_map_to_fine_tables(mi):
    from omnee.mitsuba._phase import omnee_phase

    values = [0.3, 0.25, 0.3, 0.5, 1.0, 3.0, 12.0]
    ours = omnee_phase(mi.load_dict({"type": "tabphase", "values": ", ".join(map(str, values))}))
    assert ours.spec == "table"
    # Mitsuba's density is linear in cos θ between the values; each omnee bin
    # holds its exact mass (a linear function's mean is its midpoint value),
    # so the two CDFs agree at every bin edge.
    grid = np.linspace(-1.0, 1.0, len(values))
    cos_edges = np.linspace(1.0, -1.0, 6 * 8 + 1)
    mass = np.array([np.trapezoid(np.interp(np.linspace(b, a, 65), grid, values), np.linspace(b, a, 65))
                     for a, b in zip(cos_edges[:-1], cos_edges[1:])])
    exact_cdf = np.concatenate([[0.0], np.cumsum(mass)]) / mass.sum()
    np.testing.assert_allclose(ours.cdf(np.arccos(cos_edges)), exact_cdf, atol=1e-12)
    assert abs(ours.cdf(math.pi) - 1.0) < 1e-12


@pytest.mark.parametrize("light", ["point", "area"])
def test_finite_output_on_hostile_scenes(mi, light):
    cases = [
        {"medium_extra": {"sigma_t": 0.0}},
        {"medium_extra": {"albedo": 0.0}},
        {"medium_extra": {"sigma_t": 500.0}},
        {"phase": {"type": "hg", "g": 0.999}},
        {"phase": {"type": "hg", "g": -0.999}},
    ]
    for extra in cases:
        image = render(mi, fog_box(mi, {"type": "omnee_volpath", "max_depth": 5}, light=light, **extra), spp=8)
        assert np.isfinite(image).all(), extra
        assert (image >= 0).all(), extra
    # A point light on the floor and one at the camera.
    for position in ([0.0, -1.2, 0.0], [0.0, 0.0, 4.0]):
        scene = fog_box(mi, {"type": "omnee_volpath", "max_depth": 5})
        scene["light"]["position"] = position
        assert np.isfinite(render(mi, scene, spp=8)).all()


def infinite_fog(mi, sigma_t, albedo, g):
    """A homogeneous fog filling a cube of 2 km: infinite for a problem of a
    few metres at σt ≥ 1."""
    T = mi.ScalarTransform4f
    return mi.load_dict({
        "type": "scene",
        "box": {"type": "cube", "to_world": T().scale(1000), "bsdf": {"type": "null"},
                "interior": {"type": "homogeneous", "sigma_t": sigma_t, "albedo": albedo,
                             "phase": {"type": "hg", "g": g}}},
        "light": {"type": "point", "position": [0.0, 0.0, 1.0], "intensity": 1.0},
    })


def strategies(mi, scene, n, mode):
    import drjit as dr

    from omnee.mitsuba import _integrator

    integrator = mi.load_dict({"type": "omnee_volpath", "mis": mode})
    info = integrator.scene_info(scene)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(7, n)
    random = _integrator.Random(sampler, sampler.next_1d(), dr.arange(mi.UInt32, n))
    return _integrator.Strategies(integrator, info, scene, random), info


@pytest.mark.parametrize("g", [0.0, 0.9])
def test_omnee_at_a_vertex_matches_the_cores_quadrature(mi, g):
    """With the vertex's own factor set to 1 and all the weight on OMNEE,
    the strategy estimates σs ∫ p(θ) e^{−σt (d1 + d2)} / (d1² d2²) dx1, the
    point-to-point integral the core integrates by quadrature."""
    import drjit as dr

    from omnee.mitsuba import _transport

    sigma_t, albedo, n = 1.0, 0.8, 400_000
    scene = infinite_fog(mi, sigma_t, albedo, g)
    s, info = strategies(mi, scene, n, "omnee")
    medium = dr.gather(mi.MediumPtr, mi.MediumPtr([info.groups[0].medium]), dr.zeros(mi.UInt32, n))
    x2 = mi.Point3f(dr.zeros(mi.Float, n), dr.zeros(mi.Float, n), dr.zeros(mi.Float, n))
    mei = _transport.medium_interaction(medium, x2, mi.Vector3f(0, 0, 1), mi.Color0f(), mi.Float(0.0), mi.Bool(True))
    one = lambda w21, m: (mi.Spectrum(1.0), mi.Float(1.0))  # noqa: E731
    c = s.omnee_at(x2, mei, lambda _w: medium, one, dr.zeros(mi.UInt32, n), dr.full(mi.Spectrum, 1.0, n),
                   dr.zeros(mi.UInt32, n), dr.full(mi.Bool, True, n))
    values = np.array(c)[0] if np.array(c).shape[0] == 3 else np.array(c)[:, 0]
    mean, stderr = values.mean(), values.std() / math.sqrt(n)
    e = omnee.estimate(x0=[0, 0, 1], x2=[0, 0, 0], phase=f"hg:{g}" if g else "iso",
                       sigma_s=sigma_t * albedo, sigma_t=sigma_t, samples=1000, seed=1)
    assert abs(mean - e.reference) < 5 * stderr + 1e-4 * e.reference, (mean, stderr, e.reference)


def test_equiangular_along_a_ray_matches_a_quadrature(mi):
    """Along a ray through the fog, with all the weight on equiangular
    sampling: ∫₀^L σs p(θ(t)) e^{−σt (t + d1(t))} / d1(t)² dt."""
    import drjit as dr

    from omnee.mitsuba import _integrator

    sigma_t, albedo, g, n, length = 1.0, 0.8, 0.9, 400_000, 3.0
    scene = infinite_fog(mi, sigma_t, albedo, g)
    s, info = strategies(mi, scene, n, "equiangular")
    medium = dr.gather(mi.MediumPtr, mi.MediumPtr([info.groups[0].medium]), dr.zeros(mi.UInt32, n))
    o, d = np.array([-1.0, 0.3, 0.0]), np.array([1.0, 0.0, 0.2]) / math.hypot(1.0, 0.2)
    ray = mi.Ray3f(mi.Point3f(*map(float, o)) + mi.Point3f(dr.zeros(mi.Float, n)), mi.Vector3f(*map(float, d)))
    leg = _integrator.Leg(ray, n, 1)
    c = s.equiangular_on(ray, medium, dr.full(mi.Float, length, n), dr.full(mi.Spectrum, 1.0, n), leg,
                         dr.zeros(mi.UInt32, n), dr.full(mi.Bool, True, n))
    values = np.array(c)[0] if np.array(c).shape[0] == 3 else np.array(c)[:, 0]
    mean, stderr = values.mean(), values.std() / math.sqrt(n)
    x0 = np.array([0.0, 0.0, 1.0])
    t = np.linspace(0.0, length, 200_001)
    x1 = o + t[:, None] * d
    to_light = x0 - x1
    d1 = np.linalg.norm(to_light, axis=1)
    cos = (to_light @ d) / d1  # propagation x0 → x1 is −to_light, then along −d back to the camera
    phase = (1 - g * g) / (4 * math.pi * (1 + g * g - 2 * g * cos) ** 1.5)
    f = sigma_t * albedo * phase * np.exp(-sigma_t * (t + d1)) / d1**2
    exact = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t))
    assert abs(mean - exact) < 5 * stderr + 1e-4 * exact, (mean, stderr, exact)


EMITTERS = {
    "point": {"type": "point", "position": [0.2, 1.6, 0.1], "intensity": 2.0},
    "spot": {"type": "spot", "cutoff_angle": 40.0, "intensity": 3.0},
    "area": {"type": "rectangle", "emitter": {"type": "area", "radiance": 5.0}},
    "directional": {"type": "directional", "direction": [0.3, -1.0, -0.2], "irradiance": 1.0},
    "constant": {"type": "constant", "radiance": 0.5},
    "envmap": {"type": "envmap", "filename": os.path.join(SCENES, "data", "sky.exr"), "scale": 0.01},
    "projector": {"type": "projector", "fov": 40.0, "scale": 2.0},
}


@pytest.mark.parametrize("kind", sorted(EMITTERS))
def test_every_emitter_type_renders_volpaths_image(mi, kind):
    """Each emitter type outside the fog (g = 0.5), where volpath's
    variance is finite: finite, non-negative pixels, and an image mean
    within 4.5 standard errors of volpath's (the errors from the per-pixel
    variances of the moment integrator; 7 tests, a false alarm below
    10⁻⁴)."""
    T = mi.ScalarTransform4f
    light = dict(EMITTERS[kind])
    if kind in ("spot", "projector"):
        light["to_world"] = T().look_at(origin=[-0.6, 1.7, 0.6], target=[0.2, -0.5, 0.0], up=[0, 1, 0])
    if kind == "projector":
        light["irradiance"] = {"type": "checkerboard"}
    if kind == "area":
        light["to_world"] = T().translate([0, 1.5, 0]).rotate([1, 0, 0], 90).scale(0.3)
    spp = 512

    def mean_and_error(integrator):
        scene = fog_box(mi, {"type": "moment", "nested": {"type": integrator, "max_depth": 5}},
                        phase={"type": "hg", "g": 0.5})
        scene["light"] = light
        image = render(mi, scene, spp=spp, seed=11)
        assert np.isfinite(image).all() and (image[..., :6] >= 0).all(), (kind, integrator)
        mean, m2 = image[..., 3:6].astype(np.float64), image[..., 6:9].astype(np.float64)
        variance = np.maximum(m2 - mean * mean, 0.0)
        return mean.mean(), math.sqrt(variance.sum() / spp) / mean.size

    (a, sa), (b, sb) = mean_and_error("omnee_volpath"), mean_and_error("volpath")
    assert abs(a - b) <= 4.5 * math.hypot(sa, sb) + 1e-7, (kind, a, sa, b, sb)


def test_wavefronts_split_into_chunks_render_the_same_image(mi, monkeypatch):
    """A pass cut into chunks (as a large image is) renders the same image
    as the pass at once: deterministic for its seed, and its mean within 4.5
    standard errors of the whole pass's. (Not the same samples: a strategy
    that no path of a chunk needs draws no numbers there.)"""
    from omnee.mitsuba import _integrator

    scene = fog_box(mi, {"type": "moment", "nested": {"type": "omnee_volpath", "max_depth": 4}},
                    light="area")

    def mean_and_error():
        image = render(mi, scene, spp=128, seed=9).astype(np.float64)
        mean, m2 = image[..., 3:6], image[..., 6:9]
        return image, mean.mean(), math.sqrt(np.maximum(m2 - mean * mean, 0).sum() / 128) / mean.size

    _, a, sa = mean_and_error()
    monkeypatch.setattr(_integrator, "_CHUNK", 2500)
    first, b, sb = mean_and_error()
    again, _, _ = mean_and_error()
    np.testing.assert_array_equal(first, again)
    assert abs(a - b) <= 4.5 * math.hypot(sa, sb), (a, sa, b, sb)


def test_rows_the_core_refuses_are_dropped_not_raised(mi):
    """The lanes' checks leave out what the core refuses; where rounding
    differs at a hair's breadth, the refused row is dropped and the call
    made again, and an error that names no row still raises."""
    from omnee.mitsuba import _bridge

    x0 = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.5], [0.0, 1.0, 1.0]])
    origin = np.zeros((3, 3))
    direction = np.tile([0.0, 0.0, 1.0], (3, 1))

    def draw(a, o, d):
        return omnee.EquiangularSegment(a, o, d, 0.0, 2.0).sample(np.full(len(a), 0.5))

    kept, s = _bridge._rows_accepted(draw, [x0, origin, direction])
    assert kept.tolist() == [2] and s.valid.all()

    def broken(a):
        raise ValueError("x0 is bad")

    with pytest.raises(ValueError, match="x0 is bad"):
        _bridge._rows_accepted(broken, [x0])


@pytest.mark.parametrize("variant", ["llvm_ad_spectral", "llvm_ad_mono"])
def test_spectral_and_monochrome_variants_render_volpaths_image(mi, variant):
    """The integrator in a spectral and a monochrome variant: an area light
    in chromatic fog (σt differs per channel) and a point light in grey fog,
    finite non-negative pixels, and each image's mean within 4.5 standard
    errors of volpath's (4 tests, a false alarm below 10⁻⁴)."""
    import omnee.mitsuba

    current = mi.variant()
    try:
        mi.set_variant(variant)
        omnee.mitsuba.register()
        spp = 256
        for light, sigma_t in (("area", [0.4, 0.65, 1.0]), ("point", 0.8)):
            means = []
            for integrator in ("omnee_volpath", "volpath"):
                scene = fog_box(mi, {"type": "moment", "nested": {"type": integrator, "max_depth": 5}},
                                light=light, medium_extra={"sigma_t": {"type": "rgb", "value": sigma_t}}
                                if isinstance(sigma_t, list) else {"sigma_t": sigma_t})
                loaded = mi.load_dict(scene)
                image = np.array(mi.render(loaded, spp=spp, seed=5)).astype(np.float64)
                assert np.isfinite(image).all() and (image >= -1e-6).all(), (variant, light, integrator)
                # The moment integrator's channels come last: the mean's, then the second moment's.
                k = len(loaded.integrator().aov_names()) // 2
                mean, m2 = image[..., -2 * k:-k], image[..., -k:]
                variance = np.maximum(m2 - mean * mean, 0.0)
                means.append((mean.mean(), math.sqrt(variance.sum() / spp) / mean.size))
            (a, sa), (b, sb) = means
            assert abs(a - b) <= 4.5 * math.hypot(sa, sb) + 1e-7, (variant, light, a, sa, b, sb)
    finally:
        mi.set_variant(current)
        omnee.mitsuba.register()


def test_a_new_seed_compiles_no_kernel(mi):
    """The wavefront's kernels do not depend on how many paths are alive:
    rendering again with another seed (other numbers of live paths at every
    bounce) reuses the kernels of the first renders. Dr.Jit compiles a
    literal width (``dr.mean``), a 2-D numpy array's row count and a numpy
    buffer's alignment into a kernel; each of those had made every pass
    compile again (14 % of its kernels, 2 CPU s for a small image). What
    may still compile is a bounce whose combination of strategies with and
    without live lanes (``dr.any``) the first renders did not meet: 1 kernel
    in 707 with an empty kernel cache; at most 1 % passes."""
    import drjit as dr

    scene = mi.load_dict(fog_box(mi, {"type": "omnee_volpath", "max_depth": 5}, light="area", res=16))
    # Two passes first, so that every branch of the wavefront has run once.
    for seed in (1, 2):
        mi.render(scene, spp=32, seed=seed)
    dr.sync_thread()
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    try:
        dr.kernel_history()  # clears it
        mi.render(scene, spp=32, seed=3)
        dr.sync_thread()
        history = dr.kernel_history()
    finally:
        dr.set_flag(dr.JitFlag.KernelHistory, False)
    launched = [k for k in history if k.get("type") == dr.KernelType.JIT]
    assert launched, "no kernel launched"
    compiled = [k for k in launched if not (k.get("cache_hit") or k.get("cache_disk"))]
    assert len(compiled) <= 0.01 * len(launched), f"{len(compiled)} of {len(launched)} kernels compiled again"
