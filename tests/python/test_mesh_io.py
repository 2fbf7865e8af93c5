"""fq.read_mesh, fq.write_mesh, fq.add_noise and fq.metrics."""
import numpy as np
import pytest

import fq
from conftest import DATA


def test_read_mesh(fandisk):
    V, F = fandisk
    assert V.dtype == np.float32 and V.shape[1] == 3
    assert F.dtype == np.int64 and F.shape[1] == 3
    assert F.min() == 0 and F.max() < len(V)


def test_ply_and_drc_round_trip(tmp_path, fandisk):
    V, F = fandisk
    labels = np.arange(len(V)) % 7
    fq.write_mesh(tmp_path / "out.ply", V, F, labels)
    V2, F2 = fq.read_mesh(str(tmp_path / "out.ply"))
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    header = (tmp_path / "out.ply").read_bytes().split(b"end_header")[0]
    assert b"property uint label" in header
    fq.write_mesh(tmp_path / "out.drc", V, F, drc_bits=0)
    V3, F3 = fq.read_mesh(tmp_path / "out.drc")
    assert len(V3) == len(V) and len(F3) == len(F)
    # Draco may reorder points: compare the sets of positions.
    np.testing.assert_array_equal(np.unique(V3, axis=0), np.unique(V, axis=0))


def test_file_errors(tmp_path, fandisk):
    V, F = fandisk
    with pytest.raises(FileNotFoundError):
        fq.read_mesh(tmp_path / "missing.ply")
    bad = tmp_path / "bad.ply"
    bad.write_text("not a mesh")
    with pytest.raises(ValueError, match="bad.ply"):
        fq.read_mesh(bad)
    with pytest.raises(OSError, match="for writing"):
        fq.write_mesh(tmp_path / "no" / "such" / "folder.ply", V, F)
    with pytest.raises(ValueError, match="labels"):
        fq.write_mesh(tmp_path / "x.ply", V, F, labels=np.zeros(3))
    with pytest.raises(ValueError, match="extension"):
        fq.write_mesh(tmp_path / "x.xyz", V, F)


def test_add_noise_is_reproducible_and_scaled(fandisk):
    V, F = fandisk
    a, b = fq.add_noise(V, F, 0.2, seed=5), fq.add_noise(V, F, 0.2, seed=5)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, fq.add_noise(V, F, 0.2, seed=6))
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    mean_edge = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1).mean()
    std = (a - V).std()
    assert 0.15 * mean_edge < std < 0.25 * mean_edge


def test_metrics(fandisk):
    V, F = fandisk
    same = fq.metrics(V, F, V)
    assert same["rmse_over_diagonal"] == 0 and same["mfne_deg"] == 0
    moved = V + np.array([0.01, 0, 0], dtype=np.float32)
    shifted = fq.metrics(V, F, moved)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    assert shifted["rmse_over_diagonal"] == pytest.approx(0.01 / diagonal, rel=1e-3)
    assert shifted["mfne_deg"] == pytest.approx(0, abs=1e-2)
    with pytest.raises(ValueError, match="vertices"):
        fq.metrics(V, F, V[:10])


def test_mesh_attributes_round_trip_through_ply_and_drc(tmp_path, fandisk):
    V, F = fandisk
    n = len(V)
    mesh = fq.Mesh(V, F, colors=np.linspace(0, 1, 3 * n, dtype=np.float32).reshape(n, 3),
                   normals=np.tile(np.float32([0, 0, 1]), (n, 1)), uvs=V[:, :2] / 20)
    for name in ("m.ply", "m.drc"):
        fq.write_mesh(tmp_path / name, mesh, drc_bits=0)
        back = fq.read_mesh(tmp_path / name)
        # Draco may reorder points: match them by position (fandisk's are distinct).
        order = np.lexsort(back.vertices.T) if name.endswith(".drc") else np.arange(n)
        ref = np.lexsort(V.T) if name.endswith(".drc") else np.arange(n)
        np.testing.assert_array_equal(back.vertices[order], V[ref])
        np.testing.assert_allclose(back.colors[order], mesh.colors[ref], atol=0.5 / 255)  # stored as uchar
        np.testing.assert_array_equal(back.normals[order], mesh.normals[ref])
        np.testing.assert_allclose(back.uvs[order], mesh.uvs[ref], rtol=0, atol=1e-7)


def test_obj_corners_come_as_corner_arrays_and_go_back(tmp_path):
    obj = tmp_path / "quad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                   "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/5/1 3/3/1 4/4/1\n")
    mesh = fq.read_mesh(obj)
    assert mesh.uvs is None and mesh.corner_uvs.shape == (2, 3, 2)
    np.testing.assert_array_equal(mesh.corner_uvs[1, 0], [0.5, 0.5])  # vertex 0 has two texture coordinates
    np.testing.assert_array_equal(mesh.corner_normals[:, :, 2], np.ones((2, 3)))
    fq.write_mesh(tmp_path / "again.obj", mesh)
    again = fq.read_mesh(tmp_path / "again.obj")
    np.testing.assert_array_equal(again.corner_uvs, mesh.corner_uvs)
    with pytest.warns(UserWarning, match="per-corner normals"):
        fq.write_mesh(tmp_path / "again.ply", mesh)


def test_mesh_unpacks_and_converts(fandisk):
    V, F = fandisk
    assert isinstance(fq.read_mesh(DATA / "fandisk.ply"), fq.Mesh)
    mesh = fq.Mesh(V, F, colors=np.full((len(V), 3), 0.5, np.float32))
    assert "6475 vertices" in repr(mesh) and "colors" in repr(mesh)
    o3d = pytest.importorskip("open3d")
    as_o3d = mesh.to_open3d()
    assert isinstance(as_o3d, o3d.geometry.TriangleMesh) and as_o3d.has_vertex_colors()
    back = fq.Mesh.from_open3d(as_o3d)
    np.testing.assert_array_equal(back.faces, F)
    np.testing.assert_allclose(back.colors, mesh.colors)


def test_trimesh_round_trip(fandisk):
    trimesh = pytest.importorskip("trimesh")
    V, F = fandisk
    tm = fq.Mesh(V, F, colors=np.full((len(V), 4), 0.5, np.float32)).to_trimesh()
    assert isinstance(tm, trimesh.Trimesh) and len(tm.vertices) == len(V)
    smoothed = fq.filter(tm, engine="cpu")
    assert isinstance(smoothed, trimesh.Trimesh)
    np.testing.assert_array_equal(fq.Mesh.from_trimesh(smoothed).faces, F)
