#!/usr/bin/env python3
"""Temporal filtering against per-frame filtering, on moving and static sequences.

    /usr/bin/python3 scripts/temporal_bench.py [--fqfilter build/clients/fqfilter/fqfilter]
        [--python build/python] [--meshes ../shared/meshes] [--frames 60] [--seed 1]
        [--temporal 0.75] [--only crane,static,...] [--json FILE] [--plot FILE.png] [--quick]

Every sequence is a folder of clean frames; `fqfilter --sequence --noise S --seed K` adds
Gaussian noise of S mean edges to each frame (seed K + frame index) and filters the frames in
order, once each frame alone (--temporal 0) and once with the stream's history (--temporal T).
Per sequence and noise level the table gives, for both runs: mean MFNE (rad) and vertex RMSE
(mean edges of the clean frame) against the clean frames, mean flicker (eval/flicker.h: RMS of
|(r_t - r_t-1) - (c_t - c_t-1)| in mean edges), the surface measures that read the result's
surface and not its vertex ids (fq.surface_flicker, eval/surface_flicker.h; docs/QUALITY.md):
height RMS (mean edges along the clean normals), surface flicker SF (its change from frame to
frame) and shading flicker ShF (the change of the result's smooth-shaded normal the clean one
does not have), the worst frame's MFNE ratio temporal / per-frame, and the median engine time
per frame.

Sequences (--only picks some):
  crane        ../shared/meshes/crane frames 0..N-1, noise 0.1 and 0.2 (a real capture)
  crane_fast   every 4th crane frame (4x the motion: the ghosting test), noise 0.2
  crane_shuffled crane frames with their vertices renumbered differently every frame, the same
               triangles otherwise (track B on crane's own surfaces), noise 0.2
  crane_shuffled_low, crane_fast_shuffled
               crane_shuffled at noise 0.1, and every 4th crane frame shuffled (track B at
               half the noise and at 4x the motion)
  crane_remesh crane frames with their vertices renumbered and about 5 % of edges flipped,
               differently every frame (no vertex id means anything), noise 0.2; flicker
               measured through the known renumbering
  twist        armadillo twisted about its vertical axis by a bend that grows and shrinks over
               the sequence (a synthetic non-rigid motion held out from the tuning), noise 0.2
  static       bunny, the same clean frame N times with fresh noise each frame, noise 0.2
  twist_shuffled, static_shuffled
               twist and static with their vertices renumbered differently every frame (track
               B on motions and surfaces held out from its design)

Needs the fq Python module (--python: the build's python/ folder) to write the generated
sequences and to read results back, and numpy.
"""
import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

import numpy as np


def parse_args():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fqfilter", default=os.path.join(root, "build/clients/fqfilter/fqfilter"))
    p.add_argument("--python", default=os.path.join(root, "build/python"), help="folder with the fq module")
    p.add_argument("--meshes", default=os.environ.get("FQ_MESH_DIR", os.path.join(root, "..", "shared", "meshes")),
                   help="meshes folder (default: $FQ_MESH_DIR, else ../shared/meshes)")
    p.add_argument("--frames", type=int, default=60, help="frames per sequence")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--temporal", type=float, default=None, help="temporal strength (default: fqfilter's)")
    p.add_argument("--only", default="crane,crane_fast,crane_shuffled,crane_remesh,twist,static")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--json", help="write every number here")
    p.add_argument("--plot", help="MFNE, flicker and SF per frame, per-frame vs temporal (PNG)")
    p.add_argument("--quick", action="store_true", help="6 frames of three sequences (the smoke test)")
    return p.parse_args()


def mean_edge(V, F):
    e = np.concatenate([V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 1]], V[F[:, 0]] - V[F[:, 2]]])
    return float(np.linalg.norm(e, axis=1).mean())


