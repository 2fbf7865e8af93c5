"""What fq says it did (return_info, fqfilter's report), the structured noise families and the
scan error, from Python and from fqfilter."""
import json
import os
import subprocess

import numpy as np
import pytest

import fq

from conftest import DATA


def mean_edge(V, F):
    e = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    return np.linalg.norm(V[e[:, 0]].astype(np.float64) - V[e[:, 1]], axis=1).mean()


def test_return_info_says_what_was_read_and_how_far_vertices_moved(fandisk):
    V, F = fandisk
    noisy = fq.add_noise(V, F, 0.2, seed=3)
    out, info = fq.filter(noisy, F, return_info=True, engine="cpu")
    np.testing.assert_array_equal(out, fq.filter(noisy, F, engine="cpu"))  # the same positions
    ell = mean_edge(noisy, F)
    assert info["mean_edge"] == pytest.approx(ell, rel=1e-4)
    moved = np.linalg.norm(out.astype(np.float64) - noisy, axis=1) / info["mean_edge"]
    assert info["moved_mean"] == pytest.approx(moved.mean(), rel=1e-4)
    assert info["moved_max"] == pytest.approx(moved.max(), rel=1e-4)
    assert info["moved_p99"] == pytest.approx(np.sort(moved)[int(np.ceil(0.99 * len(moved))) - 1], rel=1e-4)
    # The estimate is the residual's noise share; at noise 0.2 most of it.
    assert 0.1 < info["noise_estimate"] <= info["noise_residual"] < 0.3
    assert info["filtered_for"] == info["noise_estimate"]
    assert info["welded_vertices"] == 0
    # fandisk with its first triangle's corners copied and re-pointed (a seam): the copies are
    # counted and come back where their twins go.
    seam_v = np.concatenate([noisy, noisy[F[0]]])
    seam_f = F.copy()
    seam_f[0] = [len(noisy), len(noisy) + 1, len(noisy) + 2]
    seamed, seam_info = fq.filter(seam_v, seam_f, return_info=True, engine="cpu")
    assert seam_info["welded_vertices"] == 3
    np.testing.assert_array_equal(seamed[len(noisy):], seamed[F[0]])
    _, doubled = fq.filter(noisy, F, return_info=True, strength=2.0, engine="cpu")
    assert doubled["filtered_for"] == pytest.approx(2 * info["noise_estimate"], rel=1e-6)
    assert doubled["moved_mean"] > info["moved_mean"]
    _, qf = fq.filter(noisy, F, return_info=True, mode="qf", engine="cpu")
    assert qf["noise_estimate"] is None and qf["moved_mean"] > 0
    with pytest.raises(TypeError, match="return_info"):
        fq.filter(noisy, F, return_info=1)


def test_structured_noise_kinds(fandisk):
    V, F = fandisk
    depth = fq.add_noise(V, F, 0.1, seed=2, kind="depth")
    np.testing.assert_array_equal(depth[:, :2], V[:, :2])  # along z only
    assert np.any(depth[:, 2] != V[:, 2])
    for kind in ("correlated", "ripple"):
        a = fq.add_noise(V, F, 0.1, seed=2, kind=kind, length=2.5)
        np.testing.assert_array_equal(a, fq.add_noise(V, F, 0.1, seed=2, kind=kind, length=2.5))
        assert not np.array_equal(a, fq.add_noise(V, F, 0.1, seed=2, kind=kind, length=1.5))
    np.testing.assert_array_equal(fq.add_noise(V, F, 0.1, seed=2), fq.add_noise(V, F, 0.1, seed=2, kind="iso"))
    with pytest.raises(ValueError, match="kind"):
        fq.add_noise(V, F, 0.1, kind="gaussian")


def test_scan_error_of_a_scan_cut_from_the_reference(fandisk):
    V, F = fandisk
    # The "scan": the reference's own triangles over half the part, vertices renumbered, lifted
    # along z by a known height and wound the other way round.
    keep = F[V[F].mean(axis=1)[:, 0] < np.median(V[:, 0])]
    used, inverse = np.unique(keep, return_inverse=True)
    scan_v = V[used].astype(np.float64)
    scan_f = inverse.reshape(-1, 3)[:, ::-1]
    same = fq.scan_error(V, F, scan_v, scan_f)
    assert same["normal_error_rad"] == pytest.approx(0, abs=1e-6)
    assert same["distance_mean_edges"] == pytest.approx(0, abs=1e-6)
    assert same["flipped"] and 0 < same["faces_used"] <= same["faces"] == len(scan_f)
    noisy = fq.add_noise(scan_v, scan_f, 0.2, seed=4, kind="normal")
    worse = fq.scan_error(V, F, scan_v, scan_f, noisy)
    assert worse["normal_error_rad"] > 0.05
    assert 0.05 < worse["distance_mean_edges"] < 0.25  # noise 0.2 along the normal, RMS over centroids
    assert worse["faces_used"] == same["faces_used"]  # the faces are the raw scan's
    with pytest.raises(ValueError, match="vertices"):
        fq.scan_error(V, F, scan_v, scan_f, noisy[:5])


@pytest.mark.skipif(not os.environ.get("FQFILTER"), reason="needs FQFILTER (ctest sets it)")
def test_fqfilter_reports_the_residual_the_moves_and_the_noise_kind(tmp_path):
    out = subprocess.run([os.environ["FQFILTER"], str(DATA / "fandisk.ply"), "--noise", "0.1", "--noise-kind", "ripple",
                          "--noise-length", "3", "--engine", "cpu", "--json"], capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    assert j["noise"] == {"sigma": 0.1, "direction": "ripple", "seed": 1, "length": 3.0}
    assert 0 <= j["noise_estimate"]["estimated"] <= j["noise_estimate"]["residual"]
    assert 0 < j["moved"]["mean"] <= j["moved"]["p99"] <= j["moved"]["max"]
    assert j["cuda_refused"] is None  # --engine cpu asked for the CPU: nothing was refused
    auto = json.loads(subprocess.run([os.environ["FQFILTER"], str(DATA / "fandisk.ply"), "--json"],
                                     capture_output=True, text=True, check=True).stdout)
    if auto["engine"] == "cpu":  # auto fell back: the reason is kept (a build without CUDA, no device, a driver)
        assert isinstance(auto["cuda_refused"], str) and auto["cuda_refused"]
    else:
        assert auto["engine"].startswith("cuda") and auto["cuda_refused"] is None
    missing = subprocess.run([os.environ["FQFILTER"], "/nonexistent-fq-dir/", str(tmp_path / "out")],
                             capture_output=True, text=True)
    assert missing.returncode == 2
    assert "IN '/nonexistent-fq-dir/': no such file or folder" in missing.stderr  # not blamed on OUT
    human = subprocess.run([os.environ["FQFILTER"], str(DATA / "fandisk.ply"), "--noise", "0.05", "--engine", "cpu"],
                           capture_output=True, text=True, check=True).stdout
    assert "moved: mean" in human and "of a residual" in human
    assert "--strength" in human  # light noise is said to be read as such, with the option to turn
