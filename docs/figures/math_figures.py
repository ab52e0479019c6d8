#!/usr/bin/env python3
"""Draws the figures of docs/math.md as plain SVG (no dependencies).

    python3 docs/figures/math_figures.py

writes docs/figures/math-circumcircle.svg (§2) and
docs/figures/math-equiangular.svg (§8) next to this script. Every point is
computed from the formulas of docs/math.md, so the pictures are to scale.
"""

import math
import os

INK = "#222222"
MUTED = "#777777"
BLUE = "#1f5fbf"
ORANGE = "#c8501a"
GREEN = "#2b8a3e"
BALL = "#e8f0fc"
FONT = 'font-family="sans-serif"'


class Svg:
    """A y-up drawing in math units, mapped to pixels."""

    def __init__(self, width, height, scale, origin):
        self.w, self.h, self.k, self.o = width, height, scale, origin
        self.items = [
            f'<rect x="0" y="0" width="{width}" height="{height}" fill="#ffffff"/>'
        ]

    def p(self, x, y):
        return (self.o[0] + self.k * x, self.o[1] - self.k * y)

    def line(self, a, b, color=INK, width=1.5, dash=None):
        (x1, y1), (x2, y2) = self.p(*a), self.p(*b)
        d = f' stroke-dasharray="{dash}"' if dash else ""
        self.items.append(
            f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
            f'stroke="{color}" stroke-width="{width}"{d}/>'
        )

    def arrow(self, a, b, color=INK, width=1.5):
        """A line from a to b with a filled head at b."""
        self.line(a, b, color, width)
        dx, dy = b[0] - a[0], b[1] - a[1]
        n = math.hypot(dx, dy)
        ux, uy = dx / n, dy / n
        size = 9 / self.k
        left = (b[0] - size * (ux - 0.45 * uy), b[1] - size * (uy + 0.45 * ux))
        right = (b[0] - size * (ux + 0.45 * uy), b[1] - size * (uy - 0.45 * ux))
        pts = " ".join(f"{x:.1f},{y:.1f}" for x, y in map(lambda q: self.p(*q), [b, left, right]))
        self.items.append(f'<polygon points="{pts}" fill="{color}"/>')

    def circle(self, c, r, fill="none", color=INK, width=1.5, dash=None, px=False):
        x, y = self.p(*c)
        rr = r if px else r * self.k
        d = f' stroke-dasharray="{dash}"' if dash else ""
        self.items.append(
            f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{rr:.1f}" fill="{fill}" '
            f'stroke="{color}" stroke-width="{width}"{d}/>'
        )

    def dot(self, c, color=INK):
        self.circle(c, 4, fill=color, color=color, width=1, px=True)

    def polyline(self, pts, color=INK, width=1.5, dash=None):
        d = f' stroke-dasharray="{dash}"' if dash else ""
        s = " ".join(f"{x:.1f},{y:.1f}" for x, y in (self.p(*q) for q in pts))
        self.items.append(
            f'<polyline points="{s}" fill="none" stroke="{color}" stroke-width="{width}"{d}/>'
        )

    def angle(self, c, r, a0, a1, color, width=1.5):
        """An arc of radius r (math units) about c from angle a0 to a1 (radians, ccw)."""
        n = max(8, int(abs(a1 - a0) * 24))
        pts = [(c[0] + r * math.cos(a0 + (a1 - a0) * i / n), c[1] + r * math.sin(a0 + (a1 - a0) * i / n)) for i in range(n + 1)]
        self.polyline(pts, color, width)

    def text(self, c, s, color=INK, size=16, anchor="middle", style=""):
        x, y = self.p(*c)
        st = f' font-style="{style}"' if style else ""
        self.items.append(
            f'<text x="{x:.1f}" y="{y:.1f}" {FONT} font-size="{size}" fill="{color}" '
            f'text-anchor="{anchor}" dominant-baseline="middle"{st}>{s}</text>'
        )

    def save(self, path, title):
        head = (
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.w}" height="{self.h}" '
            f'viewBox="0 0 {self.w} {self.h}">\n<title>{title}</title>\n'
        )
        with open(path, "w", encoding="utf-8") as f:
            f.write(head + "\n".join(self.items) + "\n</svg>\n")


