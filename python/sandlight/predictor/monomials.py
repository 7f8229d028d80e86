"""Fast evaluation of all the monomials of a polynomial basis, blockwise and in place.

The monomials φ(x) are given by their exponents in graded lexicographic order, as
``sklearn.preprocessing.PolynomialFeatures.powers_`` lists them. :func:`monomial_plan` turns the
exponents into a few runs of numpy multiplies, each monomial being a lower-degree one times one
variable; :func:`monomials` applies the plan to a block of inputs, writing into a caller's buffer.
Same values as ``PolynomialFeatures.transform`` (to rounding), in a fraction of its time and
without its temporaries. Used by :class:`sandlight.predictor.SpectralModel`.

Public objects
--------------
monomial_plan
    The runs of multiplies that compute the monomials of given exponents.
monomials
    The monomials of a block of inputs, by a plan.
BLOCK_SAMPLES
    Inputs per block that keep the block's monomials in cache.
"""

from __future__ import annotations

import numpy as np

from sandlight.errors import ParameterError

__all__ = ["monomial_plan", "monomials", "BLOCK_SAMPLES"]

#: Inputs per block: the block's monomials (m × block doubles, 4.5 MB for the 560 cubic monomials
#: of 13 parameters) stay in cache between the products and the matrix product that consumes them.
BLOCK_SAMPLES = 1024


def monomial_plan(powers: np.ndarray) -> tuple:
    """Blocks that compute all monomials from lower-degree ones, for :func:`monomials`.

    Each monomial x^p (p = exponents, total degree g ≥ 1) is its *parent* x^(p − e_v) times x_v,
    with v its first variable. In graded lexicographic order (PolynomialFeatures' order) long
    runs of monomials share v and have consecutive parents, or share the parent and have
    consecutive v; each run is one numpy multiply. Cubic monomials of d variables take about 3d
    multiplies instead of C(d + 3, 3).

    Parameters
    ----------
    powers : array_like of int, shape (m, d)
        Exponents of the m monomials in d variables, the first one the constant 1 (all zeros),
        every other one after the monomial it extends by one variable (true of graded
        lexicographic order, e.g. ``PolynomialFeatures(degree).fit(X).powers_``).

    Returns
    -------
    tuple of (start, stop, parent, parent_step, var, var_step)
        ``F[start:stop] = F[parent : parent + n*parent_step] * X[var : var + n*var_step]``
        (a step of 0 broadcasts one row).

    Raises
    ------
    sandlight.errors.ParameterError
        (a ValueError) ``powers`` not starting with the constant, or a monomial without an
        earlier parent.

    Examples
    --------
    >>> plan = monomial_plan([[0, 0], [1, 0], [0, 1], [2, 0], [1, 1], [0, 2]])   # 1, a, b, a², ab, b²
    >>> x = np.array([[2.0], [3.0]])   # one input (a, b) = (2, 3) as a column
    >>> monomials(x, plan, 6, np.empty((6, 1))).ravel().tolist()
    [1.0, 2.0, 3.0, 4.0, 6.0, 9.0]
    """
    powers = np.asarray(powers, dtype=np.int64)
    lookup = {tuple(p): i for i, p in enumerate(powers)}
    if tuple(np.zeros(powers.shape[1], dtype=np.int64)) != tuple(powers[0]):
        raise ParameterError("powers", powers[0].tolist(), "the first monomial must be the constant 1 (all zeros)")
    links = []
    for f, p in enumerate(powers[1:], start=1):
        v = int(np.flatnonzero(p)[0])
        q = p.copy()
        q[v] -= 1
        parent = lookup.get(tuple(q))
        if parent is None or parent >= f:
            raise ParameterError("powers", p.tolist(), f"a monomial after its parent {q.tolist()}")
        links.append((f, parent, v))
    runs = []
    i = 0
    while i < len(links):
        f, parent, v = links[i]
        j = i + 1
        for pstep, vstep in ((1, 0), (0, 1)):
            j = i + 1
            while j < len(links) and links[j][1] == parent + (j - i) * pstep and links[j][2] == v + (j - i) * vstep:
                j += 1
            if j - i > 1:
                break
        runs.append((f, f + (j - i), parent, pstep if j - i > 1 else 0, v, vstep if j - i > 1 else 0))
        i = j
    return tuple(runs)


def monomials(XT: np.ndarray, plan: tuple, m: int, out: np.ndarray) -> np.ndarray:
    """All m monomials of the columns of ``XT`` (d × c), as an (m × c) array in ``out``.

    Parameters
    ----------
    XT : numpy.ndarray of float64, shape (d, c)
        c inputs as columns (C-contiguous for speed).
    plan : tuple
        :func:`monomial_plan` of the exponents.
    m : int
        Number of monomials (rows of the exponents).
    out : numpy.ndarray of float64, shape (m, ≥ c)
        Buffer, overwritten; reused from block to block. Inputs are not checked (inner loop).

    Returns
    -------
    numpy.ndarray, shape (m, c)
        The view ``out[:, :c]``: row f holds monomial f of every input.
    """
    c = XT.shape[1]
    F = out[:, :c]
    F[0] = 1.0
    for start, stop, parent, pstep, var, vstep in plan:
        n = stop - start
        left = F[parent : parent + n] if pstep else F[parent : parent + 1]
        right = XT[var : var + n] if vstep else XT[var : var + 1]
        np.multiply(left, right, out=F[start:stop])
    return F
