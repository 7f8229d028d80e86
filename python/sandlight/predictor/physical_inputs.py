"""Physical inputs of a network: the lengths the engine derives from a sample's parameters.

The regression's inputs are the sample parameters, each scaled to [−1, 1]. Over every parameter
at once (the broad models) the reflectance depends on some of them only through a few lengths of
the mass balance (:func:`sandlight.physics.composition.length_scales`): the pore space's mean
free path ℓ (all sizes, shapes, separates and the porosity together; a percent of clay outweighs
the sand's surface), the thickness of the iron-oxide coating (iron oxide over that surface), the
water film and the share of water-filled pores (saturation against film saturation, a kink) and
the iron's absorption path inside a grain. A network given only the parameters must learn those
products, quotients and kinks from the draws; given them as extra inputs it need not: on the
broad models' training sets one network's model error falls from 0.0146 to 0.0095 (wet) and
from 0.0106 to 0.0080 (dry), its largest error from 0.125 to 0.050 and from 0.145 to 0.069
(docs/spectral-predictor.md, "Broad models").

The inputs are functions of the model's own parameters only: the domain's varied parameters
from the sample, every other one at the value the domain fixes (else SandSample's default), so a
prediction never depends on a parameter the model was not trained over.
"""

from __future__ import annotations

import numpy as np

from sandlight.physics.composition import length_scales
from sandlight.predictor.domain import Domain
from sandlight.sample import PARAMETERS

__all__ = ["PHYSICAL_INPUTS", "physical_inputs"]

#: The lengths taken (names of :func:`~sandlight.physics.composition.length_scales`), in the
#: order of the inputs.
PHYSICAL_INPUTS = (
    "mean_free_path_mm",
    "coating_thickness_mm",
    "film_thickness_mm",
    "water_filled_probability",
    "core_iron_path_mm",
)
#: Lengths enter as log10(length + floor): the floor (mm, 0.1 nm) keeps a length that vanishes
#: (no coating, a dry sample, no iron inside the grains) finite, below every one that does not.
FLOOR_MM = 1e-7
#: The one input that is not a length (a probability, entered as it is).
_LINEAR = ("water_filled_probability",)


def physical_inputs(values: np.ndarray, codes: np.ndarray, domain: Domain, names: tuple[str, ...]) -> np.ndarray:
    """The physical inputs ``names`` (of :data:`PHYSICAL_INPUTS`) of samples given as a model's
    raw inputs: an array (n, len(names)).

    Parameters
    ----------
    values : ndarray (n, d)
        The domain's varied parameters (``domain.names``, raw units), one row per sample.
    codes : ndarray (n,)
        Iron-oxide form of each row, as codes into ``domain.forms``.
    domain : Domain
        Fixes every parameter that does not vary.
    names : tuple of str
        The inputs wanted, in order.

    Returns
    -------
    ndarray (n, len(names))
        log10(length/mm + FLOOR_MM) of the lengths, the water-filled probability as it is.
    """
    n, columns = values.shape[0], domain.columns(values, codes)
    for p in PARAMETERS:  # one the domain neither varies nor fixes: SandSample's default
        if p.kind == "float":
            columns.setdefault(p.name, np.full(n, float(p.default)))
    lengths = length_scales(columns)
    return np.column_stack([lengths[k] if k in _LINEAR else np.log10(lengths[k] + FLOOR_MM) for k in names]).reshape(
        n, len(names)
    )
