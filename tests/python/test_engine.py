"""fq.filter and fq.cluster on numpy meshes."""
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