def flip_edges(V, F, share, rng):
    """About `share` of the interior edges flipped where the two triangles are nearly coplanar
    and the flip keeps both new triangles facing the same way: a different triangulation of the
    same vertices."""
    F = F.copy()
    m = len(F)
    edges = {}
    for t in range(m):
        for k in range(3):
            edges[(int(F[t, k]), int(F[t, (k + 1) % 3]))] = t
    used = np.zeros(m, bool)
    order = rng.permutation(m)
    target = int(share * 1.5 * m)
    flipped = 0

    def normal(a, b, c):
        n = np.cross(V[b] - V[a], V[c] - V[a])
        ln = np.linalg.norm(n)
        return n / ln if ln > 0 else None

    for t in order:
        if flipped >= target:
            break
        if used[t]:
            continue
        k = rng.integers(3)
        a, b, c = (int(F[t, (k + j) % 3]) for j in range(3))
        u = edges.get((b, a))
        if u is None or used[u]:
            continue
        d = next(int(x) for x in F[u] if x != a and x != b)
        if d == c or (c, d) in edges or (d, c) in edges:
            continue
        n1, n2 = normal(a, b, c), normal(b, a, d)
        n3, n4 = normal(a, d, c), normal(d, b, c)
        if n1 is None or n2 is None or n3 is None or n4 is None:
            continue
        if n1 @ n2 < 0.95 or n3 @ n1 < 0.9 or n4 @ n1 < 0.9:
            continue
        F[t] = (a, d, c)
        F[u] = (d, b, c)
        used[t] = used[u] = True
        for key in ((a, b), (b, c), (c, a), (b, a), (a, d), (d, b)):
            edges.pop(key, None)
        for tri, idx in (((a, d, c), t), ((d, b, c), u)):
            for j in range(3):
                edges[(tri[j], tri[(j + 1) % 3])] = idx
        flipped += 1
    return F


class Sequence:
    def __init__(self, name, folder, noise, frames, perms=None, tracked=None):
        self.name, self.folder, self.noise, self.frames, self.perms = name, folder, noise, frames, perms
        # The clean frames in one vertex order (the re-meshed crane's own crane frames): what
        # the surface measures sample from.
        self.tracked = tracked


