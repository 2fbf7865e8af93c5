"""fq: filtered quadrics smoothing and clustering of triangle meshes.

Legrand, Thiery & Boubekeur, "Filtered Quadrics for High Speed Geometry Smoothing and
Clustering" (CGF 2019), on the CPU or on an NVIDIA GPU. Meshes are numpy arrays:
V (n, 3) positions and F (m, 3) vertex indices. See docs/PYTHON.md.
"""
from ._fq import (__version__, add_noise, built_with_cuda, cluster, engine_name, filter, metrics,
                  read_mesh, write_mesh)

__all__ = ["add_noise", "built_with_cuda", "cluster", "engine_name", "filter", "metrics", "read_mesh",
           "write_mesh"]
