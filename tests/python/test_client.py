"""fq.Producer, fq.Consumer and fq.wire against a real fqd (FQD: its path, set by ctest)."""
import json
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import fq

ROOT = pathlib.Path(__file__).resolve().parents[2]
FQD = os.environ.get("FQD")
needs_fqd = pytest.mark.skipif(not FQD, reason="FQD (the fqd binary) not set: run through ctest")


@pytest.fixture(scope="module")
def fqd(tmp_path_factory):
    """A child fqd on free ports of 127.0.0.1 (tests/daemon/child_fqd.toml: CPU, filter and cluster)."""
    config = tmp_path_factory.mktemp("fqd") / "fqd.toml"
    config.write_text((ROOT / "tests" / "daemon" / "child_fqd.toml").read_text())
    child = subprocess.Popen([FQD, "--config", str(config), "--print-endpoints"], stdout=subprocess.PIPE, text=True)
    endpoints = json.loads(child.stdout.readline())
    yield endpoints
    child.send_signal(signal.SIGTERM)
    assert child.wait(timeout=30) == 0


def noisy_frames(V, F, count):
    return [fq.add_noise(V, F, 0.2, seed=i) for i in range(count)]


@needs_fqd
def test_five_frames_round_trip_in_order(fqd, fandisk):
    V, F = fandisk
    frames = noisy_frames(V, F, 5)
    # What a capture engineer writes.
    consumer = fq.Consumer(fqd["publish"], "cam")
    producer = fq.Producer(fqd["ingest"], "cam")
    results = []
    for frame in frames:  # fqd keeps only a stream's newest waiting frame: one at a time
        producer.send(frame, F)
        results.append(consumer.recv(timeout_s=60))

    assert [r.header["sequence"] for r in results] == [0, 1, 2, 3, 4]
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    for sent, r in zip(frames, results):
        assert r.ok and r.header["status"] == "OK" and r.header["stream_id"] == "cam"
        assert r.positions.shape == sent.shape and r.positions.dtype == np.float32
        moved = np.linalg.norm(r.positions - sent, axis=1)
        assert 0 < moved.max() < 0.02 * diagonal  # filtered, not replaced
        assert r.labels is not None and r.labels.shape == (len(V),) and r.labels.dtype == np.uint32
        assert r.labels.max() < r.header["cluster_count"]
        assert r.faces is None  # the POSITIONS form: the faces are the frame's
        assert r.header["noise_estimate"] > 0 and r.header["latency_ms"] >= 0
        assert "decode" in " ".join(r.header["timings"])
    assert producer.sequence == 5
    producer.close()
    consumer.close()


@needs_fqd
def test_recv_times_out_with_none(fqd):
    with fq.Consumer(fqd["publish"], "nobody") as consumer:
        start = time.monotonic()
        assert consumer.recv(timeout_s=0.3) is None
        assert consumer.recv(timeout_s=0) is None
        assert time.monotonic() - start < 5


@needs_fqd
def test_consumer_of_every_stream_iterates_until_quiet(fqd, fandisk):
    V, F = fandisk
    with fq.Consumer(fqd["publish"], iter_timeout_s=0.5) as consumer, fq.Producer(fqd["ingest"], "other") as producer:
        assert producer.send(V, F, timeout_s=30) == 0
        first = consumer.recv(timeout_s=60)
        assert first.header["stream_id"] == "other" and first.header["sequence"] == 0
        assert list(consumer) == []  # nothing more within iter_timeout_s


@needs_fqd
def test_per_frame_parameters_reach_fqd(fqd, fandisk):
    V, F = fandisk
    with fq.Consumer(fqd["publish"], "filtered") as consumer, \
            fq.Producer(fqd["ingest"], "filtered", compute="filter", chunks=3, strength=2.0) as producer:
        producer.send(fq.add_noise(V, F, 0.2), F)
        r = consumer.recv(timeout_s=60)
    assert r.ok and r.labels is None and r.header["cluster_count"] == 0


