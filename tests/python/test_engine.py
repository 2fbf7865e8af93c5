"""fq.filter and fq.cluster on numpy meshes and mesh objects."""
import inspect
import os
import subprocess
import threading

import numpy as np
import pytest

import fq


def test_filter_denoises_and_keeps_the_input(fandisk):
    V, F = fandisk
    noisy = fq.add_noise(V, F, 0.3, seed=3)
    before = noisy.copy()
    smoothed = fq.filter(noisy, F, engine="cpu", threads=2)
    assert smoothed.shape == V.shape and smoothed.dtype == np.float32
    np.testing.assert_array_equal(noisy, before)  # the input array is not touched
    noisy_err, smoothed_err = fq.metrics(V, F, noisy), fq.metrics(V, F, smoothed)
    assert smoothed_err["mfne_deg"] < 0.6 * noisy_err["mfne_deg"]
    assert smoothed_err["surface_rms_over_diagonal"] < noisy_err["surface_rms_over_diagonal"]


def test_filter_follows_the_input_dtype_and_parameters(fandisk):
    V, F = fandisk
    V = fq.add_noise(V, F, 0.3, seed=3)  # qf+ filters a clean input only lightly
    as64 = fq.filter(V.astype(np.float64), F.astype(np.int32), engine="cpu")
    assert as64.dtype == np.float64
    np.testing.assert_allclose(as64, fq.filter(V, F, engine="cpu"), rtol=0, atol=1e-6)
    wider = fq.filter(V, F, sigma_s=4.0, engine="cpu")
    assert not np.allclose(wider, as64)
    bilateral = fq.filter(V, F, mode="bf", engine="cpu")
    assert not np.allclose(bilateral, as64)


def test_cluster_labels(fandisk):
    V, F = fandisk
    labels = fq.cluster(V, F, engine="cpu", threads=2)
    assert labels.shape == (len(V),) and labels.dtype == np.uint32
    k = int(labels.max()) + 1
    assert 1 < k < len(V) // 10
    assert set(np.unique(labels)) == set(range(k))  # every label in 0..k-1 is used
    fewer = fq.cluster(V, F, theta=0.99, engine="cpu", threads=2)
    assert int(fewer.max()) + 1 < k


@pytest.mark.parametrize("call, message", [
    (lambda V, F: fq.filter(V, F, sigma_s=-1.0), "sigma_s"),
    (lambda V, F: fq.filter(V, F, engine="tpu"), "engine"),
    (lambda V, F: fq.filter(V, F, mode="xx"), "mode"),
    (lambda V, F: fq.filter(V[:, :2], F), "shape"),
    (lambda V, F: fq.filter(V, F[:, :2]), "shape"),
    (lambda V, F: fq.filter(V, F + len(V)), "references vertex"),
    (lambda V, F: fq.filter(V, -F), "references vertex"),
    (lambda V, F: fq.filter(V, F.astype(np.float32)), "integer"),
    (lambda V, F: fq.cluster(V, F, theta=1.5), "theta"),
    (lambda V, F: fq.cluster(V, F, method="kmeans"), "method"),
    (lambda V, F: fq.cluster(V, F, geometry="smoothed"), "geometry"),
    (lambda V, F: fq.cluster(V, F, target_clusters=-3), "target_clusters"),
    (lambda V, F: fq.filter(V[:0], F[:0]), "no vertices"),
])
def test_bad_arguments_raise_value_error(fandisk, call, message):
    V, F = fandisk
    with pytest.raises(ValueError, match=message):
        call(V, F)


def test_missing_cuda_engine_raises_runtime_error(fandisk):
    if fq.engine_name() != "cpu":
        pytest.skip("a GPU is present: the CUDA engine is available")
    V, F = fandisk
    with pytest.raises(RuntimeError):
        fq.filter(V, F, engine="cuda")


def test_engine_releases_the_gil(fandisk):
    """While a filter runs in another thread, this thread keeps running Python code."""
    V, F = fandisk
    in_call = threading.Event()
    done = threading.Event()

    def work():
        in_call.set()
        for _ in range(3):
            fq.filter(V, F, engine="cpu", threads=1)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    in_call.wait()
    count = 0
    while not done.is_set():
        count += 1
    worker.join()
    # Holding the GIL, the worker would leave this loop only its few-millisecond switch
    # intervals between calls; released, it runs for the whole ~second of filtering.
    assert count > 100000


@pytest.mark.parametrize("call, message", [
    (lambda V, F: fq.filter(V, F, 2.0), "positional"),
    (lambda V, F: fq.filter(V, F, sigma_x=2.0), "sigma_x"),
    (lambda V, F: fq.filter(V, F, sigma_s="wide"), "sigma_s must be a number, got str"),
    (lambda V, F: fq.filter(V, F, constrained=1), "constrained must be True or False"),
    (lambda V, F: fq.cluster(V, F, target_clusters=2.5), "target_clusters must be an integer"),
    (lambda V, F: fq.cluster(V, F, sigma_r=None), "sigma_r"),
    (lambda V, F: fq.filter(V), "needs F"),
])
def test_bad_calls_raise_short_type_errors(fandisk, call, message):
    V, F = fandisk
    with pytest.raises(TypeError, match=message) as raised:
        call(V, F)
    assert len(str(raised.value)) < 300  # names the problem, never prints the arrays


def test_signature_shows_the_parameter_structs_defaults():
    text = str(inspect.signature(fq.filter))
    assert "sigma_r: float = 0.7" in text and "sigma_s: float = 1.5" in text
    assert "mode: Literal['qf+', 'qf', 'bf'] = 'qf+'" in text
    cluster = inspect.signature(fq.cluster).parameters
    assert cluster["target_clusters"].default == 0 and cluster["min_cluster_size"].default == 0
    assert cluster["geometry"].default == "auto" and cluster["theta"].default == 0.9


