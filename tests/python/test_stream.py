"""fq.Stream: one stream's frames in order, each filtered with the stream's last result."""
import numpy as np
import pytest

import fq


def frames(V, F, count):
    return [fq.add_noise(V, F, 0.2, seed=10 + k) for k in range(count)]


def test_a_still_part_gets_better_than_each_frame_alone(fandisk):
    V, F = fandisk
    stream = fq.Stream(engine="cpu", threads=2)
    assert stream.temporal == 0.75 and stream.frames == 0
    stream_err, alone_err = [], []
    for k, noisy in enumerate(frames(V, F, 4)):
        out = stream.filter(noisy, F)
        assert out.shape == V.shape and out.dtype == np.float32
        last = stream.last
        # From the second frame on the input is averaged through the ids (the frames keep their
        # triangles): its estimate reads the noise left after averaging.
        assert last["track"] == ("space" if k == 0 else "ids") and not last["ids_refused"]
        assert last["noise_estimate"] > (0.1 if k == 0 else 0.03) and not last["history_reset"]
        assert (last["prior_coverage"] == 0.0) == (k == 0)
        # fandisk holds still: its motion is smooth over eight rings nearly everywhere.
        assert (last["ids_wide"] > 0.5) if k > 0 else last["ids_wide"] == 0.0
        stream_err.append(fq.metrics(V, F, out)["mfne_rad"])
        alone_err.append(fq.metrics(V, F, fq.filter(noisy, F, engine="cpu", threads=2))["mfne_rad"])
    assert stream.frames == 4 and stream.resets == 0
    assert stream_err[0] == pytest.approx(alone_err[0], abs=1e-12)  # nothing to follow yet
    assert sum(stream_err[2:]) < sum(alone_err[2:])


def test_zero_is_fq_filter_and_reset_forgets(fandisk):
    V, F = fandisk
    noisy = frames(V, F, 2)
    alone = fq.Stream(temporal=0, engine="cpu")
    for x in noisy:
        np.testing.assert_array_equal(alone.filter(x, F), fq.filter(x, F, engine="cpu"))
    stream = fq.Stream(engine="cpu")
    first = stream.filter(noisy[0], F)
    stream.reset()
    assert stream.frames == 0
    np.testing.assert_array_equal(stream.filter(noisy[0], F), first)


def test_a_mesh_in_gives_a_mesh_out(fandisk):
    V, F = fandisk
    mesh = fq.Mesh(fq.add_noise(V, F, 0.2, seed=1), F)
    out = fq.Stream(engine="cpu").filter(mesh)
    assert isinstance(out, fq.Mesh) and out.vertices.shape == V.shape


def test_bad_arguments_are_clear():
    with pytest.raises(ValueError, match="temporal"):
        fq.Stream(temporal=1.5)
    with pytest.raises(ValueError, match="qf\\+"):
        fq.Stream(mode="qf")
    with pytest.raises(TypeError, match="unexpected keyword argument 'sigma_x'"):
        fq.Stream(sigma_x=1.0)
    with pytest.raises(TypeError, match="temporal must be a number"):
        fq.Stream(temporal="strong")
