# %% [markdown]
# # fq next to Open3D, in pictures
#
# A notebook in script form (each `# %%` is a cell; Jupyter, VS Code and `jupytext` open it as
# one). It adds noise to a mesh, smooths it with fq's default filter and with Open3D's Taubin
# smoothing, prints their errors against the clean mesh and draws the three side by side.
#
# Run from the repository root (Open3D and matplotlib are Debian's `python3-open3d` and
# `python3-matplotlib`):
#
#     PYTHONPATH=build/python python3 python/examples/fq_vs_open3d.py data/fandisk.ply docs/fq-vs-open3d.png

# %%
import sys

import numpy as np

import fq

try:
    import matplotlib
    import open3d  # noqa: F401 (fq converts to and from its meshes)
except ImportError:
    print("fq_vs_open3d: needs open3d and matplotlib (python3-open3d, python3-matplotlib)", file=sys.stderr)
    sys.exit(77)
matplotlib.use("Agg")  # draws into a file, no display needed
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

mesh_path = sys.argv[1] if len(sys.argv) > 1 else "data/fandisk.ply"
picture = sys.argv[2] if len(sys.argv) > 2 else "fq-vs-open3d.png"

# %% [markdown]
# ## The same noisy input for both
# `fq.read_mesh` gives an `fq.Mesh`; `add_noise` draws Gaussian noise of 0.3 mean edge lengths
# per coordinate, the same on every machine for a given seed.

# %%
clean = fq.read_mesh(mesh_path)
noisy = fq.Mesh(fq.add_noise(clean.vertices, clean.faces, 0.3, seed=1), clean.faces)

# %% [markdown]
# ## Smooth
# fq takes the Open3D mesh itself and gives an Open3D mesh back; its defaults are fqfilter's.
# Taubin needs an iteration count; 20 was the best of 5, 20 and 100 on this mesh
# (python/examples/compare_taubin.py).

# %%
o3d_noisy = noisy.to_open3d()
by_fq = fq.filter(o3d_noisy, engine="cpu", threads=2)
by_taubin = o3d_noisy.filter_smooth_taubin(number_of_iterations=20)

results = {"noisy input": noisy.vertices, "fq (defaults)": np.asarray(by_fq.vertices),
           "Open3D Taubin x20": np.asarray(by_taubin.vertices)}
for name, positions in results.items():
    m = fq.metrics(clean.vertices, clean.faces, positions)
    print(f"{name:<20} face-normal error {m['mfne_deg']:6.2f} deg, "
          f"surface RMS / diagonal {m['surface_rms_over_diagonal']:.2e}")

# %% [markdown]
# ## Draw
# Flat-shaded triangles under one light, the same view for all three.


# %%
def draw(ax, vertices, faces, title):
    corners = vertices[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    shade = 0.25 + 0.75 * np.clip(np.abs(normals @ light), 0, 1)
    colours = np.stack([shade * 0.55, shade * 0.7, shade * 0.9, np.ones_like(shade)], axis=1)
    ax.add_collection3d(Poly3DCollection(corners, facecolors=colours, linewidths=0, antialiased=False))
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for axis, c in zip("xyz", centre):
        getattr(ax, f"set_{axis}lim")(c - half, c + half)
    ax.view_init(elev=25, azim=-60)
    ax.set_box_aspect(None, zoom=1.25)
    ax.set_axis_off()
    ax.set_title(title)


figure = plt.figure(figsize=(12, 3.6), dpi=100)
for i, (name, positions) in enumerate(results.items()):
    draw(figure.add_subplot(1, 3, i + 1, projection="3d"), positions, clean.faces, name)
figure.subplots_adjust(left=0, right=1, bottom=0, top=0.92, wspace=0)
figure.savefig(picture)
print("wrote", picture)
