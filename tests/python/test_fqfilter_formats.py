"""fqfilter's OBJ and glb outputs, read back with Open3D's parsers (tinyobjloader, tinygltf):
geometry, recomputed normals, texture coordinates and vertex colours come through."""
import os
import subprocess

import numpy as np
import pytest

o3d = pytest.importorskip("open3d")

FQFILTER = os.environ.get("FQFILTER", "fqfilter")
N = 8  # grid of N x N vertices


def attributed_ply(path):
    """A bumpy grid with colours, (wrong) normals and texture coordinates, as ASCII PLY."""
    i, j = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    xyz = np.stack([i, j, 0.05 * np.sin(i) * np.cos(j)], axis=-1).reshape(-1, 3)
    rgb = np.stack([i * 30, j * 30, np.full_like(i, 7)], axis=-1).reshape(-1, 3)
    uv = np.stack([i, j], axis=-1).reshape(-1, 2) / (N - 1)
    a = (i[:-1, :-1] * N + j[:-1, :-1]).ravel()
    faces = np.concatenate([np.stack([a, a + N, a + N + 1], 1), np.stack([a, a + N + 1, a + 1], 1)])
    lines = ["ply", "format ascii 1.0", f"element vertex {N * N}"]
    lines += [f"property float {p}" for p in ("x", "y", "z", "nx", "ny", "nz")]
    lines += [f"property uchar {p}" for p in ("red", "green", "blue")]
    lines += ["property float u", "property float v", f"element face {len(faces)}",
              "property list uchar int vertex_indices", "end_header"]
    lines += [f"{p[0]} {p[1]} {p[2]} 1 0 0 {c[0]} {c[1]} {c[2]} {t[0]} {t[1]}" for p, c, t in zip(xyz, rgb, uv)]
    lines += [f"3 {f[0]} {f[1]} {f[2]}" for f in faces]
    path.write_text("\n".join(lines) + "\n")
    return rgb / 255.0, faces


def fqfilter(*args):
    done = subprocess.run([FQFILTER, *map(str, args), "--threads", "2"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stderr


def read(path):
    mesh = o3d.io.read_triangle_mesh(str(path))
    return mesh, np.asarray(mesh.vertices), np.asarray(mesh.triangles)


@pytest.fixture()
def grid(tmp_path):
    source = tmp_path / "grid.ply"
    colours, faces = attributed_ply(source)
    fqfilter(source, tmp_path / "ref.ply")
    _, reference, _ = read(tmp_path / "ref.ply")  # the filtered positions, from our PLY
    return source, colours, faces, reference


@pytest.mark.parametrize("extension", [".glb", ".obj"])
def test_geometry_normals_and_uvs(tmp_path, grid, extension):
    source, colours, faces, reference = grid
    out = tmp_path / ("out" + extension)
    fqfilter(source, out)
    mesh, vertices, triangles = read(out)
    assert len(triangles) == len(faces)
    # Parsers may reorder or split vertices: compare each triangle's corner positions.
    np.testing.assert_allclose(vertices[triangles], reference[faces], atol=1e-5)
    assert mesh.has_vertex_normals()
    normals = np.asarray(mesh.vertex_normals)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-4)
    assert np.all(np.abs(normals[:, 2]) > 0.9)  # recomputed: the input's (1, 0, 0) is gone
    assert mesh.has_triangle_uvs()


def test_glb_keeps_vertex_colours_or_shows_clusters(tmp_path, grid):
    source, colours, faces, _ = grid
    fqfilter(source, tmp_path / "kept.glb")
    mesh, _, triangles = read(tmp_path / "kept.glb")
    kept = np.asarray(mesh.vertex_colors)[triangles]
    np.testing.assert_allclose(kept, colours[faces], atol=1.0 / 255)
    warnings = fqfilter(source, tmp_path / "clusters.glb", "--cluster", "--colour-clusters")
    mesh, _, triangles = read(tmp_path / "clusters.glb")
    assert not np.allclose(np.asarray(mesh.vertex_colors)[triangles], colours[faces], atol=1.0 / 255)
    assert "cluster labels as integers" in warnings
