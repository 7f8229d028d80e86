"""The paper's Figure 3 from the model: pure quartz, pure iron oxide and the 98/2 mixture.

Public objects
--------------
FIGURE3_PARTICLE_UM
    The iron-oxide particle size of the figure (2.5 µm).
powder_reflectance
    Reflectance of a powder of one pure material (an iron-oxide end-member, which a
    :class:`~sandlight.SandSample` cannot describe; :class:`sandlight.physics.powder.Powder`).
figure3_spectra, FIGURE3_MEASURED, plot_figure3
    The model spectra, their measured counterparts and the two-panel plot.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy.typing as npt

from sandlight.errors import ParameterError
from sandlight.validation.scoring import model_wavelengths_nm

if TYPE_CHECKING:
    from sandlight.engine import ReflectanceResult

__all__ = ["FIGURE3_PARTICLE_UM", "FIGURE3_MEASURED", "powder_reflectance", "figure3_spectra", "plot_figure3"]


def powder_reflectance(
    material: str,
    diameter_um: float | tuple[float, float],
    wavelengths_nm: npt.ArrayLike,
    *,
    rays: int,
    porosity: float = 0.45,
    aspect_ratio: float = 1.0,
    seed: int = 0,
    progress: bool = False,
) -> ReflectanceResult:
    """Directional-hemispherical reflectance at normal incidence of a dry powder of one pure
    material: :func:`sandlight.reflectance` of a :class:`sandlight.physics.powder.Powder`.

    ``material``, ``diameter_um`` (µm), ``porosity`` and ``aspect_ratio`` are the powder's (see
    :class:`~sandlight.physics.powder.Powder`); ``wavelengths_nm`` (nm, in [350, 2500]),
    ``rays`` (per wavelength) and ``seed`` the run's. Returns a ``sandlight.ReflectanceResult``
    whose ``sample`` records the powder's description.
    """
    from sandlight.engine import reflectance
    from sandlight.physics.powder import Powder

    powder = Powder(material, diameter_um, porosity, aspect_ratio)
    return reflectance(powder, wavelengths_nm, rays=rays, seed=seed, progress=progress)


#: Size of the iron-oxide particles of the figure (µm), pure and in the mixture.
FIGURE3_PARTICLE_UM = 2.5


def figure3_spectra(
    *, rays: int, wavelengths_nm: npt.ArrayLike | None = None, seed: int = 0, progress: bool = False
) -> dict:
    """Model spectra of the paper's Figure 3: pure quartz, pure iron oxide and the 98/2 mixture.

    The quartz is the host of the ``gds76-hematite-quartz`` preset (that preset with no iron
    oxide); the mixtures are that preset with 2 wt% hematite or 2 wt% goethite as separate
    particles of 2.5 µm; the pure iron oxides are powders of the same 2.5 µm particles at the
    preset's porosity (:func:`powder_reflectance`).

    Returns
    -------
    dict
        ``{"wavelengths_nm": ndarray, "quartz": result, "hematite": {"powder": result,
        "mixture": result}, "goethite": {...}}`` with :class:`sandlight.ReflectanceResult` values.
    """
    from sandlight.engine import reflectance
    from sandlight.sample import SandSample

    wl = model_wavelengths_nm(wavelengths_nm)
    base = SandSample.preset("gds76-hematite-quartz").replace(iron_oxide_particle_size_um=FIGURE3_PARTICLE_UM)
    out = {
        "wavelengths_nm": wl,
        "quartz": reflectance(base.replace(iron_oxide=0.0), wl, rays=rays, seed=seed, progress=progress),
    }
    for mineral, ratio in (("hematite", 1.0), ("goethite", 0.0)):
        out[mineral] = {
            "powder": powder_reflectance(
                mineral, FIGURE3_PARTICLE_UM, wl, rays=rays, porosity=base.porosity, seed=seed, progress=progress
            ),
            "mixture": reflectance(
                base.replace(iron_oxide=0.02, hematite_ratio=ratio), wl, rays=rays, seed=seed, progress=progress
            ),
        }
    return out


# Measured counterparts drawn in grey (USGS splib07a), where the library has them.
FIGURE3_MEASURED = {
    "hematite": {
        "quartz": "Quartz_HS32.4B_BECKa_AREF",
        "powder": "Hematite_GDS27_BECKa_AREF",
        "mixture": "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
    },
    "goethite": {"quartz": "Quartz_HS32.4B_BECKa_AREF", "powder": "Goethite_WS222_Medium_Gr._BECKa_AREF"},
}


def plot_figure3(spectra: dict, path: str | os.PathLike, *, measured: bool = True) -> None:
    """Two panels (hematite, goethite) in the style of the paper's Figure 3, to a PNG (atomic).

    Dotted: pure quartz; dashed: pure iron oxide; solid: 98 wt% quartz + 2 wt% iron oxide.
    Coloured: model; grey: the USGS measurements of :data:`FIGURE3_MEASURED` when ``measured``
    and the spectra are found (:func:`sandlight.measured.usgs_library`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sandlight.io import atomic_path
    from sandlight.measured import read_usgs, usgs_library

    wl = spectra["wavelengths_nm"]
    styles = {"quartz": ":", "powder": "--", "mixture": "-"}
    names = {"quartz": "pure quartz", "powder": "pure {m} (2.5 µm)", "mixture": "98 wt% quartz + 2 wt% {m}"}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120, sharey=True)
    for ax, mineral, colour in zip(axes, ("hematite", "goethite"), ("C3", "C1")):
        curves = {"quartz": spectra["quartz"], **spectra[mineral]}
        for key, r in curves.items():
            ax.plot(wl, r.values, styles[key], color=colour, lw=1.6, label="model: " + names[key].format(m=mineral))
        if measured:
            for key, stem in FIGURE3_MEASURED[mineral].items():
                try:
                    m = read_usgs(usgs_library(stem))
                except (FileNotFoundError, ParameterError):
                    continue
                m = m[(m["wavelength"].values >= 350) & (m["wavelength"].values <= 2500)]
                ax.plot(
                    m["wavelength"].values,
                    m.values,
                    styles[key],
                    color="0.55",
                    lw=1,
                    label=f"measured: {stem.replace('_AREF', '')}",
                )
        ax.set_title(
            f"iron oxide = {mineral}" + (" (provisional optical constants)" if mineral == "goethite" else ""),
            fontsize=9,
        )
        ax.set_xlabel("wavelength (nm)")
        ax.set_xlim(350, 2500)
        ax.set_ylim(0, 1)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    axes[0].set_ylabel("directional-hemispherical reflectance")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
