"""The `sand` BSDF for Mitsuba 3, in Dr.Jit array operations (traced into the llvm/cuda kernels).

Public objects
--------------
bsdf_class
    The plugin class for the current Mitsuba variant (a subclass of ``mitsuba.BSDF``).
plugin_tables
    The `PluginTables` of a `SandSpec` (cached).

Conventions. Mitsuba's ``si.wi`` points to the previous path vertex (the camera side) and
``wo`` to the next (the light side), both in the local shading frame (z = normal). The BRDF is
reciprocal, so f(si.wi, wo) = `SandAppearance.brdf`(wi=si.wi, wo=wo) needs no swap. The
sampler draws ``wo`` given ``si.wi`` exactly in proportion to f cos θ_o at the reference spectrum
(`sandlight.mitsuba.tables`, "Sampling tables"): pdf = f_ref cos θ_o / A_ref, A_ref the reference
albedo of the given direction. ``eval`` returns f cos θ_o, ``sample`` the weight
f cos θ_o / pdf = A_ref f / f_ref, as Mitsuba expects. Both sides must be above the surface
(one-sided, like Mitsuba's ``diffuse``).

The evaluation is `sandlight.gonio.brdf.interpolate_band_grid` (trilinear in μ_i, μ_o, Δφ on
the band grid, held below the lowest node) plus the combination's diffuse term, for every shape
of a level blended per wavelength as `sandlight.appearance.shapes` does, and blended linearly
between the levels around the textured parameter's value. Mitsuba computes in float32:
the plugin agrees with `SandAppearance` to float32 rounding (tested), except exactly at the cap's
step (its two nodes 10⁻⁸ apart in μ coincide in float32).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from sandlight.mitsuba.parameters import PLUGIN_NAME, PluginParameterError, SandSpec, appearance_levels
from sandlight.mitsuba.tables import PluginTables

__all__ = ["bsdf_class", "plugin_tables", "LUMINANCE_WEIGHTS", "NEWTON_STEPS"]

#: Linear-sRGB luminance weights (IEC 61966-2-1): the mono variants' weight from the RGB ones.
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)
#: Newton–bisection steps inverting a cell's cubic CDF in μ (float32: converged after ~5).
NEWTON_STEPS = 8


@functools.lru_cache(maxsize=32)
def plugin_tables(spec: SandSpec) -> PluginTables:
    """The flat tables of ``spec``'s appearances (`PluginTables.build`)."""
    return PluginTables.build(appearance_levels(spec), spec.level_values or None)