def arc_points(theta, lower=False, n=120):
    """The arc of constant deflection θ through x0 = (−1, 0) and x2 = (1, 0)
    (s = 2): centre (0, −cot θ), radius 1/sin θ (R = s/(2 sin θ))."""
    cy, r = -math.cos(theta) / math.sin(theta), 1 / math.sin(theta)
    a0 = math.atan2(0 - cy, -1)  # angle of x0 seen from the centre
    a1 = math.atan2(0 - cy, 1)  # angle of x2
    # The upper arc runs from x2's angle counter-clockwise to x0's.
    if a0 < a1:
        a0 += 2 * math.pi
    pts = [(r * math.cos(a1 + (a0 - a1) * i / n), cy + r * math.sin(a1 + (a0 - a1) * i / n)) for i in range(n + 1)]
    return [(x, -y) for x, y in pts] if lower else pts


def circumcircle(path):
    g = Svg(700, 500, 150, (330, 325))
    x0, x2 = (-1.0, 0.0), (1.0, 0.0)
    s = 2.0
    # The Thales ball: θ < π/2 exactly inside it.
    g.circle((0, 0), 1, fill=BALL, color=BLUE, width=1, dash="5 4")
    g.line((-1.55, 0), (1.9, 0), MUTED, 1, dash="2 4")
    # Waterlevels: arcs of constant θ.
    for deg in (20, 45, 90, 120):
        th = math.radians(deg)
        col, w = (BLUE, 1.2) if deg != 90 else (BLUE, 1.6)
        g.polyline(arc_points(th), col, w)
        top = arc_points(th)[60]
        g.text((top[0] + 0.02, top[1] + 0.08), f"θ = {deg}°", BLUE, 13)
    # The sampled arc θ = 60°, with x1 at β = 0.65 θ.
    theta = math.radians(60)
    beta = 0.65 * theta
    alpha = theta - beta
    g.polyline(arc_points(theta), ORANGE, 2.2)
    g.polyline(arc_points(theta, lower=True), ORANGE, 1.2, dash="6 4")
    d1 = s * math.sin(beta) / math.sin(theta)
    d2 = s * math.sin(alpha) / math.sin(theta)
    x1 = (x0[0] + d1 * math.cos(alpha), d1 * math.sin(alpha))
    # Triangle.
    g.line(x0, x1, INK, 2)
    g.line(x1, x2, INK, 2)
    g.line(x0, x2, INK, 2)
    # Extension of x0 → x1 beyond x1, and the deflection θ between it and x1 → x2.
    w1 = ((x1[0] - x0[0]) / d1, (x1[1] - x0[1]) / d1)
    ext = (x1[0] + 0.55 * w1[0], x1[1] + 0.55 * w1[1])
    g.line(x1, ext, INK, 1.2, dash="4 3")
    a_ext = math.atan2(w1[1], w1[0])
    a_to2 = math.atan2(x2[1] - x1[1], x2[0] - x1[0])
    g.angle(x1, 0.32, a_to2, a_ext, ORANGE, 2)
    mid = 0.5 * (a_to2 + a_ext)
    g.text((x1[0] + 0.44 * math.cos(mid), x1[1] + 0.44 * math.sin(mid)), "θ", ORANGE, 20, style="italic")
    # α at x0, β at x2.
    g.angle(x0, 0.38, 0, alpha, GREEN, 1.8)
    g.text((x0[0] + 0.5 * math.cos(alpha / 2), 0.5 * math.sin(alpha / 2)), "α", GREEN, 18, style="italic")
    g.angle(x2, 0.5, math.pi - beta, math.pi, GREEN, 1.8)
    g.text((x2[0] - 0.62 * math.cos(beta / 2), 0.62 * math.sin(beta / 2)), "β", GREEN, 18, style="italic")
    # Foot of x1 on the axis: t = d1 cos α / s.
    foot = (x1[0], 0.0)
    g.line(x1, foot, MUTED, 1, dash="3 3")
    g.text((x0[0] + 0.5 * (foot[0] - x0[0]), -0.1), "t·s", MUTED, 13)
    # Labels.
    g.dot(x0)
    g.dot(x2)
    g.dot(x1, ORANGE)
    g.text((x0[0] - 0.12, -0.1), "x₀", INK, 18)
    g.text((x2[0] + 0.12, -0.1), "x₂", INK, 18)
    g.text((x1[0] - 0.05, x1[1] + 0.12), "x₁", ORANGE, 18)
    g.text((x0[0] + 0.5 * (x1[0] - x0[0]) - 0.12, 0.5 * x1[1] + 0.06), "d₁", INK, 15)
    g.text((x1[0] + 0.5 * (x2[0] - x1[0]) + 0.1, 0.5 * x1[1] + 0.06), "d₂", INK, 15)
    g.text((0.55, -0.1), "s", INK, 15, style="italic")
    g.arrow((1.55, 0), (1.85, 0), MUTED, 1.2)
    g.text((1.87, 0.09), "e", MUTED, 15, style="italic")
    # φ: the triangle's plane turns about the axis.
    g.items.append(
        '<ellipse cx="{:.1f}" cy="{:.1f}" rx="9" ry="24" fill="none" stroke="{}" stroke-width="1.2"/>'.format(
            *g.p(1.7, 0), MUTED
        )
    )
    g.text((1.7, 0.26), "φ", MUTED, 15, style="italic")
    g.text((0, -0.86), "Thales ball: θ &lt; π/2", BLUE, 13)
    g.text((0, -0.4), "θ = 60°, turned by φ = π", ORANGE, 13)
    g.save(path, "The triangle x0 x1 x2 on its circumcircle, and arcs of constant deflection θ")


