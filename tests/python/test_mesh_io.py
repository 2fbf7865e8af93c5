"""fq.read_mesh, fq.write_mesh, fq.add_noise and fq.metrics."""
import numpy as np
import pytest

import fq


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
