"""The result of a fit: the best sample, intervals, correlations, residuals and what answered.

Public objects
--------------
FitResult
    ``sample`` (the best SandSample), ``interval(name, level)``, ``correlation``, ``residual``,
    ``model`` (the forward model that answered), ``engine_check``, ``to_xarray()``,
    ``to_toml()``, ``save(path)``, ``plot(path)``, ``summary()``.
FIT_FORMAT
    The ``format`` key of the TOML a FitResult writes.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from sandlight.errors import ParameterError
from sandlight.physics.powder import Powder
from sandlight.retrieval.engine_check import EngineCheck
from sandlight.retrieval.fitting import Optimum
from sandlight.retrieval.identifiability import NotIdentifiableError, is_flat
from sandlight.retrieval.observation import Observation
from sandlight.retrieval.posterior import LaplacePosterior, SampledPosterior
from sandlight.retrieval.powder_forward import PowderSpace
from sandlight.retrieval.space import ParameterSpace
from sandlight.sample import SandSample

__all__ = ["FitResult", "FIT_FORMAT"]

FIT_FORMAT = "sandlight-fit"
_LEVEL = 0.95


@dataclass(frozen=True)
class FitResult:
    """A fitted sample and its uncertainty (see :func:`sandlight.fit`).

    Attributes
    ----------
    sample : SandSample or Powder
        The maximum-likelihood sample (free parameters at the optimum, the rest as given); a
        :class:`~sandlight.physics.powder.Powder` for a powder fit (``forward='powder'``).
    free : tuple of str
    estimate : dict of str to float
        The free parameters at the optimum.
    posterior : LaplacePosterior or SampledPosterior
    max_delta_chi2 : ndarray (p,)
        Largest −2 Δlog L along each parameter's range (identifiability scan).
    observation : Observation
        What was fitted (channels, values, noise).
    optimum : Optimum
    model : str
        The forward model that answered (a bank model's name and error, or the engine).
    method : {'bank', 'engine'}
    sigma : float
        Measurement noise used: as given (its RMS) or estimated from the residuals.
    sigma_estimated : bool
    space : ParameterSpace or PowderSpace
        Free parameters and their bounds (the sample domain ∩ the model's training domain), in
        the fit's coordinates (a powder's diameter in log10 µm; ``space.physical`` maps back).
    chi2 : float
        rᵀ C⁻¹ r at the optimum (about n − p for a fit whose error budget is right).
    candidates : dict of str to float
        −log L of every forward model tried; the lowest answered.
    engine_check : EngineCheck or None
        The Monte Carlo check at the optimum of a predictor fit.
    """

    sample: SandSample | Powder
    free: tuple[str, ...]
    estimate: dict
    posterior: LaplacePosterior | SampledPosterior
    max_delta_chi2: np.ndarray
    observation: Observation
    optimum: Optimum
    model: str
    method: str
    sigma: float
    sigma_estimated: bool
    space: ParameterSpace | PowderSpace
    chi2: float
    candidates: dict = field(default_factory=dict)
    engine_check: EngineCheck | None = None

    def _index(self, name: str) -> int:
        if name not in self.free:
            raise ParameterError("name", name, f"one of the free parameters {list(self.free)}")
        return self.free.index(name)

    def identifiable(self, name: str, level: float = _LEVEL) -> bool:
        """False when the likelihood is flat over the parameter's whole range at ``level``."""
        return not is_flat(float(self.max_delta_chi2[self._index(name)]), _check_level(level))

    def interval(self, name: str, level: float = _LEVEL) -> tuple[float, float]:
        """Central posterior interval (low, high) of a free parameter at ``level`` in (0, 1).

        Raises
        ------
        NotIdentifiableError
            The data do not constrain the parameter: its likelihood is flat over its range.
        """
        i = self._index(name)
        level = _check_level(level)
        if not self.identifiable(name, level):
            lo, hi = self._bounds(i)
            raise NotIdentifiableError(
                f"{name} is not identifiable from this spectrum: the likelihood is flat over its whole "
                f"range [{lo:g}, {hi:g}] (largest −2 Δlog L {self.max_delta_chi2[i]:.2f} < the "
                f"{level:g} threshold); fix it (fixed={{'{name}': ...}}) or add data that constrain it"
            )
        return self._physical(i, self.posterior.interval(i, level))

    def _physical(self, i: int, pair: tuple[float, float]) -> tuple[float, float]:
        return (self.space.physical(i, pair[0]), self.space.physical(i, pair[1]))

    def _bounds(self, i: int) -> tuple[float, float]:
        """Bounds of free parameter ``i`` in physical units."""
        return self._physical(i, (self.space.low[i], self.space.high[i]))

    def _sample_table(self) -> dict:
        """The fitted sample's parameters: ``SandSample.to_dict`` or ``Powder.describe``."""
        return self.sample.describe() if isinstance(self.sample, Powder) else self.sample.to_dict()

    @property
    def correlation(self) -> xr.DataArray:
        """Posterior correlation matrix of the free parameters."""
        return xr.DataArray(
            self.posterior.correlation,
            dims=("parameter", "parameter_2"),
            coords={"parameter": list(self.free), "parameter_2": list(self.free)},
            name="correlation",
        )

    @property
    def residual(self) -> xr.DataArray:
        """Measured − fitted, per channel (wavelength or band)."""
        return self._channel(self.optimum.residual, "residual", "measured − fitted reflectance")

    def _channel(self, values: np.ndarray, name: str, long_name: str) -> xr.DataArray:
        obs = self.observation
        return xr.DataArray(
            np.asarray(values, float),
            dims="channel",
            coords={"channel": list(obs.labels), "centre_nm": ("channel", obs.centres_nm, {"units": "nm"})},
            name=name,
            attrs={"long_name": long_name, "units": "1"},
        )

    # -- export ---------------------------------------------------------------------------------
    def _rows(self) -> list[dict]:
        rows = []
        for i, name in enumerate(self.free):
            ok = self.identifiable(name)
            lo, hi = self._physical(i, self.posterior.interval(i, _LEVEL)) if ok else (math.nan, math.nan)
            bound_low, bound_high = self._bounds(i)
            rows.append(
                {
                    "name": name,
                    "estimate": float(self.estimate[name]),
                    "low_95": lo,
                    "high_95": hi,
                    "sd": float(self.posterior.sd[i]),
                    "identifiable": ok,
                    "bound_low": bound_low,
                    "bound_high": bound_high,
                }
            )
        return rows

    def to_xarray(self) -> xr.Dataset:
        """The fit as a Dataset: measured, fitted, residual, noise on ``channel``; estimates and
        95 % intervals on ``parameter``; the correlation matrix."""
        obs = self.observation
        rows = self._rows()
        ds = xr.Dataset(
            {
                "measured": self._channel(obs.values, "measured", "measured reflectance"),
                "fitted": self._channel(self.optimum.model, "fitted", "fitted reflectance"),
                "residual": self.residual,
                "estimate": ("parameter", [r["estimate"] for r in rows]),
                "low_95": ("parameter", [r["low_95"] for r in rows]),
                "high_95": ("parameter", [r["high_95"] for r in rows]),
                "identifiable": ("parameter", [r["identifiable"] for r in rows]),
                "correlation": self.correlation,
            },
            coords={"parameter": list(self.free)},
        )
        ds.attrs.update(
            {
                "title": "sandlight fit of sample parameters to a measured spectrum",
                "model": self.model,
                "method": self.method,
                "posterior": self.posterior.kind,
                "sigma": self.sigma,
                "sigma_estimated": int(self.sigma_estimated),
                "space": obs.space,
                "sample": json.dumps(self._sample_table()),
                "engine_check": self.engine_check.summary() if self.engine_check else "",
            }
        )
        return ds

    def to_toml(self) -> str:
        """The fit as TOML: ``[sample]`` (every parameter; ``SandSample.from_dict`` reads it; a
        powder fit writes ``[powder]``, ``Powder.describe``), ``sd`` in the fit's coordinates,
        ``[fit]`` and one ``[parameters.NAME]`` table per free parameter."""
        lines = [f'format = "{FIT_FORMAT}"', "", "[fit]"]
        fit = {
            "model": self.model,
            "method": self.method,
            "posterior": self.posterior.kind,
            "space": self.observation.space,
            "channels": self.observation.size,
            "sigma": self.sigma,
            "sigma_estimated": self.sigma_estimated,
            "residual_rms": float(np.sqrt(np.mean(self.optimum.residual**2))),
            "chi2": self.chi2,
        }
        if self.engine_check:
            fit["engine_check_rms_error"] = self.engine_check.rms_error
            fit["engine_check_consistent"] = self.engine_check.consistent
        lines += [f"{k} = {_toml(v)}" for k, v in fit.items()]
        for r in self._rows():
            lines += ["", f"[parameters.{r['name']}]"]
            lines += [
                f"{k} = {_toml(v)}"
                for k, v in r.items()
                if k != "name" and not (isinstance(v, float) and math.isnan(v))
            ]
        lines += ["", "[correlation]"]
        corr = self.posterior.correlation
        lines += [f"{n} = [{', '.join(_toml(float(c)) for c in corr[i])}]" for i, n in enumerate(self.free)]
        lines += ["", "[powder]" if isinstance(self.sample, Powder) else "[sample]"]
        lines += [f"{k} = {_toml(v)}" for k, v in self._sample_table().items()]
        return "\n".join(lines) + "\n"

    def save(self, path: str | os.PathLike) -> None:
        """Write `to_toml` to ``path`` atomically."""
        from sandlight.io import write_atomically

        text = self.to_toml()
        write_atomically(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))

    def summary(self) -> str:
        lines = [f"fit by {self.model}; {self.observation.size} channels ({self.observation.space} space)"]
        what = "estimated from the residuals" if self.sigma_estimated else "as given"
        lines.append(f"measurement noise σ = {self.sigma:.4g} ({what}); posterior: {self.posterior.kind}")
        if isinstance(self.posterior, SampledPosterior):
            p = self.posterior
            state = "converged" if p.converged else "NOT converged (run longer)"
            lines.append(
                f"emcee: {p.steps} steps per walker kept, autocorrelation {p.autocorrelation_steps:.0f} steps, "
                f"acceptance {p.acceptance:.2f}: {state}"
            )
        for r in self._rows():
            if r["identifiable"]:
                lines.append(f"  {r['name']} = {r['estimate']:.4g}  (95 %: {r['low_95']:.4g} – {r['high_95']:.4g})")
            else:
                lines.append(
                    f"  {r['name']}: not identifiable (flat likelihood over [{r['bound_low']:g}, {r['bound_high']:g}])"
                )
        if self.engine_check:
            lines.append(self.engine_check.summary())
        return "\n".join(lines)

    def plot(self, path: str | os.PathLike, *, title: str | None = None) -> None:
        """Measured and fitted values with the residual below, to a PNG written atomically."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from sandlight.io import atomic_path

        obs = self.observation
        x = obs.centres_nm
        fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5), dpi=120, sharex=True, height_ratios=(3, 1))
        top.plot(x, obs.values, "o", ms=4, color="k", label="measured")
        top.plot(
            x,
            self.optimum.model,
            "-",
            color="C3",
            label=f"fitted ({'predictor' if self.method == 'bank' else 'engine'})",
        )
        if self.engine_check is not None:
            top.plot(x, self.engine_check.engine, "--", color="C0", label="engine at the optimum")
        top.set_ylabel("reflectance")
        top.legend(fontsize=8)
        top.grid(alpha=0.3)
        bottom.axhline(0, color="0.5", lw=0.8)
        bottom.plot(x, self.optimum.residual, "o-", ms=3, color="C3")
        bottom.fill_between(x, -2 * self.sigma, 2 * self.sigma, color="0.8", label="±2σ noise")
        bottom.set_xlabel("wavelength (nm)")
        bottom.set_ylabel("residual")
        bottom.grid(alpha=0.3)
        top.set_title(title or ", ".join(f"{k} = {v:.3g}" for k, v in self.estimate.items()), fontsize=9)
        fig.tight_layout()
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png")
        plt.close(fig)


def _check_level(level: float) -> float:
    if isinstance(level, bool) or not isinstance(level, (int, float)) or not 0 < level < 1:
        raise ParameterError("level", level, "a probability in (0, 1), e.g. 0.95")
    return float(level)


def _toml(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(value)