def equiangular(path):
    g = Svg(720, 330, 85, (60, 215))
    # A ray from x2 along ω (drawn horizontally), the light point x0 above it.
    x2 = (0.0, 0.0)
    delta, dist = 3.6, 1.6
    x0 = (delta, dist)
    ta, tb = 0.9, 6.6
    t = 1.6
    g.line((ta, 0), (tb, 0), INK, 3)
    g.line(x2, (ta, 0), MUTED, 1.2, dash="4 3")
    g.arrow((tb, 0), (tb + 0.6, 0), MUTED, 1.2)
    g.text((tb + 0.7, 0.22), "ω", MUTED, 16, style="italic")
    foot = (delta, 0)
    g.line(x0, foot, MUTED, 1.2, dash="4 3")
    g.text((delta + 0.17, 0.45), "D", MUTED, 16, style="italic")
    # Angles at x0 from the perpendicular: θa to the segment's start, θb to its end.
    down = -math.pi / 2
    th_a = math.atan2(ta - delta, dist)
    th_b = math.atan2(tb - delta, dist)
    g.line(x0, (ta, 0), GREEN, 1.2)
    g.line(x0, (tb, 0), GREEN, 1.2)
    g.angle(x0, 0.85, down + th_a, down, GREEN, 1.6)
    mid = down + 0.5 * th_a
    g.text((x0[0] + 1.12 * math.cos(mid), x0[1] + 1.12 * math.sin(mid)), SUB("θ", "a"), GREEN, 15)
    g.angle(x0, 0.6, down, down + th_b, GREEN, 1.6)
    mid = down + 0.5 * th_b
    g.text((x0[0] + 0.85 * math.cos(mid), x0[1] + 0.85 * math.sin(mid)), SUB("θ", "b"), GREEN, 15)
    # The sampled vertex.
    x1 = (t, 0.0)
    g.line(x0, x1, ORANGE, 2)
    g.text((0.5 * (x0[0] + x1[0]) - 0.3, 0.5 * x0[1] + 0.15), "d₁", ORANGE, 15)
    # Ticks and labels along the ray.
    for xx, lab in ((ta, SUB("t", "a")), (tb, SUB("t", "b")), (delta, "Δ")):
        g.line((xx, -0.08), (xx, 0.08), INK, 1.5)
        g.text((xx, -0.3), lab, INK, 15)
    g.text((t, -0.3), "t", ORANGE, 15, style="italic")
    g.line((t, -0.62), (delta, -0.62), MUTED, 1)
    g.text((0.5 * (t + delta), -0.8), "v = t − Δ", MUTED, 13)
    g.line((0, -1.02), (t, -1.02), MUTED, 1)
    g.text((0.5 * t, -1.2), "d₂ = t", MUTED, 13)
    g.dot(x2)
    g.dot(x0)
    g.dot(x1, ORANGE)
    g.text((-0.05, 0.28), "x₂", INK, 18)
    g.text((x0[0], x0[1] + 0.28), "x₀", INK, 18)
    g.text((x1[0] + 0.22, 0.26), "x₁", ORANGE, 18)
    g.text((5.1, -0.3), "in the medium", MUTED, 12)
    g.save(path, "Equiangular sampling along a ray from x2 towards the light point x0")


def SUB(base, sub):
    """Text with a subscript, as SVG tspans."""
    return f'{base}<tspan font-size="11" dy="4">{sub}</tspan>'


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    circumcircle(os.path.join(here, "math-circumcircle.svg"))
    equiangular(os.path.join(here, "math-equiangular.svg"))
