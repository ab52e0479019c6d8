"""A diffuse transmitter (a translucent screen) as a Mitsuba BSDF plugin:
Mitsuba 3.9.1 ships no `difftrans`. Light arriving on one side leaves the
other side with `f = t/π` (t: the transmittance); nothing is reflected.
Register it with `register()` before loading the scene; then
`{"type": "screen", "transmittance": 0.5}`."""

import drjit as dr
import mitsuba as mi


class Screen(mi.BSDF):
    """f(ωi, ωo) = t/π when ωi and ωo lie on opposite sides, else 0;
    sampled cosine-weighted on the side opposite to ωi."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.t = props.get("transmittance", 0.5)
        flags = mi.BSDFFlags.DiffuseTransmission | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [flags]
        self.m_flags = flags

    def sample(self, ctx, si, sample1, sample2, active=True):
        wo = mi.warp.square_to_cosine_hemisphere(sample2)
        wo.z = dr.select(si.wi.z > 0, -wo.z, wo.z)  # the other side
        bs = mi.BSDFSample3f()
        bs.wo = wo
        bs.pdf = mi.warp.square_to_cosine_hemisphere_pdf(mi.Vector3f(wo.x, wo.y, dr.abs(wo.z)))
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.DiffuseTransmission)
        bs.sampled_component = 0
        value = dr.select(active & (bs.pdf > 0), mi.Color3f(self.t), mi.Color3f(0.0))
        return bs, value  # f cos / pdf = t

    def eval(self, ctx, si, wo, active=True):
        opposite = si.wi.z * wo.z < 0
        return dr.select(active & opposite, mi.Color3f(self.t * dr.inv_pi * dr.abs(wo.z)), mi.Color3f(0.0))

    def pdf(self, ctx, si, wo, active=True):
        opposite = si.wi.z * wo.z < 0
        return dr.select(active & opposite, dr.inv_pi * dr.abs(wo.z), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"Screen[transmittance={self.t}]"


def register():
    mi.register_bsdf("screen", lambda props: Screen(props))