@needs_fqd
def test_examples_run_against_fqd(fqd):
    examples = ROOT / "python" / "examples"
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    consumer = subprocess.Popen([sys.executable, examples / "consumer.py", fqd["publish"], "2"], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert consumer.stderr.readline().startswith("waiting for results")  # subscribed
    producer = subprocess.run([sys.executable, examples / "producer.py", fqd["ingest"], ROOT / "data" / "fandisk.ply",
                               "3"], env=env, capture_output=True, text=True, timeout=120)
    assert producer.returncode == 0, producer.stderr
    assert producer.stdout.splitlines() == [f"sent frame {i}: 6475 vertices" for i in range(3)]
    out, err = consumer.communicate(timeout=120)
    assert consumer.returncode == 0, err
    # fqd may skip frame 1 (superseded by frame 2 while it waited), never the last one.
    lines = out.splitlines()
    sequences = [int(line.split(":")[0].split()[1]) for line in lines]
    assert sequences[-1] == 2 and sequences == sorted(set(sequences)), out
    assert all("OK, 6475 vertices" in line for line in lines), out


def varint(n):
    out = bytearray()
    while True:
        out.append((n & 0x7F) | (0x80 if n > 0x7F else 0))
        n >>= 7
        if not n:
            return bytes(out)


def result_header(fields):
    """A ResultHeader by hand (protobuf: varint and length-delimited fields, by number)."""
    out = b""
    for number, value in fields:
        if isinstance(value, bytes):
            out += varint(number << 3 | 2) + varint(len(value)) + value
        else:
            out += varint(number << 3) + varint(value)
    return out


def test_encoded_frame_decodes_as_a_mesh_result(fandisk):
    V, F = fandisk
    parts = fq.wire.encode_frame(V, F, "cam", 7, chunks=4)
    assert parts[0] == b"cam" and len(parts) == 2 + 4
    # fqd's MESH results are chunked meshes like the frames: a result of these very chunks.
    header = result_header([(1, 2), (2, b"cam"), (3, 7), (14, 4), (15, len(V)), (17, 1)])
    r = fq.wire.decode_result([parts[0], header] + parts[2:])
    assert r.header["sequence"] == 7 and r.header["form"] == "MESH" and r.header["status"] == "OK"
    step = np.ptp(V, axis=0).max() / (2 ** 16 - 1)  # 16-bit positions on the bounding box
    assert np.abs(r.positions - V).max() <= step
    assert sorted(map(tuple, r.faces.tolist())) == sorted(map(tuple, np.asarray(F).tolist()))
    assert r.labels is None


def test_error_result_and_bad_messages():
    r = fq.wire.decode_result([b"cam", result_header([(1, 2), (2, b"cam"), (8, 2), (9, b"bad frame")])])
    assert not r.ok and r.header["error"] == "bad frame" and len(r.positions) == 0
    with pytest.raises(ValueError, match="version"):
        fq.wire.decode_result([b"cam", result_header([(1, 1), (2, b"cam")])])
    with pytest.raises(ValueError, match="chunk"):
        fq.wire.decode_result([b"cam", result_header([(1, 2), (2, b"cam"), (14, 1)])])
    with pytest.raises(ValueError):
        fq.wire.decode_result([b"cam"])


def test_bad_frames_raise(fandisk):
    V, F = fandisk
    with pytest.raises(ValueError):
        fq.wire.encode_frame(V[:, :2], F, "cam", 0)
    with pytest.raises(ValueError):
        fq.wire.encode_frame(V, F[:, :2], "cam", 0)
    with pytest.raises(ValueError):
        fq.wire.encode_frame(V, F + len(V), "cam", 0)
    with pytest.raises(ValueError, match="compute"):
        fq.wire.encode_frame(V, F, "cam", 0, compute="everything")
    with pytest.raises(TypeError, match="not a frame parameter"):
        fq.wire.encode_frame(V, F, "cam", 0, colour=1)
    producer = fq.Producer("tcp://127.0.0.1:9", "cam")  # nothing there: the socket only queues
    with pytest.raises(ValueError):
        producer.send(V[:, :2], F)
    with pytest.raises(ValueError):
        fq.Producer("not an endpoint", "cam")


CTRL_C = """
import fq
consumer = fq.Consumer("tcp://127.0.0.1:9", "cam", connect_timeout_s=0)
print("waiting", flush=True)
try:
    consumer.recv()
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def test_ctrl_c_interrupts_a_blocking_recv():
    child = subprocess.Popen([sys.executable, "-c", CTRL_C], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "waiting"
    time.sleep(0.5)  # inside recv
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=10)
    assert child.returncode == 0 and "interrupted" in out, err