def test_every_fqfilter_parameter_is_a_keyword():
    """The parameter table's fqfilter rows are keywords of fq.filter, fq.cluster or fq.Stream,
    as the table says, and every Python row of the table is one."""
    takes = {"filter": inspect.signature(fq.filter).parameters, "cluster": inspect.signature(fq.cluster).parameters,
             "Stream": inspect.signature(fq.Stream).parameters}
    rows = fq._param_names()
    assert {"mode", "known_noise", "cluster_geometry", "temporal"} <= {name for name, _, _ in rows}
    for name, keyword, surfaces in rows:
        functions = [s for s in surfaces if s in takes]
        if "fqfilter" in surfaces and name not in ("cluster",):  # fq.cluster is --cluster
            assert functions, f"--{name.replace('_', '-')} has no Python keyword"
        for function in functions:
            assert keyword in takes[function], f"fq.{function} does not take {keyword} ({name})"


def test_every_function_has_a_numpy_docstring():
    for name in fq.__all__:
        obj = getattr(fq, name)
        if not callable(obj) or inspect.isclass(obj):
            continue
        doc = inspect.getdoc(obj)
        returns_none = inspect.signature(obj).return_annotation in (None, "None")
        for section in ("Parameters\n----------", "Raises\n------") + (() if returns_none else ("Returns\n-------",)):
            assert section in doc, f"fq.{name}: no {section.splitlines()[0]} section"
    assert "sigma_s : float, default 1.5" in fq.filter.__doc__
    assert "target_clusters : int, default 0" in fq.cluster.__doc__


def test_type_stub_lists_the_generated_keywords():
    stub = os.path.join(os.path.dirname(fq.__file__), "__init__.pyi")
    text = open(stub, encoding="utf-8").read()
    compile(text, stub, "exec")  # valid Python
    assert "def filter(V: Union[ArrayLike, MeshLike], F: Optional[ArrayLike] = None, *, mode: " in text
    assert "sigma_r: float = 0.7" in text and "min_cluster_size: int = 0" in text
    assert os.path.exists(os.path.join(os.path.dirname(fq.__file__), "py.typed"))


def test_default_mode_is_fqfilters_bit_for_bit(tmp_path, fandisk):
    """fq.filter's defaults are fqfilter's: the same positions from the same noisy input."""
    V, F = fandisk
    noisy = fq.add_noise(V, F, 0.3, seed=3)
    fq.write_mesh(tmp_path / "noisy.ply", noisy, F)
    done = subprocess.run([os.environ.get("FQFILTER", "fqfilter"), tmp_path / "noisy.ply", tmp_path / "out.ply",
                           "--engine", "cpu", "--threads", "2", "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    expected, _ = fq.read_mesh(tmp_path / "out.ply")
    ours = fq.filter(noisy, F, engine="cpu", threads=2)
    np.testing.assert_array_equal(ours, expected)
    np.testing.assert_array_equal(ours, fq.filter(noisy, F, mode="qf+", engine="cpu", threads=2))
    assert not np.array_equal(ours, fq.filter(noisy, F, mode="qf", engine="cpu", threads=2))


def test_cluster_target_count_minimum_size_and_geometry(fandisk):
    V, F = fandisk
    about_12 = fq.cluster(V, F, target_clusters=12, engine="cpu", threads=2)
    assert 6 <= int(about_12.max()) + 1 <= 24
    merged = fq.cluster(V, F, theta=0.5, min_cluster_size=200, engine="cpu", threads=2)
    assert np.bincount(merged).min() >= 200
    filtered = fq.cluster(V, F, geometry="filtered", engine="cpu", threads=2)
    assert not np.array_equal(filtered, fq.cluster(V, F, geometry="input", engine="cpu", threads=2))


def test_filter_and_cluster_take_mesh_objects(fandisk):
    V, F = fandisk
    noisy = fq.Mesh(fq.add_noise(V, F, 0.3, seed=3), F, normals=np.zeros_like(V))
    smoothed = fq.filter(noisy, engine="cpu", threads=2)
    assert isinstance(smoothed, fq.Mesh) and smoothed.faces is noisy.faces
    np.testing.assert_array_equal(smoothed.vertices, fq.filter(noisy.vertices, F, engine="cpu", threads=2))
    np.testing.assert_allclose(np.linalg.norm(smoothed.normals, axis=1), 1.0, atol=1e-5)  # follow the surface
    np.testing.assert_array_equal(fq.cluster(noisy, engine="cpu"), fq.cluster(*noisy, engine="cpu"))


def test_open3d_mesh_in_open3d_mesh_out(fandisk):
    o3d = pytest.importorskip("open3d")
    V, F = fandisk
    noisy = fq.add_noise(V, F, 0.3, seed=3).astype(np.float64)
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(noisy), o3d.utility.Vector3iVector(F))
    mesh.compute_vertex_normals()
    smoothed = fq.filter(mesh, engine="cpu", threads=2)
    assert isinstance(smoothed, o3d.geometry.TriangleMesh)
    np.testing.assert_array_equal(np.asarray(smoothed.vertices), fq.filter(noisy, F, engine="cpu", threads=2))
    np.testing.assert_array_equal(np.asarray(mesh.vertices), noisy)  # the input is not touched
    assert smoothed.has_vertex_normals()
    back = fq.Mesh.from_open3d(fq.Mesh(V, F, uvs=V[:, :2].copy()).to_open3d())
    np.testing.assert_allclose(back.corner_uvs, V[:, :2][F], atol=1e-6)
