"""fq: filtered quadrics smoothing and clustering of triangle meshes.

Legrand, Thiery & Boubekeur, "Filtered Quadrics for High Speed Geometry Smoothing and
Clustering" (CGF 2019), on the CPU or on an NVIDIA GPU. A mesh is numpy arrays, V (n, 3)
positions and F (m, 3) vertex indices, or a `Mesh` that also carries colours, normals and
texture coordinates (and converts to and from trimesh and Open3D meshes). Every function
has a numpy-style docstring; see also docs/PYTHON.md. Producer and Consumer connect a capture
pipeline to the fqd daemon; fq.wire holds its message codec.
"""
from . import wire
from ._client import Consumer, Producer
from ._engine import _param_names, cluster, engine_name, filter
from ._fq import __version__, built_with_cuda
from ._files import read_mesh, write_mesh
from ._measures import add_noise, metrics, scan_error, surface_flicker, surface_sample
from ._stream import Stream
from .mesh import Mesh

__all__ = ["Consumer", "Mesh", "Producer", "Stream", "add_noise", "built_with_cuda", "cluster", "engine_name",
           "filter", "metrics", "read_mesh", "scan_error", "surface_flicker", "surface_sample", "wire",
           "write_mesh"]
