"""fq.add_noise, fq.metrics, fq.scan_error, fq.surface_sample and fq.surface_flicker: the noise and
error measures of fqfilter."""
from __future__ import annotations

import numpy as np
from typing import Any, Iterable

from numpy.typing import ArrayLike, NDArray

from . import _fq


def add_noise(V: ArrayLike, F: ArrayLike, sigma: float, seed: int = 1, kind: str = "iso",
              length: float = 2.0) -> NDArray[np.floating]:
    """Add synthetic noise to vertex positions, as ``fqfilter --noise`` does.

    Parameters
    ----------
    V : array_like of shape (n, 3)
        Vertex positions.
    F : array_like of shape (m, 3)
        Triangles as vertex indices in 0..n-1 (they give the mean edge length).
    sigma : float
        Standard deviation of the noise, in mean edge lengths (on each coordinate for
        ``iso``, along the normal for the others).
    seed : int, default 1
        Seed of the generator: the same seed gives the same noise on every machine.
    kind : {'iso', 'normal', 'depth', 'correlated', 'ripple'}, default 'iso'
        ``fqfilter --noise-kind``: Gaussian on every coordinate; along the vertex normals;
        a range scanner's depth noise along z, growing at grazing angles; noise along the
        normals correlated over ``length`` mean edges; scan-line stripes along x of period
        ``length`` (``eval/noise.h``).
    length : float, default 2.0
        The correlated kind's correlation length, the ripples' period (mean edges).

    Returns
    -------
    numpy.ndarray of shape (n, 3)
        ``V`` plus the noise, float64 when ``V`` is float64, else float32. ``V`` is not changed.

    Raises
    ------
    ValueError
        A wrong shape or dtype, an index out of range, or an unknown kind.
    """
    return _fq.add_noise(V, F, float(sigma), int(seed), str(kind), float(length))


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


def scan_error(V_ref: ArrayLike, F_ref: ArrayLike, V_scan: ArrayLike, F_scan: ArrayLike,
               V: ArrayLike | None = None) -> dict[str, Any]:
    """Error of a real scan against a reference surface it shares no vertices with.

    A raw range scan measured against the merged reconstruction of all the scans, as
    ``fqfilter --reference-surface`` and ``scripts/scan_quality.py`` measure it
    (``eval/scan_error.h``): the normal error is the mean angle between a scan face's normal
    and the normal of the reference triangle nearest the face's centroid; the distance is the
    RMS distance of the centroids to the reference surface, in mean edges of the raw scan.
    Only faces over the reference count (the scan sees parts the reference does not): those
    whose centroid is within 3 mean edges of a reference triangle off the reference's
    boundary, chosen on the raw scan. A scan wound the other way round from the reference is
    measured against the flipped reference normals.

    Parameters
    ----------
    V_ref, F_ref : array_like
        The reference surface (n×3 positions, m×3 triangles).
    V_scan, F_scan : array_like
        The raw scan, in the reference's frame: it chooses the faces and the unit.
    V : array_like of shape (len(V_scan), 3), optional
        Positions to measure on the scan's triangles (a filtered scan); the raw scan when None.

    Returns
    -------
    dict
        ``normal_error_rad``, ``distance_mean_edges``, ``faces_used`` (faces counted),
        ``faces`` (the scan's faces), ``flipped`` (the scan is wound against the reference),
        ``normal_error_coarse_rad`` (the normal error at the reference's scale: each reference
        triangle's normal against the area-weighted normal of the scan faces nearest to it, for
        a reference coarser than the scan) and ``reference_faces_used``.
        The errors are NaN when no face is over the reference.

    Raises
    ------
    ValueError
        A wrong shape or dtype, an index out of range, or V of another length than V_scan.
    """
    return _fq.scan_error(V_ref, F_ref, V_scan, F_scan, V)


def surface_sample(V_clean: ArrayLike, F_clean: ArrayLike, V_result: ArrayLike, F_result: ArrayLike,
                   threads: int = 0) -> dict[str, Any]:
    """The result surface seen from every vertex of the clean mesh (``eval/surface_flicker.h``).

    Each clean vertex c, with its unit area-weighted normal n, samples the result along the
    line c + s·n: the crossing with the result's triangles nearest c within 3 clean mean
    edges, else the result's closest point (s then its offset along n). Only the result's
    surface counts, never its vertex order or triangles: the result may be re-meshed.

    Parameters
    ----------
    V_clean, F_clean : array_like
        The clean mesh (n×3 positions, m×3 triangles): where to sample and the unit.
    V_result, F_result : array_like
        The result's own positions and triangles.
    threads : int, default 0
        Threads to sample with; 0: every hardware thread.

    Returns
    -------
    dict
        ``height`` (n,): s in clean mean edges; ``result_normal`` (n, 3): the result's
        smooth-shaded unit normal there (barycentric mix of its unit area-weighted vertex
        normals); ``clean_normal`` (n, 3); ``area`` (n,): a third of each incident clean
        triangle's area (0 for a vertex without a normal, which does not count); ``hit`` (n,)
        bool: the line met the result within reach; ``mean_edge``; ``height_rms`` (the
        area-weighted RMS of height) and ``smooth_normal_error_rad`` (the area-weighted mean
        angle between the two normals).

    Raises
    ------
    ValueError
        A wrong shape or dtype, or an index out of range.
    """
    return _fq.surface_sample(V_clean, F_clean, V_result, F_result, int(threads))


def surface_flicker(frames: Iterable[tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike]],
                    threads: int = 0) -> dict[str, Any]:
    """Surface flicker, shading flicker and the per-frame surface measures of a sequence.

    ``frames`` yields (V_clean, F_clean, V_result, F_result) per frame in order, sampled as
    :func:`surface_sample` does. Surface flicker (SF) is the area-weighted RMS over clean
    vertices of height_t − height_t−1 (clean mean edges); shading flicker (ShF) the
    area-weighted RMS of |(n_r,t − n_r,t−1) − (n_c,t − n_c,t−1)| (n_r the result's
    smooth-shaded normal, n_c the clean one; a chord of unit vectors, about radians). Both
    need clean frames that share their vertices (a tracked reference): a pair whose clean
    frames differ in vertex count has neither. The results may be re-meshed.

    Parameters
    ----------
    frames : iterable of 4-tuples
        (V_clean, F_clean, V_result, F_result) for every frame, in order (a generator does:
        one frame at a time is held).
    threads : int, default 0
        Threads to sample with; 0: every hardware thread.

    Returns
    -------
    dict
        ``height_rms`` and ``smooth_normal_error_rad`` (means over frames),
        ``surface_flicker`` and ``shading_flicker`` (means over transitions; NaN without one),
        ``transitions``, and ``frames``: per frame a dict of the four (the pair measures None
        on the first frame).

    Raises
    ------
    ValueError
        A frame that is not four arrays, a wrong shape or dtype, or an index out of range.
    """
    return _fq.surface_flicker(frames, int(threads))