def build_sequences(fq, args, work):
    """The clean frames of every sequence, written (or linked) into folders under `work`."""
    crane_dir = os.path.join(args.meshes, "crane")
    n = args.frames
    wanted = args.only.split(",")
    out = []

    def link_frames(name, sources):
        folder = os.path.join(work, name)
        os.makedirs(folder, exist_ok=True)
        for i, src in enumerate(sources):
            os.symlink(os.path.abspath(src), os.path.join(folder, f"f{i:04d}{os.path.splitext(src)[1]}"))
        return folder

    crane = lambda i: os.path.join(crane_dir, f"crane_{i:04d}.drc")  # noqa: E731
    crane_frames = [crane(i) for i in range(n)]
    fast_frames = [crane(4 * i) for i in range(min(n, 175 // 4 + 1))]  # every 4th of crane's 176
    bunny = os.path.join(args.meshes, "bunny.ply")
    if "crane" in wanted:
        folder = link_frames("crane", crane_frames)
        for noise in (0.1, 0.2):
            out.append(Sequence("crane", folder, noise, n))
    if "crane_fast" in wanted:
        out.append(Sequence("crane_fast", link_frames("crane_fast", fast_frames), 0.2, len(fast_frames)))
    def renumbered(name, sources, flipped, noise=0.2):
        """The frames `sources` with their vertices renumbered (and a share `flipped` of edges
        flipped) differently every frame: track B's sequence of the same surfaces."""
        folder = os.path.join(work, name)
        os.makedirs(folder)
        rng = np.random.default_rng(args.seed)
        perms = []
        for i, src in enumerate(sources):
            V, F = fq.read_mesh(src)
            V, F = np.asarray(V, np.float64), np.asarray(F, np.int64)
            if flipped > 0:
                F = flip_edges(V, F, flipped, rng)
            perm = rng.permutation(len(V))  # new vertex j is old vertex perm[j]
            inverse = np.empty_like(perm)
            inverse[perm] = np.arange(len(perm))
            fq.write_mesh(os.path.join(folder, f"f{i:04d}.ply"), V[perm], inverse[F].astype(np.uint32))
            perms.append(perm)
        return Sequence(name, folder, noise, len(sources), perms, list(sources))

    for name, flipped in (("crane_shuffled", 0.0), ("crane_remesh", 0.05)):
        if name in wanted:
            out.append(renumbered(name, crane_frames, flipped))
    if "crane_shuffled_low" in wanted:  # the same at half the noise
        out.append(renumbered("crane_shuffled_low", crane_frames, 0.0, 0.1))
    if "crane_fast_shuffled" in wanted:
        out.append(renumbered("crane_fast_shuffled", fast_frames, 0.0))
    if "twist" in wanted or "twist_shuffled" in wanted:
        folder = os.path.join(work, "twist")
        os.makedirs(folder)
        V, F = fq.read_mesh(os.path.join(args.meshes, "armadillo.ply"))
        V, F = np.asarray(V, np.float64), np.asarray(F, np.uint32)
        lo, hi = V.min(0), V.max(0)
        centre = (lo + hi) / 2
        for i in range(n):
            # up to 0.6 rad of twist from bottom to top, in and out over the sequence
            amount = 0.6 * math.sin(math.pi * i / max(1, n - 1))
            h = (V[:, 1] - lo[1]) / (hi[1] - lo[1])
            a = amount * h
            x, z = V[:, 0] - centre[0], V[:, 2] - centre[2]
            W = V.copy()
            W[:, 0] = centre[0] + np.cos(a) * x - np.sin(a) * z
            W[:, 2] = centre[2] + np.sin(a) * x + np.cos(a) * z
            fq.write_mesh(os.path.join(folder, f"f{i:04d}.ply"), W, F)
        if "twist" in wanted:
            out.append(Sequence("twist", folder, 0.2, n))
        if "twist_shuffled" in wanted:
            out.append(renumbered("twist_shuffled", [os.path.join(folder, f"f{i:04d}.ply") for i in range(n)], 0.0))
    if "static" in wanted:
        out.append(Sequence("static", link_frames("static", [bunny] * n), 0.2, n))
    if "static_shuffled" in wanted:
        out.append(renumbered("static_shuffled", [bunny] * n, 0.0))
    return out


def run_sequence(args, seq, temporal, out_dir):
    cmd = [args.fqfilter, seq.folder, out_dir, "--sequence", "--noise", str(seq.noise), "--seed", str(args.seed),
           "--json", "--quiet", "--engine", "cpu", "--threads", str(args.threads)]
    if temporal is not None:
        cmd += ["--temporal", str(temporal)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"temporal_bench: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
    frames = [json.loads(line) for line in p.stdout.splitlines() if line.strip()]
    if len(frames) != seq.frames:
        sys.exit(f"temporal_bench: {seq.name}: {len(frames)} reports for {seq.frames} frames")
    return frames


def per_frame(fq, seq, frames, clean, threads):
    """MFNE, RMSE (mean edges), flicker per frame (through the renumbering when re-meshed), and
    the surface measures (the results as written, sampled from the tracked clean frames)."""
    mfne = [f["metrics"]["output"]["mfne_rad"] for f in frames]
    rmse, flick = [], [None]
    results = []
    for i, f in enumerate(frames):
        V, F = fq.read_mesh(f["output"])
        R = np.asarray(V, np.float64)
        C, _, edge = clean[i]
        if seq.perms is not None:  # back to the crane's own vertex order
            R = R[np.argsort(seq.perms[i])]
        rmse.append(float(np.sqrt(((R - C) ** 2).sum(1).mean()) / edge))
        results.append(R)
        if i > 0:
            d = (R - results[i - 1]) - (C - clean[i - 1][0])
            flick.append(float(np.sqrt((d ** 2).sum(1).mean()) / edge))

    def surfaces():
        for (C, CF, _), f in zip(clean, frames):
            V, F = fq.read_mesh(f["output"])  # the result's own vertex order and triangles
            yield C, CF, V, F

    surface = fq.surface_flicker(surfaces(), threads=threads)["frames"]
    return mfne, rmse, flick, surface


def clean_frames(fq, seq):
    """Per frame its clean positions and triangles (in the first frame's vertex order) and mean edge."""
    out = []
    names = seq.tracked or [os.path.join(seq.folder, name) for name in sorted(os.listdir(seq.folder))]
    for path in names:
        V, F = fq.read_mesh(path)
        V, F = np.asarray(V, np.float64), np.asarray(F, np.int64)
        out.append((V, F, mean_edge(V, F)))
    return out


def mean_of(values):
    kept = [x for x in values if x is not None]
    return statistics.mean(kept) if kept else float("nan")


def summarize(mfne, rmse, flick, surface, ms):
    return {"mfne": statistics.mean(mfne), "rmse": statistics.mean(rmse), "flicker": mean_of(flick),
            "height_rms": mean_of([f["height_rms"] for f in surface]),
            "smooth_normal_error": mean_of([f["smooth_normal_error_rad"] for f in surface]),
            "sf": mean_of([f["surface_flicker"] for f in surface]),
            "shf": mean_of([f["shading_flicker"] for f in surface]), "ms": statistics.median(ms)}


def main():
    args = parse_args()
    if args.quick:
        args.frames, args.only = 6, "crane,crane_shuffled,static"
    wanted = args.only.split(",")
    needed = [os.path.join(args.meshes, "crane", "crane_0000.drc")] if any(w.startswith("crane") for w in wanted) else []
    needed += [os.path.join(args.meshes, f) for w, f in (("twist", "armadillo.ply"), ("static", "bunny.ply"))
               if w in wanted or w + "_shuffled" in wanted]
    if missing := [p for p in needed if not os.path.exists(p)]:
        print(f"temporal_bench: skipped: no {missing[0]} (--meshes)")
        sys.exit(77)
    sys.path.insert(0, args.python)
    import fq  # noqa: E402 (from --python)

    rows = []
    with tempfile.TemporaryDirectory(prefix="fq_temporal_") as work:
        sequences = build_sequences(fq, args, work)
        for seq in sequences:
            clean = clean_frames(fq, seq)
            row = {"sequence": seq.name, "noise": seq.noise, "frames": seq.frames}
            curves = {}
            for label, temporal in (("per_frame", 0.0), ("temporal", args.temporal)):
                out_dir = os.path.join(work, f"out_{seq.name}_{seq.noise}_{label}")
                frames = run_sequence(args, seq, temporal, out_dir)
                mfne, rmse, flick, surface = per_frame(fq, seq, frames, clean, args.threads)
                ms = [f["timings_ms"]["total"] for f in frames]
                row[label] = summarize(mfne, rmse, flick, surface, ms)
                curves[label] = {"mfne": mfne, "rmse": rmse, "flicker": flick,
                                 "height_rms": [f["height_rms"] for f in surface],
                                 "sf": [f["surface_flicker"] for f in surface],
                                 "shf": [f["shading_flicker"] for f in surface]}
                if label == "temporal":
                    row["scene_cuts"] = sum(1 for f in frames if f.get("temporal", {}).get("history_reset"))
                shutil.rmtree(out_dir)
            ratios = [t / p for t, p in zip(curves["temporal"]["mfne"][1:], curves["per_frame"]["mfne"][1:])]
            row["worst_frame_ratio"] = max(ratios) if ratios else float("nan")
            row["curves"] = curves
            rows.append(row)
            print_row(row, header=len(rows) == 1)
    if args.quick:  # the smoke test: every surface measure came back
        bad = [r["sequence"] for r in rows for label in ("per_frame", "temporal")
               if not all(math.isfinite(r[label][k]) for k in ("height_rms", "sf", "shf", "smooth_normal_error"))]
        if bad:
            sys.exit(f"temporal_bench: surface measures missing for {', '.join(bad)}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    if args.plot:
        plot(rows, args.plot)


def print_row(r, header):
    if header:
        print("| sequence | noise | frames | MFNE per-frame | MFNE temporal | RMSE per-frame | RMSE temporal "
              "| flicker per-frame | flicker temporal | height RMS per-frame | height RMS temporal "
              "| SF per-frame | SF temporal | ShF per-frame | ShF temporal | worst frame | ms per-frame "
              "| ms temporal |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    p, t = r["per_frame"], r["temporal"]
    cells = [r["sequence"], str(r["noise"]), str(r["frames"])]
    for key in ("mfne", "rmse", "flicker", "height_rms", "sf", "shf"):
        cells += [f"{p[key]:.4f}", f"{t[key]:.4f}"]
    cells += [f"{r['worst_frame_ratio']:.3f}", f"{p['ms']:.1f}", f"{t['ms']:.1f}"]
    print("| " + " | ".join(cells) + " |", flush=True)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    what_label = {"mfne": "MFNE (rad)", "flicker": "flicker (mean edges)", "sf": "SF (mean edges)"}
    fig, axes = plt.subplots(len(what_label), len(rows), figsize=(3.2 * len(rows), 8), squeeze=False)
    for k, r in enumerate(rows):
        for j, what in enumerate(what_label):
            ax = axes[j][k]
            for label, style in (("per_frame", "C0"), ("temporal", "C3")):
                ys = r["curves"][label][what]
                xs = [i for i, y in enumerate(ys) if y is not None]
                ax.plot(xs, [ys[i] for i in xs], style, lw=1, label=label.replace("_", "-"))
            ax.set_title(f"{r['sequence']} {r['noise']}" if j == 0 else "", fontsize=9)
            ax.set_ylabel(what_label[what], fontsize=8)
            ax.set_xlabel("frame", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.set_ylim(bottom=0)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
