"""fq.surface_sample and fq.surface_flicker against the same measures written again with numpy,
SciPy and Open3D, on a noisy crane frame whose vertices are renumbered (ids must not matter).

The crossings are found here with numpy (Möller–Trumbore over the triangles a SciPy k-d tree
puts near each vertex) and the closest points with Open3D's RaycastingScene: its cast_rays hits
nothing with Debian's python3-open3d 0.16 and embree 3.13 (a ray without embree's ray mask
set), while compute_closest_points works."""
import os
import pathlib

import numpy as np
import pytest

import fq

MESHES = pathlib.Path(os.environ.get("FQ_MESH_DIR", pathlib.Path(__file__).resolve().parents[3] / "shared" / "meshes"))
REACH = 3.0  # clean mean edges, as eval/surface_flicker.h


def crane(i):
    path = MESHES / "crane" / f"crane_{i:04d}.drc"
    if not path.exists():
        pytest.skip(f"no {path} (FQ_MESH_DIR)")
    V, F = fq.read_mesh(path)
    return np.asarray(V, np.float64), np.asarray(F, np.int64)


def area_normals(V, F):
    """Per vertex the sum of its triangles' cross products, and a third of their areas."""
    c = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n = np.zeros_like(V)
    area = np.zeros(len(V))
    for k in range(3):
        np.add.at(n, F[:, k], c)
        np.add.at(area, F[:, k], np.linalg.norm(c, axis=1) / 6)
    return n, area


def unit(x):
    length = np.linalg.norm(x, axis=-1, keepdims=True)
    return np.divide(x, length, out=np.zeros_like(x), where=length > 0)


def barycentric(P, A, B, C):
    e1, e2, d = B - A, C - A, P - A
    d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    det = d11 * d22 - d12 * d12
    u = (d22 * (d * e1).sum(1) - d12 * (d * e2).sum(1)) / det
    v = (d11 * (d * e2).sum(1) - d12 * (d * e1).sum(1)) / det
    return np.stack([1 - u - v, u, v], 1)


def nearest_crossings(C, N, RV, RF, reach):
    """Per line C + s·N the crossing with the triangles (RV, RF) of smallest |s| <= reach:
    (s, triangle), inf and -1 where there is none."""
    from scipy.spatial import cKDTree
    A, B, D = RV[RF[:, 0]], RV[RF[:, 1]], RV[RF[:, 2]]
    centroid = (A + B + D) / 3
    spread = np.linalg.norm(np.stack([A, B, D]) - centroid, axis=2).max()
    near = cKDTree(centroid).query_ball_point(C, reach + spread)
    line = np.repeat(np.arange(len(C)), [len(x) for x in near])
    tri = np.concatenate([np.asarray(x, np.int64) for x in near])
    e1, e2, o, d = B[tri] - A[tri], D[tri] - A[tri], C[line] - A[tri], N[line]
    h = np.cross(d, e2)
    det = (e1 * h).sum(1)
    ok = np.abs(det) > 1e-300
    det = np.where(ok, det, 1.0)
    u = (o * h).sum(1) / det
    q = np.cross(o, e1)
    v = (d * q).sum(1) / det
    t = (e2 * q).sum(1) / det
    ok &= (u >= -1e-12) & (v >= -1e-12) & (u + v <= 1 + 1e-12) & (np.abs(t) <= reach)
    line, tri, t = line[ok], tri[ok], t[ok]
    order = np.lexsort((tri, np.abs(t), line))  # per line the smallest |s|, then the lowest index
    line, tri, t = line[order], tri[order], t[order]
    first = np.r_[True, line[1:] != line[:-1]]
    s = np.full(len(C), np.inf)
    best = np.full(len(C), -1)
    s[line[first]] = t[first]
    best[line[first]] = tri[first]
    return s, best


def reference_sample(CV, CF, RV, RF):
    """The sampler of eval/surface_flicker.h written again."""
    o3d = pytest.importorskip("open3d")
    pytest.importorskip("scipy")
    edge = np.linalg.norm(np.concatenate([CV[CF[:, 1]] - CV[CF[:, 0]], CV[CF[:, 2]] - CV[CF[:, 1]],
                                          CV[CF[:, 0]] - CV[CF[:, 2]]]), axis=1).mean()
    n_sum, area = area_normals(CV, CF)
    nc = unit(n_sum)
    rn = unit(area_normals(RV, RF)[0])
    s, tri = nearest_crossings(CV, nc, RV, RF, REACH * edge)
    hit = tri >= 0
    P = CV + np.where(hit, s, 0)[:, None] * nc
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(RV.astype(np.float32)), o3d.core.Tensor(RF.astype(np.uint32)))
    closest = scene.compute_closest_points(o3d.core.Tensor(CV[~hit].astype(np.float32)))
    P[~hit] = closest["points"].numpy()
    tri[~hit] = closest["primitive_ids"].numpy()
    s[~hit] = ((P[~hit] - CV[~hit]) * nc[~hit]).sum(1)
    w = barycentric(P, RV[RF[tri, 0]], RV[RF[tri, 1]], RV[RF[tri, 2]])
    nr = unit((w[:, :, None] * rn[RF[tri]]).sum(1))
    return {"height": s / edge, "result_normal": nr, "clean_normal": nc, "area": area, "hit": hit, "mean_edge": edge}


