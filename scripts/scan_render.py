"""Close-up pictures of a raw scan and its filtered versions for scripts/scan_quality.py --render:
the same patch of the surface, flat-shaded by its face normals, seen along the patch's mean
normal, one panel per method (matplotlib only: no GPU, no window)."""
import numpy as np

LIGHT = np.array([0.35, 0.45, 0.82])


def middle(v, f, radius_edges=14.0):
    """The scan's middle vertex (the one nearest the centroid of the vertices) and a close-up
    radius of `radius_edges` mean edges around it."""
    edges = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1), axis=0)
    ell = np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean()
    used = np.unique(f)
    return v[used[np.argmin(np.linalg.norm(v[used] - v[used].mean(axis=0), axis=1))]], radius_edges * ell


def patch(v, f, centre, radius):
    """Indices of the faces whose centroid is within radius of centre."""
    return np.flatnonzero(np.linalg.norm(v[f].mean(axis=1) - centre, axis=1) < radius)


def view_frame(v, f, faces):
    """An orthonormal frame (right, up, towards the viewer) looking along the patch's mean normal."""
    n = np.cross(v[f[faces, 1]] - v[f[faces, 0]], v[f[faces, 2]] - v[f[faces, 0]]).sum(axis=0)
    z = n / np.linalg.norm(n)
    x = np.cross(z, [0.0, 1.0, 0.0] if abs(z[1]) < 0.9 else [1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    return x, np.cross(z, x), z


def draw(ax, v, f, faces, frame, title):
    from matplotlib.collections import PolyCollection
    x, y, z = frame
    tri = v[f[faces]]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-30)[:, None]
    n *= np.sign(n @ z)[:, None]  # both windings lit alike
    light = LIGHT[0] * x + LIGHT[1] * y + LIGHT[2] * z
    shade = 0.15 + 0.85 * np.clip(n @ light, 0.0, 1.0)
    order = np.argsort(tri.mean(axis=1) @ z)  # far faces first
    xy = np.stack([tri @ x, tri @ y], axis=-1)[order]
    ax.add_collection(PolyCollection(xy, facecolors=np.repeat(shade[order, None], 3, axis=1), edgecolors="none"))
    ax.set_xlim(xy[..., 0].min(), xy[..., 0].max())
    ax.set_ylim(xy[..., 1].min(), xy[..., 1].max())
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def render(path, panels):
    """panels: [(title, positions, faces)]; the first (the raw scan) chooses the patch and the
    view, and every panel shows its faces around the same point (a reference with other
    triangles too)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    _, v0, f0 = panels[0]
    centre, radius = middle(v0, f0)
    frame = view_frame(v0, f0, patch(v0, f0, centre, radius))
    fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3.4), dpi=110)
    for ax, (title, v, f) in zip(np.atleast_1d(axes), panels):
        draw(ax, v, f, patch(v, f, centre, radius), frame, title)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(path)
    plt.close(fig)
