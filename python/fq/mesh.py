"""fq.Mesh: positions, triangles and what a mesh file carries besides, and the conversions
to and from trimesh and Open3D meshes (imported only when such a mesh is met or asked for)."""
from __future__ import annotations

import dataclasses
from typing import Any, Iterator, Optional

import numpy as np
from numpy.typing import NDArray


@dataclasses.dataclass(eq=False)
class Mesh:
    """A triangle mesh and its attributes, as numpy arrays.

    It unpacks as ``V, F = mesh``, so code written for ``(V, F)`` tuples keeps working.

    Parameters
    ----------
    vertices : numpy.ndarray of shape (n, 3)
        Vertex positions (float32 as read from files).
    faces : numpy.ndarray of shape (m, 3)
        Triangles as int64 vertex indices.
    colors : numpy.ndarray of shape (n, 3) or (n, 4), optional
        Vertex colours as float32 in [0, 1] (RGB or RGBA).
    normals : numpy.ndarray of shape (n, 3), optional
        Vertex normals.
    uvs : numpy.ndarray of shape (n, 2), optional
        Texture coordinates per vertex (PLY ``u, v`` and its aliases).
    corner_uvs : numpy.ndarray of shape (m, 3, 2), optional
        Texture coordinates per triangle corner (OBJ ``vt``, Open3D ``triangle_uvs``).
    corner_normals : numpy.ndarray of shape (m, 3, 3), optional
        Normals per triangle corner (OBJ ``vn``).
    labels : numpy.ndarray of shape (n,), optional
        A cluster label per vertex (uint32), written as fqfilter writes them.
    """

    vertices: NDArray[Any]
    faces: NDArray[np.int64]
    colors: Optional[NDArray[np.float32]] = None
    normals: Optional[NDArray[np.float32]] = None
    uvs: Optional[NDArray[np.float32]] = None
    corner_uvs: Optional[NDArray[np.float32]] = None
    corner_normals: Optional[NDArray[np.float32]] = None
    labels: Optional[NDArray[np.uint32]] = None

    def __iter__(self) -> Iterator[NDArray[Any]]:
        return iter((self.vertices, self.faces))

    def __repr__(self) -> str:
        extra = [f.name for f in dataclasses.fields(self)[2:] if getattr(self, f.name) is not None]
        return (f"fq.Mesh({len(self.vertices)} vertices, {len(self.faces)} triangles"
                + (", " + ", ".join(extra) if extra else "") + ")")

    def moved(self, vertices: NDArray[Any]) -> Mesh:
        """A copy with new positions (what a filter gives).

        Parameters
        ----------
        vertices : numpy.ndarray of shape (n, 3)
            The new positions, one per vertex.

        Returns
        -------
        Mesh
            The same triangles and attributes; normals recomputed from the moved surface (as
            fqfilter does): vertex normals, and per-corner normals within their groups
            (corner_normals_in_groups); texture coordinates as they were.
        """
        normals = None if self.normals is None else vertex_normals(vertices, self.faces)
        corner_normals = (None if self.corner_normals is None
                          else corner_normals_in_groups(vertices, self.faces, self.corner_normals))
        return dataclasses.replace(self, vertices=vertices, normals=normals, corner_normals=corner_normals)

    @classmethod
    def from_open3d(cls, mesh: Any) -> Mesh:
        """A Mesh of an ``open3d.geometry.TriangleMesh`` (vertices, triangles, vertex
        colours and normals, ``triangle_uvs`` as corner_uvs); the arrays are copies."""
        colors = np.asarray(mesh.vertex_colors, dtype=np.float32) if mesh.has_vertex_colors() else None
        normals = np.asarray(mesh.vertex_normals, dtype=np.float32) if mesh.has_vertex_normals() else None
        corner_uvs = (np.asarray(mesh.triangle_uvs, dtype=np.float32).reshape(-1, 3, 2)
                      if mesh.has_triangle_uvs() else None)
        return cls(np.asarray(mesh.vertices).copy(), np.asarray(mesh.triangles, dtype=np.int64),
                   colors=colors, normals=normals, corner_uvs=corner_uvs)

    def to_open3d(self) -> Any:
        """This mesh as an ``open3d.geometry.TriangleMesh`` (float64 positions; per-vertex
        texture coordinates become Open3D's per-corner ``triangle_uvs``)."""
        import open3d as o3d  # Debian: python3-open3d
        out = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(np.asarray(self.vertices, np.float64)),
                                        o3d.utility.Vector3iVector(np.asarray(self.faces, np.int32)))
        if self.colors is not None:
            out.vertex_colors = o3d.utility.Vector3dVector(np.asarray(self.colors[:, :3], np.float64))
        if self.normals is not None:
            out.vertex_normals = o3d.utility.Vector3dVector(np.asarray(self.normals, np.float64))
        corners = self.corner_uvs if self.corner_uvs is not None else (
            None if self.uvs is None else self.uvs[self.faces])
        if corners is not None:
            out.triangle_uvs = o3d.utility.Vector2dVector(np.asarray(corners, np.float64).reshape(-1, 2))
        return out

    @classmethod
    def from_trimesh(cls, mesh: Any) -> Mesh:
        """A Mesh of a ``trimesh.Trimesh`` (vertices, faces, vertex colours, per-vertex texture
        coordinates; trimesh derives normals from the faces, so none are copied)."""
        visual = mesh.visual
        colors = None
        if getattr(visual, "kind", None) == "vertex":
            colors = np.asarray(visual.vertex_colors, dtype=np.float32) / 255.0
        uv = getattr(visual, "uv", None)
        return cls(np.asarray(mesh.vertices).copy(), np.asarray(mesh.faces, dtype=np.int64), colors=colors,
                   uvs=None if uv is None else np.asarray(uv, np.float32))

    def to_trimesh(self) -> Any:
        """This mesh as a ``trimesh.Trimesh`` (``process=False``: vertices kept as they are)."""
        import trimesh
        visual = None
        if self.uvs is not None:
            visual = trimesh.visual.TextureVisuals(uv=self.uvs)
        elif self.colors is not None:
            visual = trimesh.visual.ColorVisuals(vertex_colors=np.round(self.colors * 255).astype(np.uint8))
        return trimesh.Trimesh(self.vertices, self.faces, vertex_normals=self.normals, visual=visual, process=False)


