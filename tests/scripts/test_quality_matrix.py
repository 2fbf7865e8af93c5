"""scripts/peers.py and scripts/quality_matrix.py against real fqfilter, Open3D and MeshLab runs
on the bundled fandisk (skipped without python3-open3d; MeshLab's checks without meshlabserver)."""
import importlib.util
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "scripts"
FANDISK = ROOT / "data" / "fandisk.ply"
FQFILTER = os.environ.get("FQFILTER", str(ROOT / "build" / "clients" / "fqfilter" / "fqfilter"))
HAVE_O3D = importlib.util.find_spec("open3d") is not None
HAVE_MESHLAB = bool(shutil.which("meshlabserver") and shutil.which("xvfb-run"))

pytestmark = pytest.mark.skipif(not HAVE_O3D, reason="python3-open3d not installed")
sys.path.insert(0, str(SCRIPTS))


@pytest.fixture(scope="module")
def peers():
    import peers as module
    return module


@pytest.fixture(scope="module")
def noisy(tmp_path_factory):
    """fandisk with fqfilter's noise (iso 0.2, seed 1): the noisy file of the --quick row."""
    path = tmp_path_factory.mktemp("noisy") / "noisy.ply"
    subprocess.run([FQFILTER, str(FANDISK), "--noise", "0.2", "--noise-direction", "iso", "--seed", "1",
                    "--noisy-out", str(path), "--engine", "cpu", "--mode", "qf"], check=True, capture_output=True)
    return path


def write_ply(path, v, f):
    import numpy as np
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    faces = b"".join(b"\x03" + np.asarray(t, dtype="<i4").tobytes() for t in f)
    path.write_bytes(header.encode() + np.asarray(v, dtype="<f4").tobytes() + faces)


def test_mfne_skips_the_faces_fqfilter_skips(peers, tmp_path):
    # Face (0, 1, 4) is a sliver (|cross| / longest² = 1e-10) that flips between the meshes:
    # eval/error_metrics.cpp skips it; counting it would add a π-radian face.
    faces = [(0, 1, 2), (1, 3, 2), (0, 1, 4), (2, 3, 5)]
    clean = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0.5, 1e-10, 0), (0.5, 2, 0)]
    moved = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0.3), (0.5, -1e-10, 0), (0.5, 2, 0)]
    write_ply(tmp_path / "clean.ply", clean, faces)
    write_ply(tmp_path / "moved.ply", moved, faces)
    report = peers.fqfilter_json(FQFILTER, [str(tmp_path / "moved.ply"), "--reference", str(tmp_path / "clean.ply"),
                                            "--engine", "cpu", *peers.QF_ARGS])["metrics"]["input"]
    assert report["faces_skipped"] == 1
    c, f = peers.load(str(tmp_path / "clean.ply"))
    v, _ = peers.load(str(tmp_path / "moved.ply"))
    assert peers.mfne(c, f, v) == pytest.approx(report["mfne_rad"], abs=1e-9)
    assert peers.rmse_over_diagonal(c, v) == pytest.approx(report["rmse_over_diagonal"], rel=1e-9)


def test_cache_is_one_file_per_noisy_file_keyed_by_peer_and_setting(peers, noisy, tmp_path):
    c, f = peers.load(str(FANDISK))
    cache = tmp_path / "cache"
    sweeps = [("o3d_laplacian", [1, 2]), ("o3d_simple", [3])]
    found, failures = peers.peer_results(str(noisy), c, f, sweeps, str(tmp_path), str(cache))
    assert not failures
    files = list(cache.iterdir())
    assert [p.name for p in files] == [peers.sha256_file(str(noisy)) + ".json"]
    stored = json.loads(files[0].read_text())
    assert sorted(stored) == ["o3d_laplacian:1", "o3d_laplacian:2", "o3d_simple:3"]
    assert stored == found and all(len(v) == 2 for v in stored.values())
    assert peers.key("ml_twostep", (3, 60)) == "ml_twostep:(3, 60)"
    # What the cache says is used without running the peer, null included; new settings are added.
    files[0].write_text(json.dumps({"o3d_laplacian:1": [9.0, 8.0], "o3d_laplacian:2": None}))
    found, _ = peers.peer_results(str(noisy), c, f, [("o3d_laplacian", [1, 2, 3])], str(tmp_path), str(cache))
    assert found["o3d_laplacian:1"] == [9.0, 8.0] and found["o3d_laplacian:2"] is None
    assert found["o3d_laplacian:3"][0] < 1
    assert sorted(json.loads(files[0].read_text())) == ["o3d_laplacian:1", "o3d_laplacian:2", "o3d_laplacian:3"]


@pytest.mark.parametrize("peer,settings", [
    ("o3d_laplacian", [2, 5]), ("o3d_taubin", [3, 10]), ("o3d_simple", [1, 4]),
    ("ml_taubin", [5, 10]), ("ml_hc", [1, 3]), ("ml_twostep", [(3, 60), (5, 60), (3, 30)])])
def test_a_chain_of_settings_gives_what_each_setting_gives_alone(peers, noisy, tmp_path, peer, settings):
    p = peers.PEERS[peer]
    if not p.available():
        pytest.skip("meshlabserver or xvfb-run not installed")
    chained = {}
    for group, chain in p.chains(settings):
        chained.update(zip(chain, p.run(str(noisy), group, [p.steps(s) for s in chain], str(tmp_path))))
    assert sorted(chained, key=str) == sorted(settings, key=str)
    for s in settings:
        (v, f), = p.run(str(noisy), p.group(s), [p.steps(s)], str(tmp_path))
        assert (chained[s][0] == v).all() and (chained[s][1] == f).all(), f"{peer} {s}"