def weighted_rms(area, x):
    return float(np.sqrt((area * x).sum() / area.sum()))


def noisy_renumbered(V, F, seed):
    """V with 0.2 mean edges of noise, its vertices renumbered: the same surface, other ids."""
    noisy = fq.add_noise(V, F, 0.2, seed=seed)
    perm = np.random.default_rng(seed).permutation(len(V))
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    return noisy[perm], inverse[F]


def test_sample_matches_open3d_on_a_noisy_renumbered_crane():
    V, F = crane(0)
    RV, RF = noisy_renumbered(V, F, 5)
    ours = fq.surface_sample(V, F, RV, RF, threads=2)
    ref = reference_sample(V, F, RV, RF)
    assert ours["mean_edge"] == pytest.approx(ref["mean_edge"], rel=1e-9)
    np.testing.assert_allclose(ours["area"], ref["area"], rtol=1e-6, atol=1e-12 * ref["area"].max())
    np.testing.assert_allclose(ours["clean_normal"], ref["clean_normal"], atol=1e-9)
    # Both in doubles: the same crossings, but for a line through an edge where rounding picks
    # the other triangle (the same height) and the closest points Open3D finds in float32.
    np.testing.assert_array_equal(ours["hit"], ref["hit"])
    same = np.abs(ours["height"] - ref["height"]) < 1e-6
    assert same.mean() > 0.999, f"{(~same).sum()} of {len(same)} heights differ"
    missed = ~ref["hit"]  # a few lines leave the crane's thin parts unmet: the closest point
    assert 0 < missed.sum() < 0.01 * len(missed)
    np.testing.assert_allclose(ours["height"][missed], ref["height"][missed], atol=1e-4)
    turned = np.linalg.norm(ours["result_normal"] - ref["result_normal"], axis=1)
    assert (turned < 1e-3).mean() > 0.999
    assert ours["height_rms"] == pytest.approx(weighted_rms(ref["area"], ref["height"] ** 2), rel=1e-3)
    angle = np.arctan2(np.linalg.norm(np.cross(ref["result_normal"], ref["clean_normal"]), axis=1),
                       (ref["result_normal"] * ref["clean_normal"]).sum(1))
    assert ours["smooth_normal_error_rad"] == pytest.approx((ref["area"] * angle).sum() / ref["area"].sum(), rel=1e-3)
    # 0.2 mean edges of iso noise: about 0.2 along the normal, and a visible normal error.
    assert 0.12 < ours["height_rms"] < 0.3
    assert ours["smooth_normal_error_rad"] > 0.05


def test_flicker_of_two_frames_matches_open3d():
    frames = [crane(i) for i in (0, 1)]
    results = [noisy_renumbered(V, F, 10 + i) for i, (V, F) in enumerate(frames)]
    ours = fq.surface_flicker(((V, F, RV, RF) for (V, F), (RV, RF) in zip(frames, results)), threads=2)
    a, b = (reference_sample(V, F, RV, RF) for (V, F), (RV, RF) in zip(frames, results))
    sf = weighted_rms(b["area"], (b["height"] - a["height"]) ** 2)
    d = (b["result_normal"] - a["result_normal"]) - (b["clean_normal"] - a["clean_normal"])
    shf = weighted_rms(b["area"], (d ** 2).sum(1))
    assert ours["transitions"] == 1
    assert ours["frames"][0]["surface_flicker"] is None
    assert ours["surface_flicker"] == pytest.approx(sf, rel=2e-3)
    assert ours["shading_flicker"] == pytest.approx(shf, rel=2e-3)
    # Independent noise each frame: SF about sqrt(2) times the height RMS.
    assert ours["surface_flicker"] == pytest.approx(np.sqrt(2) * ours["height_rms"], rel=0.2)


def test_a_result_that_is_the_clean_frame_has_no_error_and_no_flicker():
    V, F = crane(0)
    W, G = crane(1)
    out = fq.surface_flicker([(V, F, V, F), (W, G, W, G)], threads=2)
    assert out["height_rms"] == pytest.approx(0.0, abs=1e-6)
    assert out["smooth_normal_error_rad"] == pytest.approx(0.0, abs=1e-6)
    assert out["surface_flicker"] == pytest.approx(0.0, abs=1e-6)
    assert out["shading_flicker"] == pytest.approx(0.0, abs=1e-6)


def test_a_frame_that_is_not_four_arrays_is_refused():
    V, F = crane(0)
    with pytest.raises(ValueError, match="clean_V, clean_F, result_V, result_F"):
        fq.surface_flicker([(V, F, V)])
