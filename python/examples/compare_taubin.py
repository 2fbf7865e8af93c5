"""Denoise a mesh with fq and with Open3D's Taubin smoothing; compare errors and times.

Run from the repository root:  PYTHONPATH=build/python python3 python/examples/compare_taubin.py
docs/PYTHON.md walks through it and shows its output.
"""
import sys
import time

import numpy as np

import fq

try:
    import open3d as o3d
except ImportError:  # Debian: apt install python3-open3d
    print("compare_taubin: needs open3d (python3-open3d)", file=sys.stderr)
    sys.exit(77)

mesh_path = sys.argv[1] if len(sys.argv) > 1 else "data/fandisk.ply"
V, F = fq.read_mesh(mesh_path)                 # float32 (n, 3), int64 (m, 3)
noisy = fq.add_noise(V, F, 0.2, seed=1)        # 0.2 mean edge lengths per coordinate


def timed(run):
    start = time.perf_counter()
    result = run()
    return result, 1000 * (time.perf_counter() - start)


rows = [("noisy input", fq.metrics(V, F, noisy), 0.0)]
for label, kwargs in [("fq (defaults)", {}), ("fq strength=2", {"strength": 2.0}),
                      ("fq qf (paper)", {"mode": "qf", "sigma_s": 2.0, "sigma_r": 1.0})]:
    fq.filter(noisy, F, engine="cpu", threads=2, **kwargs)  # warm-up: first call allocates
    smoothed, ms = timed(lambda: fq.filter(noisy, F, engine="cpu", threads=2, **kwargs))
    rows.append((label, fq.metrics(V, F, smoothed), ms))

o3d_mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(noisy.astype(np.float64)),
                                     o3d.utility.Vector3iVector(F.astype(np.int32)))
for iterations in (5, 20, 100):
    taubin, ms = timed(lambda: o3d_mesh.filter_smooth_taubin(number_of_iterations=iterations))
    rows.append((f"Open3D Taubin x{iterations}", fq.metrics(V, F, np.asarray(taubin.vertices)), ms))

print(f"{mesh_path}: {len(V)} vertices, {len(F)} triangles, noise 0.2 mean edges (seed 1)")
print(f"{'method':<22}{'RMSE/diag':>11}{'surf RMS':>11}{'MFNE deg':>10}{'ms':>9}")
for label, m, ms in rows:
    print(f"{label:<22}{m['rmse_over_diagonal']:>11.2e}{m['surface_rms_over_diagonal']:>11.2e}"
          f"{m['mfne_deg']:>10.2f}{ms:>9.1f}")

labels = fq.cluster(V, F, engine="cpu", threads=2)
print(f"clusters on the clean mesh: {labels.max() + 1}")