def run_matrix(tmp_path, *args):
    out = subprocess.run([sys.executable, str(SCRIPTS / "quality_matrix.py"), "--fqfilter", FQFILTER,
                          "--meshes", str(FANDISK.parent), "--jobs", "2", "--json", str(tmp_path / "m.json"), *args],
                         capture_output=True, text=True, timeout=600)
    return out


def test_matrix_takes_a_dropped_in_cache(peers, noisy, tmp_path):
    # Made-up numbers in the cache file of the --quick row's noisy file: the matrix must report
    # them, so it read the cache and ran no peer.
    cache = tmp_path / "cache"
    cache.mkdir()
    made_up = {"o3d_laplacian:1": [0.0123, 0.00045], "o3d_taubin:3": [0.5, 0.01], "o3d_simple:1": None,
               "ml_taubin:5": [0.4, 0.002], "ml_hc:1": [0.6, 0.003], "ml_twostep:(3, 60)": [0.7, 0.004]}
    (cache / (peers.sha256_file(str(noisy)) + ".json")).write_text(json.dumps(made_up))
    out = run_matrix(tmp_path, "--quick", "--peer-cache", str(cache), "--plot", str(tmp_path / "m.png"))
    assert out.returncode == 0, out.stderr
    doc = json.loads((tmp_path / "m.json").read_text())
    row, = doc["rows"]
    assert row["peers"] == made_up
    assert row["best_peer"] == {"peer": "o3d_laplacian:1", "mfne": 0.0123, "rmse": 0.00045}
    assert "Open3D Laplacian (iterations 1)" in out.stdout and "**fq default wins 0 of 1 rows**" in out.stdout
    assert doc["summary"]["rmse_above_1.1_best_peer"] == ["fandisk iso 0.2 seed 1"]
    assert (tmp_path / "m.png").stat().st_size > 0 and (tmp_path / "m-rmse.png").stat().st_size > 0


@pytest.mark.skipif(not shutil.which("draco_encoder"), reason="Draco's tools not installed")
def test_a_drc_mesh_is_decoded_to_its_clean_reference(tmp_path):
    drc = tmp_path / "fandisk16.drc"
    subprocess.run(["draco_encoder", "-i", str(FANDISK), "-o", str(drc), "-qp", "16", "-cl", "0"],
                   check=True, capture_output=True)
    out = run_matrix(tmp_path, "--quick", "--mesh", str(drc), "--iso", "0.1", "--seeds", "3")
    assert out.returncode == 0, out.stderr
    doc = json.loads((tmp_path / "m.json").read_text())
    row, = doc["rows"]
    assert (row["mesh"], row["direction"], row["noise"], row["seed"]) == ("fandisk16", "iso", 0.1, 3)
    assert [c["mesh"] for c in doc["clean"]] == ["fandisk16"]


@pytest.mark.parametrize("args,error", [
    (["--mesh", "no_such_mesh"], "no mesh 'no_such_mesh'"),
    (["--iso", "0,0.1"], "noise levels must be above 0"),  # fqfilter writes no noisy file for 0
    (["--seeds", "one"], "--seeds: invalid literal"),
    (["--peers", "o3d_taubin,meshlab"], "--peers: unknown meshlab")])
def test_bad_options_are_named_in_the_error(tmp_path, args, error):
    out = run_matrix(tmp_path, "--quick", *args)
    assert out.returncode != 0 and error in out.stderr


def test_summary_counts_rows_won_rmse_and_monotony(peers):
    import quality_matrix_report as report

    def row(noise, fq, fq_rmse, peer):
        return {"mesh": "m", "vertices": 3, "direction": "iso", "noise": noise, "seed": 1,
                "noisy": {"mfne": 1.0, "rmse": 0.01}, "fq_default": {"mfne": fq, "rmse": fq_rmse},
                "fq_qf": {"mfne": 0.5, "rmse": 0.01}, "peer_failures": [],
                "peers": {"o3d_taubin:3": [peer, 0.005], "ml_hc:1": [peer * 2, 0.001], "o3d_simple:1": None}}
    doc = report.build({}, [row(0.1, 0.1, 0.02, 0.2), row(0.2, 0.05, 0.004, 0.1), row(0.3, 0.4, 0.006, 0.2)], [])
    s = doc["summary"]
    assert (s["rows_judged"], s["rows_won"]) == (3, 2)
    assert s["geomean_fq_over_peer_mfne"] == pytest.approx((0.5 * 0.5 * 2) ** (1 / 3))
    assert s["worst_row"] == {"row": "m iso 0.3 seed 1", "ratio": 2.0}
    assert s["rmse_above_noisy"] == ["m iso 0.1 seed 1"]
    assert s["rmse_above_1.1_best_peer"] == ["m iso 0.1 seed 1", "m iso 0.3 seed 1"]
    assert s["mfne_not_monotone"] == ["m iso 0.1 seed 1"]
    assert doc["rows"][0]["lowest_peer_rmse"] == {"peer": "ml_hc:1", "mfne": 0.4, "rmse": 0.001}
