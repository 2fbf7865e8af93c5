"""fq.add_noise and fq.metrics: the noise and error measures of fqfilter."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _fq


def add_noise(V: ArrayLike, F: ArrayLike, sigma: float, seed: int = 1) -> NDArray[np.floating]:
    """Add Gaussian noise to vertex positions, as ``fqfilter --noise`` does.

    Parameters
    ----------
    V : array_like of shape (n, 3)
        Vertex positions.
    F : array_like of shape (m, 3)
        Triangles as vertex indices in 0..n-1 (they give the mean edge length).
    sigma : float
        Standard deviation of the noise on each coordinate, in mean edge lengths.
    seed : int, default 1
        Seed of the generator: the same seed gives the same noise on every machine.

    Returns
    -------
    numpy.ndarray of shape (n, 3)
        ``V`` plus the noise, float64 when ``V`` is float64, else float32. ``V`` is not changed.

    Raises
    ------
    ValueError
        A wrong shape or dtype, or an index out of range.
    """
    return _fq.add_noise(V, F, float(sigma), int(seed))


def metrics(V_ref: ArrayLike, F: ArrayLike, V: ArrayLike) -> dict[str, float]:
    """Errors of positions ``V`` against the reference mesh (V_ref, F), as in fqfilter's JSON.

    Parameters
    ----------
    V_ref : array_like of shape (n, 3)
        Positions of the clean reference mesh.
    F : array_like of shape (m, 3)
        Triangles of both meshes.
    V : array_like of shape (n, 3)
        The positions to measure (same vertex order as ``V_ref``).

    Returns
    -------
    dict
        ``rmse_over_diagonal``, ``surface_rms_over_diagonal``, ``surface_max_over_diagonal``
        (vertex and surface distances over the bounding-box diagonal), ``mfne_rad`` and
        ``mfne_deg`` (mean face-normal error) and ``faces_skipped`` (degenerate faces).

    Raises
    ------
    ValueError
        Shapes that differ, a wrong dtype, or an index out of range.
    """
    return _fq.metrics(V_ref, F, V)
