"""fq.read_mesh and fq.write_mesh: mesh files as fqfilter reads and writes them."""
from __future__ import annotations

import dataclasses
import os
import warnings
from typing import Any, Optional, Union

from numpy.typing import ArrayLike

from . import _fq
from .mesh import Mesh, as_mesh, is_mesh

PathLike = Union[str, "os.PathLike[str]"]


def read_mesh(path: PathLike) -> Mesh:
    """Read a mesh file as fqfilter does, with what it carries besides positions.

    Parameters
    ----------
    path : str or os.PathLike
        A .ply, .obj, .stl or .drc file. PLY keeps its vertex count and order; OBJ and STL
        are welded (one vertex per distinct position); polygons are split into triangles.

    Returns
    -------
    Mesh
        float32 (n, 3) vertices and int64 (m, 3) faces, and when the file has them vertex
        colours, normals and texture coordinates, an OBJ's per-corner texture coordinates and
        normals, and cluster labels. It unpacks as ``V, F = fq.read_mesh(path)``.

    Raises
    ------
    FileNotFoundError
        No such file.
    OSError
        The file cannot be opened or read.
    ValueError
        An unsupported extension, or content that cannot be decoded or is not a triangle mesh.

    Warns
    -----
    UserWarning
        For each group of attributes the file holds that the Mesh cannot carry.
    """
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(2, "no such file", path)
    arrays = _fq.read_mesh(path)
    for what in arrays.pop("dropped"):
        warnings.warn(f"{path}: cannot keep {what}", stacklevel=2)
    return Mesh(**arrays)


def write_mesh(path: PathLike, V: Union[ArrayLike, Any], F: Optional[ArrayLike] = None,
               labels: Optional[ArrayLike] = None, *, drc_bits: int = 16) -> None:
    """Write a mesh file as fqfilter does, by the extension of ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        A .ply (everything kept), .drc (Draco: labels, normals, colours and per-vertex
        texture coordinates), .obj (normals and texture coordinates, per vertex or per
        corner) or .glb (also vertex colours) file.
    V : array_like of shape (n, 3), or a mesh
        Vertex positions, or an fq.Mesh, open3d TriangleMesh or trimesh.Trimesh whose
        attributes are written too (then F is left out).
    F : array_like of shape (m, 3), optional
        Triangles; needed when V is an array.
    labels : array_like of shape (n,), optional
        A cluster label per vertex (integers >= 0); a Mesh's own labels otherwise.
    drc_bits : int, default 16
        Position quantization bits of .drc files, 0 for none (lossless).

    Raises
    ------
    TypeError
        F given with a mesh, or left out with an array.
    ValueError
        An unsupported extension, a bad shape or index, or labels that are not one
        non-negative integer per vertex.
    OSError
        The file cannot be written (no such folder, no permission, disk full).

    Warns
    -----
    UserWarning
        For each group of attributes the format cannot hold.
    """
    path = os.fspath(path)
    if F is None:
        if not is_mesh(V):
            raise TypeError("write_mesh() needs F with an array V (or a mesh as V)")
        mesh = as_mesh(V)
    elif is_mesh(V):
        raise TypeError("write_mesh() takes F only with an array V, not with a mesh")
    else:
        mesh = Mesh(V, F)  # type: ignore[arg-type]
    if labels is None:
        labels = mesh.labels
    arrays = {f.name: getattr(mesh, f.name) for f in dataclasses.fields(mesh)[2:] if f.name != "labels"}
    for what in _fq.write_mesh(path, mesh.vertices, mesh.faces, labels, arrays, int(drc_bits)):
        warnings.warn(f"{path}: not kept: {what}", stacklevel=2)
