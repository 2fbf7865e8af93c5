"""fq.filter's meshes come back with the normals of the filtered surface, not the input's
(noisy) ones: Open3D, trimesh and fq.Mesh, vertex and per-corner normals. The expected normals
are computed here, independently of fq.mesh."""
import numpy as np
import pytest

import fq


def area_weighted(V, F):
    """Unit vertex normals: each vertex's sum of its triangles' cross products, normalised."""
    V = np.asarray(V, np.float64)
    cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    sums = np.zeros_like(V)
    for k in range(3):
        np.add.at(sums, F[:, k], cross)
    return sums / np.linalg.norm(sums, axis=1, keepdims=True)


def max_angle_deg(a, b):
    a = np.asarray(a, np.float64)
    b = np.asarray(b, np.float64)
    cos = np.sum(a * b, axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).max())


@pytest.fixture(scope="module")
def noisy(fandisk):
    V, F = fandisk
    return fq.add_noise(V, F, 0.3, seed=5).astype(np.float64), F


def test_open3d_vertex_normals_are_the_filtered_surfaces(noisy):
    o3d = pytest.importorskip("open3d")
    V, F = noisy
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V), o3d.utility.Vector3iVector(F))
    mesh.compute_vertex_normals()  # the noisy surface's normals, as a scan loaded in Open3D has
    mesh.compute_triangle_normals()
    smoothed = fq.filter(mesh, engine="cpu", threads=2)
    positions = np.asarray(smoothed.vertices)
    expected = area_weighted(positions, F)
    assert max_angle_deg(np.asarray(mesh.vertex_normals), expected) > 5  # the input's are far off
    assert max_angle_deg(np.asarray(smoothed.vertex_normals), expected) < 1
    faces = np.cross(positions[F[:, 1]] - positions[F[:, 0]], positions[F[:, 2]] - positions[F[:, 0]])
    assert max_angle_deg(np.asarray(smoothed.triangle_normals), faces) < 1


def test_trimesh_vertex_normals_are_the_filtered_surfaces(noisy):
    trimesh = pytest.importorskip("trimesh")
    V, F = noisy
    rng = np.random.default_rng(1)
    given = area_weighted(V, F) + 0.2 * rng.standard_normal(V.shape)  # normals that came with a file
    mesh = trimesh.Trimesh(V, F, vertex_normals=given / np.linalg.norm(given, axis=1, keepdims=True),
                           process=False)
    smoothed = fq.filter(mesh, engine="cpu", threads=2)
    assert isinstance(smoothed, trimesh.Trimesh)
    assert max_angle_deg(smoothed.vertex_normals, area_weighted(np.asarray(smoothed.vertices), F)) < 1


def roof(noise):
    """A noisy roof of two slopes meeting at x = 4, its corners carrying one normal per slope
    (an OBJ export of a hard edge): vertices, faces, per-corner normals and each face's side."""
    n = 9
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    z = 0.75 * (4 - np.abs(i - 4)) + noise * np.sin(12.9898 * i + 78.233 * j)
    V = np.stack([i, j, z], axis=-1).reshape(-1, 3).astype(np.float32)
    a = (i[:-1, :-1] * n + j[:-1, :-1]).ravel()
    F = np.concatenate([np.stack([a, a + n, a + n + 1], 1), np.stack([a, a + n + 1, a + 1], 1)])
    left = V[F, 0].mean(axis=1) < 4
    normals = np.where(left[:, None], [-0.6, 0.0, 0.8], [0.6, 0.0, 0.8]).astype(np.float32)
    return V, F, np.repeat(normals[:, None, :], 3, axis=1), left


def test_mesh_corner_normals_are_recomputed_within_their_groups():
    V, F, corner_normals, left = roof(0.04)
    smoothed = fq.filter(fq.Mesh(V, F, corner_normals=corner_normals), engine="cpu", threads=2)
    P = np.asarray(smoothed.vertices, np.float64)
    cross = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    for side in (True, False):  # each slope's corners: area-weighted over that slope's faces only
        faces = F[left == side]
        sums = np.zeros_like(P)
        for k in range(3):
            np.add.at(sums, faces[:, k], cross[left == side])
        expected = sums[faces.ravel()]
        assert max_angle_deg(smoothed.corner_normals[left == side].reshape(-1, 3), expected) < 0.01
    ridge = F[:, 0] // 9 == 4  # faces right of the ridge, with a corner on it
    on_ridge_right = smoothed.corner_normals[ridge & ~left][:, 0]
    on_ridge_left = smoothed.corner_normals[(F[:, 1] // 9 == 4) & left][:, 1]
    assert np.all(on_ridge_right[:, 0] > 0.3) and np.all(on_ridge_left[:, 0] < -0.3)  # the edge stays hard
    assert max_angle_deg(smoothed.corner_normals.reshape(-1, 3), corner_normals.reshape(-1, 3)) > 0.5