def _area_normals(vertices: NDArray[Any], faces: NDArray[np.int64]) -> NDArray[np.float64]:
    """Each triangle's normal times twice its area: larger triangles weigh more in a sum."""
    v = np.asarray(vertices, dtype=np.float64)
    return np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])


def _unit(sums: NDArray[np.float64], fallback: NDArray[Any]) -> NDArray[np.float32]:
    """Rows of ``sums`` scaled to unit length; rows of ``fallback`` where a sum has none."""
    lengths = np.linalg.norm(sums, axis=1, keepdims=True)
    return np.where(lengths > 0, sums / np.where(lengths > 0, lengths, 1.0), fallback).astype(np.float32)


def vertex_normals(vertices: NDArray[Any], faces: NDArray[np.int64]) -> NDArray[np.float32]:
    """Area-weighted unit vertex normals (fqfilter's rule); a vertex on no proper triangle gets 0."""
    faces = np.asarray(faces, dtype=np.int64)
    sums = np.zeros((len(vertices), 3))
    np.add.at(sums, faces.ravel(), np.repeat(_area_normals(vertices, faces), 3, axis=0))
    return _unit(sums, np.zeros(3))


def corner_normals_in_groups(vertices: NDArray[Any], faces: NDArray[np.int64],
                             corner_normals: NDArray[Any]) -> NDArray[np.float32]:
    """Per-corner normals (m, 3, 3) of the surface ``vertices, faces``, keeping the hard edges of
    ``corner_normals`` (fqfilter's rule for an OBJ's ``vn``): at each vertex, the corners that
    had the same normal form a group, whose new normal is the area-weighted normal of its
    triangles. A group on degenerate triangles only keeps its normal."""
    faces = np.asarray(faces, dtype=np.int64)
    old = np.ascontiguousarray(corner_normals, dtype=np.float32).reshape(-1, 3)
    keys = np.column_stack([faces.reshape(-1), old.view(np.int32)])  # (vertex, the normal's bits)
    _, first, group = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    group = group.ravel()  # (some numpy 2 releases give the inverse more than one dimension)
    sums = np.zeros((len(first), 3))
    np.add.at(sums, group, np.repeat(_area_normals(vertices, faces), 3, axis=0))
    return _unit(sums, old[first])[group].reshape(-1, 3, 3)


def _kind(obj: Any) -> str:
    module = type(obj).__module__
    if isinstance(obj, Mesh):
        return "fq"
    if module.startswith("open3d") and hasattr(obj, "triangles"):
        return "open3d"
    if module.startswith("trimesh") and hasattr(obj, "faces"):
        return "trimesh"
    return ""


def is_mesh(obj: Any) -> bool:
    """Whether ``obj`` is a Mesh, an Open3D TriangleMesh or a trimesh.Trimesh."""
    return bool(_kind(obj))


def as_mesh(obj: Any) -> Mesh:
    """``obj`` (a Mesh, an Open3D TriangleMesh or a trimesh.Trimesh) as a Mesh.

    Raises
    ------
    TypeError
        For anything else.
    """
    kind = _kind(obj)
    if kind == "fq":
        return obj
    if kind == "open3d":
        return Mesh.from_open3d(obj)
    if kind == "trimesh":
        return Mesh.from_trimesh(obj)
    raise TypeError(f"expected an fq.Mesh, open3d TriangleMesh or trimesh.Trimesh, got {type(obj).__name__}")


def moved_like(original: Any, vertices: NDArray[Any]) -> Any:
    """``original`` (a Mesh, Open3D or trimesh mesh) with new vertex positions, as a new mesh
    of the same kind: its normals are the moved surface's (area-weighted vertex normals, as
    fqfilter writes them), everything else is kept."""
    kind = _kind(original)
    if kind == "fq":
        return original.moved(vertices)
    faces = np.asarray(original.triangles if kind == "open3d" else original.faces, dtype=np.int64)
    normals = vertex_normals(vertices, faces).astype(np.float64)
    if kind == "open3d":
        import open3d as o3d
        out = o3d.geometry.TriangleMesh(original)
        out.vertices = o3d.utility.Vector3dVector(np.asarray(vertices, np.float64))
        # Not compute_vertex_normals(): Open3D adds onto the normals a mesh already has, so the
        # input's (noisy) normals would come back.
        if original.has_vertex_normals():
            out.vertex_normals = o3d.utility.Vector3dVector(normals)
        if original.has_triangle_normals():
            out.triangle_normals = o3d.utility.Vector3dVector(_unit(_area_normals(vertices, faces),
                                                                    np.zeros(3)).astype(np.float64))
        return out
    out = original.copy()
    out.vertices = vertices  # trimesh drops its cached normals when the vertices change...
    out.vertex_normals = normals  # ...and would weigh new ones by angle: fqfilter's rule instead
    return out