@functools.cache
def bsdf_class(variant: str) -> type:
    """The `sand` plugin class for Mitsuba variant ``variant`` (the current one; each variant
    has its own ``mitsuba.BSDF`` base class)."""
    import drjit as dr

    import mitsuba as mi

    if mi.variant() != variant:
        raise RuntimeError(f"bsdf_class({variant!r}) called while the Mitsuba variant is {mi.variant()!r}")

    class SandBSDF(mi.BSDF):
        """The explicit spectral BRDF of sand (sandlight.appearance.SandAppearance) as a BSDF."""

        def __init__(self, props: mi.Properties) -> None:
            mi.BSDF.__init__(self, props)
            values, textures = {}, {}
            for name in props.keys():  # noqa: SIM118 (a mitsuba.Properties, not a dict)
                if name in ("type", "id"):
                    continue
                v = props[name]
                if isinstance(v, mi.Texture):
                    textures[name] = v
                elif isinstance(v, mi.Object):
                    raise PluginParameterError(name, type(v).__name__, "a number, a string or a texture")
                else:
                    values[name] = v
            self.spec = SandSpec.parse(values, tuple(textures))
            self.texture = textures.get(self.spec.varied) if self.spec.varied else None
            self._upload(plugin_tables(self.spec))
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            if self.texture is not None:
                flags = flags | mi.BSDFFlags.SpatiallyVarying
            self.m_components = [flags]
            self.m_flags = flags

        # ---- data ------------------------------------------------------------------------
        def _upload(self, t: PluginTables) -> None:
            self.t = t
            self.n, self.L, self.K, self.S = t.n_nodes, t.slices, t.n_levels, t.shapes
            self.asc = [float(v) for v in t.nodes_ascending]
            self.asc_array = mi.Float(np.asarray(t.nodes_ascending, dtype=np.float32))
            self.grid = mi.Float(t.grid.astype(np.float32))
            self.profile = mi.Float(t.profile.astype(np.float32))
            self.reflectance = mi.Float(t.reflectance.astype(np.float32))
            self.r0 = mi.Float(t.reference_reflectance.astype(np.float32))
            self.log_anchor = mi.Float(t.log_anchor.astype(np.float32))
            self.anchor_range = mi.Float(t.anchor_range.astype(np.float32))
            self.reference_grid = mi.Float(t.reference_grid.astype(np.float32))
            self.M = t.n_wavelengths
            rgb_a, rgb_b = t.rgb_a, t.rgb_b
            if mi.is_monochromatic:  # mono variants: luminance
                rgb_a, rgb_b = rgb_a @ np.array(LUMINANCE_WEIGHTS), rgb_b @ np.array(LUMINANCE_WEIGHTS)
            self.colour_a = mi.Float(np.ravel(rgb_a).astype(np.float32))
            self.colour_b = mi.Float(np.ravel(rgb_b).astype(np.float32))
            self.row_cdf = mi.Float(t.row_cdf.astype(np.float32))
            self.row_albedo = mi.Float(t.row_albedo.astype(np.float32))
            self.last_cell = mi.UInt32(t.last_cell.astype(np.uint32))

        # ---- helpers ---------------------------------------------------------------------
        def _level(self, si: mi.SurfaceInteraction3f, active: mi.Bool) -> tuple:
            """(k0, k1, w): the two levels around the texture's value and the weight of k1."""
            if self.K == 1:
                return mi.UInt32(0), mi.UInt32(0), mi.Float(0.0)
            lo, hi = float(self.t.levels[0]), float(self.t.levels[-1])
            value = self.texture.eval_1(si, active)
            x = (dr.clip(value, lo, hi) - lo) * ((self.K - 1) / (hi - lo))
            k0 = mi.UInt32(dr.clip(dr.floor(x), 0, self.K - 2))
            return k0, k0 + 1, x - mi.Float(k0)

        def _bracket(self, mu: mi.Float) -> tuple:
            """(q0, q1, t): the nodes (band-grid order) around μ and the weight of q1 (`mu_bracket`)."""
            n = self.n
            m = dr.clip(mu, self.asc[0], self.asc[-1])
            j = mi.UInt32(0)
            for q in range(1, n - 1):  # j: the last node ≤ μ, in [0, n − 2]
                j += dr.select(m >= self.asc[q], mi.UInt32(1), mi.UInt32(0))
            lo = dr.gather(mi.Float, self.asc_array, j)
            hi = dr.gather(mi.Float, self.asc_array, j + 1)
            t = dr.clip((m - lo) / (hi - lo), 0.0, 1.0)
            return (n - 1) - j, (n - 2) - j, t

        @staticmethod
        def _dphi(wi: mi.Vector3f, wo: mi.Vector3f) -> mi.Float:
            return dr.atan2(wo.y, wo.x) - dr.atan2(wi.y, wi.x)

        def _azimuth(self, dphi: mi.Float) -> tuple:
            """(j0, j1, t): the Δφ nodes around Δφ and the weight of j1 (periodic)."""
            L = self.L
            x = dphi * (L / (2.0 * math.pi))
            x = x - L * dr.floor(x / L)
            j0 = mi.UInt32(dr.floor(x))
            t = x - mi.Float(j0)
            j0 = dr.select(j0 >= L, j0 - L, j0)  # x can round up to exactly L
            return j0, dr.select(j0 + 1 >= L, mi.UInt32(0), j0 + 1), t

        def _interpolate(self, table: mi.Float, layer: mi.UInt32, qi: tuple, qo: tuple, az: tuple, active: mi.Bool):
            """The trilinear interpolant of ``table``'s n × n × L grid number ``layer``."""
            n, L = self.n, self.L
            k0, k1, tk = az
            f = mi.Float(0.0)
            for b_in, w_in in ((qi[0], 1.0 - qi[2]), (qi[1], qi[2])):
                for b_out, w_out in ((qo[0], 1.0 - qo[2]), (qo[1], qo[2])):
                    row = ((layer * n + b_in) * n + b_out) * L
                    v0 = dr.gather(mi.Float, table, row + k0, active)
                    v1 = dr.gather(mi.Float, table, row + k1, active)
                    f += w_in * w_out * ((1.0 - tk) * v0 + tk * v1)
            return f

        def _spatial(self, layer: mi.UInt32, qi: tuple, qo: tuple, az: tuple, active: mi.Bool) -> tuple:
            """(f̂, P(μ_i) P(μ_o)) of shape ``layer`` = k·S + s (`interpolate_band_grid`)."""
            n = self.n
            p = []
            for q0, q1, t in (qi, qo):
                p0 = dr.gather(mi.Float, self.profile, layer * n + q0, active)
                p1 = dr.gather(mi.Float, self.profile, layer * n + q1, active)
                p.append((1.0 - t) * p0 + t * p1)
            return self._interpolate(self.grid, layer, qi, qo, az, active), p[0] * p[1]

        def _weights(self, k: mi.UInt32, si: mi.SurfaceInteraction3f, active: mi.Bool) -> list:
            """[(a_s, b_s)] of level k's S shapes as Spectrum: at the sampled wavelengths, or
            projected (RGB/mono)."""
            S = self.S
            if not mi.is_spectral:
                c = dr.size_v(mi.Spectrum)
                out = []
                for s in range(S):
                    base = (k * S + s) * c
                    a = mi.Spectrum([dr.gather(mi.Float, self.colour_a, base + i, active) for i in range(c)])
                    b = mi.Spectrum([dr.gather(mi.Float, self.colour_b, base + i, active) for i in range(c)])
                    out.append((a, b))
                return out
            base = k * self.M
            channels = []  # per channel: [(a_s, b_s)] for s in range(S)
            for c in range(dr.size_v(mi.Spectrum)):
                x = dr.clip(si.wavelengths[c] - self.t.wavelength0_nm, 0.0, self.M - 1.0)
                i0 = mi.UInt32(dr.clip(dr.floor(x), 0, self.M - 2))
                tw = x - mi.Float(i0)
                r0_c = dr.gather(mi.Float, self.reflectance, base + i0, active)
                r1_c = dr.gather(mi.Float, self.reflectance, base + i0 + 1, active)
                channels.append(self._shape_weights(k, (1.0 - tw) * r0_c + tw * r1_c, active))
            return [
                (mi.Spectrum([ch[s][0] for ch in channels]), mi.Spectrum([ch[s][1] for ch in channels]))
                for s in range(S)
            ]

        def _shape_weights(self, k: mi.UInt32, r: mi.Float, active: mi.Bool) -> list:
            """[(a_s, b_s)] of level k's shapes at reflectance r (`ShapeSeries.weights`): linear in
            log r between the anchors around it, each shape's own combination, and inside the
            anchors' range the product r f̂."""
            S = self.S
            if S == 1:
                weights = [mi.Float(1.0)]
                inside = mi.Bool(False)
            else:
                lr = dr.log(dr.maximum(r, 1e-30))
                lo = dr.gather(mi.Float, self.anchor_range, 2 * k, active)
                hi = dr.gather(mi.Float, self.anchor_range, 2 * k + 1, active)
                u = dr.clip(lr, lo, hi)
                j = mi.UInt32(0)
                for s in range(1, S - 1):  # j: the last anchor ≤ u, in [0, S − 2]
                    x_s = dr.gather(mi.Float, self.log_anchor, k * S + s, active)
                    j += dr.select(u >= x_s, mi.UInt32(1), mi.UInt32(0))
                x0 = dr.gather(mi.Float, self.log_anchor, k * S + j, active)
                x1 = dr.gather(mi.Float, self.log_anchor, k * S + j + 1, active)
                t = dr.select(dr.isfinite(x1) & (x1 > x0), (u - x0) / (x1 - x0), 0.0)
                weights = [dr.select(j == s, 1.0 - t, 0.0) + dr.select(j + 1 == s, t, 0.0) for s in range(S)]
                inside = (lr > lo) & (lr < hi)
            out = []
            for s, w in enumerate(weights):
                if self.t.product:
                    a, b = r, mi.Float(0.0)
                else:  # Combination.weights, 'energy': a = min(r, r0), b = (r − r0)/(1 − r0) where r > r0.
                    r0 = dr.gather(mi.Float, self.r0, k * S + s, active)
                    bright = r > r0
                    a = dr.select(bright, r0, r)
                    b = dr.select(bright & (r0 < 1.0), (r - r0) / (1.0 - r0), 0.0)
                out.append((dr.select(inside, w * r, w * a), dr.select(inside, 0.0, w * b)))
            return out

        def _levels(self, si: mi.SurfaceInteraction3f, active: mi.Bool) -> list:
            """[(level, weight)]: the one level, or the two around the texture's value."""
            k0, k1, w = self._level(si, active)
            return [(k0, 1.0 - w), (k1, w)] if self.K > 1 else [(k0, 1.0)]

        def _f(self, si: mi.SurfaceInteraction3f, wo: mi.Vector3f, active: mi.Bool) -> tuple:
            """(f(si.wi, wo, λ), f_ref(si.wi, wo)), sr⁻¹ (no horizon test)."""
            qi, qo = self._bracket(si.wi.z), self._bracket(wo.z)
            az = self._azimuth(self._dphi(si.wi, wo))
            value, ref = mi.Spectrum(0.0), mi.Float(0.0)
            for k, wk in self._levels(si, active):
                for s, (a, b) in enumerate(self._weights(k, si, active)):
                    g, pp = self._spatial(k * self.S + s, qi, qo, az, active)
                    value += wk * (a * g + b * pp)
                ref += wk * self._interpolate(self.reference_grid, k, qi, qo, az, active)
            return value, ref

        def _rows(self, si: mi.SurfaceInteraction3f, active: mi.Bool) -> list:
            """[(level, given-side node, weight w_c, row albedo A_c)] of the blend f_ref = Σ w_c h_c."""
            q0, q1, t = self._bracket(si.wi.z)
            rows = []
            for k, wk in self._levels(si, active):
                for q, wq in ((q0, 1.0 - t), (q1, t)):
                    rows.append((k, q, wk * wq, dr.gather(mi.Float, self.row_albedo, k * self.n + q, active)))
            return rows

        def _pdf(self, si: mi.SurfaceInteraction3f, wo: mi.Vector3f, f_ref: mi.Float, active: mi.Bool) -> mi.Float:
            """f_ref cos θ_o / A_ref (`sandlight.mitsuba.tables`, "Sampling tables"), sr⁻¹."""
            albedo = mi.Float(0.0)
            for _, _, w, a in self._rows(si, active):
                albedo += w * a
            ok = active & (wo.z > 0) & (albedo > 0)
            return dr.select(ok, f_ref * wo.z / albedo, 0.0)

        def _row_value(self, k: mi.UInt32, q: mi.UInt32, i: mi.UInt32, j: mi.UInt32, active: mi.Bool) -> mi.Float:
            """h_{k,q} at ascending sampled-side node i and Δφ node j: the reference grid H_k."""
            n = self.n
            return dr.gather(mi.Float, self.reference_grid, ((k * n + q) * n + (n - 1) - i) * self.L + j, active)

        def _enabled(self, ctx: mi.BSDFContext, si: mi.SurfaceInteraction3f, active: mi.Bool) -> mi.Bool:
            return active & (si.wi.z > 0) & ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0)

        # ---- the BSDF interface -----------------------------------------------------------
        def eval(self, ctx, si, wo, active=True):  # noqa: ANN001, ANN201 (Mitsuba's signature)
            active = self._enabled(ctx, si, active) & (wo.z > 0)
            value, _ = self._f(si, wo, active)
            return dr.select(active, value * wo.z, 0.0)

        def pdf(self, ctx, si, wo, active=True):  # noqa: ANN001, ANN201
            active = self._enabled(ctx, si, active)
            _, ref = self._f(si, wo, active)
            return self._pdf(si, wo, ref, active)

        def eval_pdf(self, ctx, si, wo, active=True):  # noqa: ANN001, ANN201
            active = self._enabled(ctx, si, active)
            value, ref = self._f(si, wo, active)
            return dr.select(active & (wo.z > 0), value * wo.z, 0.0), self._pdf(si, wo, ref, active)

        def sample(self, ctx, si, sample1, sample2, active=True):  # noqa: ANN001, ANN201
            active = self._enabled(ctx, si, active)
            n, L = self.n, self.L
            # The row: c with probability w_c A_c / Σ w A (sample1).
            rows = self._rows(si, active)
            total = mi.Float(0.0)
            for _, _, w, a in rows:
                total += w * a
            u, acc = sample1 * total, mi.Float(0.0)
            k, q = rows[-1][0], rows[-1][1]
            found = mi.Bool(False)
            for kc, qc, w, a in rows:
                acc += w * a
                take = ~found & (u < acc)
                k, q = dr.select(take, kc, k), dr.select(take, qc, q)
                found |= take
            # The cell by W / A (sample2.x); its residual samples Δφ, sample2.y samples μ.
            base = (k * n + q) * (n * L)
            x = sample2.x
            cell = dr.binary_search(0, n * L - 1, lambda i: dr.gather(mi.Float, self.row_cdf, base + i, active) <= x)
            cell = dr.minimum(cell, dr.gather(mi.UInt32, self.last_cell, k * n + q, active))
            hi = dr.gather(mi.Float, self.row_cdf, base + cell, active)
            lo = dr.select(cell > 0, dr.gather(mi.Float, self.row_cdf, base + cell - 1, active & (cell > 0)), 0.0)
            xi_phi = dr.clip(dr.select(hi > lo, (x - lo) / (hi - lo), 0.5), 0.0, 1.0)
            m, j = cell // L, cell % L
            j1 = dr.select(j + 1 >= L, mi.UInt32(0), j + 1)
            i0 = dr.select(m > 0, m - 1, mi.UInt32(0))
            mu0 = dr.select(m > 0, dr.gather(mi.Float, self.asc_array, i0, active), 0.0)
            mu1 = dr.gather(mi.Float, self.asc_array, m, active)
            dmu = mu1 - mu0
            v00, v01 = self._row_value(k, q, i0, j, active), self._row_value(k, q, i0, j1, active)
            v10, v11 = self._row_value(k, q, m, j, active), self._row_value(k, q, m, j1, active)
            # Δφ: the marginal (1 − u) c0 + u c1 on the cell, inverted in closed form.
            c_a, c_b = dmu * (2.0 * mu0 + mu1) / 6.0, dmu * (mu0 + 2.0 * mu1) / 6.0
            c0, c1 = v00 * c_a + v10 * c_b, v01 * c_a + v11 * c_b
            root = dr.sqrt(dr.maximum(c0 * c0 + xi_phi * (c1 * c1 - c0 * c0), 0.0))
            u_phi = dr.select(c0 + root > 0, xi_phi * (c0 + c1) / (c0 + root), xi_phi)
            u_phi = dr.clip(u_phi, 0.0, 1.0)
            # μ: density ∝ ((1 − s) e0 + s e1)(μ0 + s Δμ) on s ∈ [0, 1], its cubic CDF inverted by
            # Newton steps kept inside a shrinking bracket (bisection when a step leaves it).
            e0 = (1.0 - u_phi) * v00 + u_phi * v01
            e1 = (1.0 - u_phi) * v10 + u_phi * v11
            p1, p2, p3 = e0 * mu0, e0 * dmu + (e1 - e0) * mu0, (e1 - e0) * dmu
            target = sample2.y * (p1 + p2 / 2.0 + p3 / 3.0)
            s, s_lo, s_hi = mi.Float(sample2.y), mi.Float(0.0), mi.Float(1.0)
            for _ in range(NEWTON_STEPS):
                g = s * (p1 + s * (p2 / 2.0 + s * p3 / 3.0)) - target
                d = p1 + s * (p2 + s * p3)
                s_lo, s_hi = dr.select(g < 0, s, s_lo), dr.select(g >= 0, s, s_hi)
                step = s - g / d
                inside = (d > 0) & (step > s_lo) & (step < s_hi)
                s = dr.select(inside, step, 0.5 * (s_lo + s_hi))
            mu_o = dr.clip(mu0 + s * dmu, 1e-7, 1.0)
            phi = dr.atan2(si.wi.y, si.wi.x) + (mi.Float(j) + u_phi) * (2.0 * math.pi / L)
            sin_o = dr.safe_sqrt(1.0 - mu_o * mu_o)

            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.Vector3f(sin_o * dr.cos(phi), sin_o * dr.sin(phi), mu_o)
            value, bs.pdf = self.eval_pdf(ctx, si, bs.wo, active)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            active &= bs.pdf > 0
            return bs, dr.select(active, value / bs.pdf, 0.0)

        # ---- parameters ------------------------------------------------------------------
        def traverse(self, callback):  # noqa: ANN001, ANN201
            """The textured parameter's texture, and the sample's other numeric parameters as
            non-differentiable floats (changing one rebuilds the appearances)."""
            if self.texture is not None:
                callback.put(self.spec.varied, self.texture, mi.ParamFlags.NonDifferentiable)
            self.exposed = {
                name: mi.Float(float(value))
                for name, value in self.spec.sample.to_dict().items()
                if name != self.spec.varied and isinstance(value, (int, float)) and math.isfinite(value)
            }
            for name, value in self.exposed.items():
                callback.put(name, value, mi.ParamFlags.NonDifferentiable)

        def parameters_changed(self, keys=None):  # noqa: ANN001, ANN201
            changed = {k: float(self.exposed[k][0]) for k in (keys or []) if k in getattr(self, "exposed", {})}
            if not changed:
                return  # the texture is read at every evaluation; nothing is derived from it
            values = {**self.spec.sample.to_dict(), **changed}
            values.pop(self.spec.varied, None)
            values = {k: v for k, v in values.items() if not (isinstance(v, float) and not math.isfinite(v))}
            values["combination"] = self.spec.combination
            values["shape"] = self.spec.shape
            for name in ("spectral_model", "spatial_model"):
                if getattr(self.spec, name) is not None:
                    values[name] = getattr(self.spec, name)
            if self.spec.varied is not None:
                values.update(
                    levels=len(self.spec.level_values),
                    level_min=self.spec.level_values[0],
                    level_max=self.spec.level_values[-1],
                )
            self.spec = SandSpec.parse(values, (self.spec.varied,) if self.spec.varied else ())
            self._upload(plugin_tables(self.spec))

        def to_string(self) -> str:
            s = self.spec
            varied = f", {s.varied} textured over {len(s.level_values)} levels" if s.varied else ""
            return f"SandBSDF[{PLUGIN_NAME}: {s.sample!r}, combination={s.combination!r}, shape={s.shape!r}{varied}]"

    return SandBSDF
