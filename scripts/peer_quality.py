#!/usr/bin/env python3
"""fq's filters against the smoothers users already have, on mean face normal error (MFNE).

    /usr/bin/python3 scripts/peer_quality.py [--fqfilter build/clients/fqfilter/fqfilter]
        [--meshes ../shared/meshes] [--rows fandisk:0.2:iso,...] [--quick]

For every row (mesh, noise in mean edges, noise direction; seed 7) fqfilter makes the noisy
mesh (its own --noise, written with --noisy-out) and runs fq's methods; then Open3D's
Taubin and Laplacian (python3-open3d) and MeshLab's Taubin, HC Laplacian and TwoStep
(meshlabserver under xvfb-run) run on the same noisy file, each over a small parameter
sweep. Prints the markdown tables of docs/QUALITY.md: per row the best setting of each peer.
MFNE is measured here the way eval/error_metrics.cpp does (faces degenerate in either mesh
skipped); the script checks that it agrees with fqfilter's own number on the noisy input.
A last table gives fq's methods on the clean meshes (damage to a clean input); --clean-only
prints only that one. --quick runs one row (fandisk, iso 0.2) with one setting per peer: a
smoke test. --peer-cache DIR keeps the peers' results under DIR, one file per noisy file named
by its SHA-256 (scripts/peers.py; the same cache as scripts/quality_matrix.py's): peers do not
depend on fq, so a re-run after a change to fq runs only fq (the noisy input is the same for
the same seed, and its hash says so).
"""
import argparse
import os
import sys
import tempfile

import peers  # exits 77 without Open3D

ROWS = ["fandisk:0.3:iso", "bunny:0.3:iso", "igea:0.3:iso", "dragon:0.3:iso",
        "fandisk:0.2:iso", "max_planck:0.2:iso", "bunny:0.2:iso", "igea:0.2:iso",
        "fandisk:0.3:normal", "bunny:0.3:normal"]
SEED = 7
CLEAN = ["fandisk", "max_planck", "bunny", "igea"]

# fq's methods: label, fqfilter arguments.
FQ_METHODS = [
    ("fq qf+ (default)", []),
    ("fq qf (paper, σ 2/1)", peers.QF_ARGS),
]

# Peer sweeps (scripts/peers.py names the peers).
SWEEPS = [("o3d_taubin", [5, 10, 30, 100]), ("o3d_laplacian", [1, 3, 10, 30]),
          ("ml_taubin", [10, 30, 100]), ("ml_hc", [1, 3, 10, 30]),
          ("ml_twostep", [(3, 60), (10, 60), (10, 30), (30, 30)])]


def run_fq(fqfilter, mesh, noise, direction, extra, noisy_out=None):
    args = [mesh, "--noise", str(noise), "--noise-direction", direction, "--seed", str(SEED), "--engine", "cpu", *extra]
    return peers.fqfilter_json(fqfilter, args + (["--noisy-out", noisy_out] if noisy_out else []))


def sweeps(quick):
    if not peers.PEERS["ml_taubin"].available():
        print("(meshlabserver or xvfb-run not found: MeshLab peers skipped)", file=sys.stderr)
    return [(p, settings[:1] if quick else settings) for p, settings in SWEEPS]


def row_table(fqfilter, meshes, row, quick, tmp, cache=None):
    name, noise, direction = row.split(":")
    path = os.path.join(meshes, name + ".ply")
    noisy_path = os.path.join(tmp, "noisy.ply")
    clean, faces = peers.load(path)
    results = []  # (method, setting, mfne)
    for label, extra in FQ_METHODS:
        r = run_fq(fqfilter, path, noise, direction, extra, noisy_out=None if results else noisy_path)
        if not results:
            peers.check_noisy(clean, faces, noisy_path, r)
            results.append(("noisy input", "–", r["metrics"]["input"]["mfne_rad"]))
        ms = sum(p["ms"] for p in r["timings_ms"]["passes"])
        results.append((label, f"CPU {ms:.0f} ms", r["metrics"]["output"]["mfne_rad"]))
    runs = sweeps(quick)
    found, failures = peers.peer_results(noisy_path, clean, faces, runs, tmp, cache)
    for failure in failures:
        print(f"peer failed: {failure}", file=sys.stderr)
    for p, settings in runs:
        peer = peers.PEERS[p]
        scored = [(s, found[peers.key(p, s)]) for s in settings if found.get(peers.key(p, s))]
        for s in settings:
            if peers.key(p, s) in found and found[peers.key(p, s)] is None:
                print(f"{peer.label} {peer.text(s)}: vertex or face order changed; skipped", file=sys.stderr)
        if scored:
            s, (e, _) = min(scored, key=lambda se: se[1][0])
            results.append((peer.label, f"{peer.what} {peer.text(s)}", e))
    return f"{name} {direction} {noise}", len(clean), results


def clean_table(fqfilter, meshes):
    """fq's methods on clean meshes against themselves: how much a clean input is damaged."""
    print("#### Clean meshes filtered, against themselves\n")
    print("| mesh | " + " | ".join(f"{label} MFNE (rad)" for label, _ in FQ_METHODS) + " |")
    print("|---|" + "---:|" * len(FQ_METHODS))
    for name in CLEAN:
        path = os.path.join(meshes, name + ".ply")
        errs = []
        for _, extra in FQ_METHODS:
            r = peers.fqfilter_json(fqfilter, [path, "--reference", path, "--engine", "cpu", *extra])
            errs.append(r["metrics"]["output"]["mfne_rad"])
        print(f"| {name} | " + " | ".join(f"{e:.3f}" for e in errs) + " |")
        sys.stdout.flush()
    print()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fqfilter", default="build/clients/fqfilter/fqfilter")
    ap.add_argument("--meshes", default=os.path.join("..", "shared", "meshes"))
    ap.add_argument("--rows", default=",".join(ROWS), help="mesh:noise:iso|normal, comma separated")
    ap.add_argument("--quick", action="store_true", help="one row, one setting per peer (smoke test)")
    ap.add_argument("--clean-only", action="store_true", help="only the clean-mesh table")
    ap.add_argument("--peer-cache", help="folder keeping peer results between runs (keyed by the noisy file's hash)")
    a = ap.parse_args()
    rows = ["fandisk:0.2:iso"] if a.quick else a.rows.split(",")
    print(f"Machine: {peers.machine()}; fq on its CPU engine; Open3D {peers.o3d.__version__}; noise seed {SEED}.\n")
    if a.clean_only or not a.quick:
        clean_table(a.fqfilter, a.meshes)
    if a.clean_only:
        return
    summary = []
    with tempfile.TemporaryDirectory(prefix="fq_peers_") as tmp:
        for row in rows:
            title, nv, results = row_table(a.fqfilter, a.meshes, row, a.quick, tmp, a.peer_cache)
            print(f"#### {title} ({nv} V)\n\n| method | best setting | MFNE (rad) |\n|---|---|---:|")
            for label, setting, e in results:
                print(f"| {label} | {setting} | {e:.3f} |")
            print()
            sys.stdout.flush()
            fq = dict((r[0], r[2]) for r in results)
            peer = min((r for r in results[len(FQ_METHODS) + 1:]), key=lambda r: r[2], default=None)
            summary.append((title, fq["noisy input"], fq[FQ_METHODS[1][0]], fq[FQ_METHODS[0][0]], peer))
            if a.quick and not fq[FQ_METHODS[0][0]] < fq[FQ_METHODS[1][0]] < fq["noisy input"]:
                sys.exit("peer_quality.py: expected noisy > qf > qf+ on the smoke row")
    print("#### Summary: fq against the best peer setting\n")
    print("| mesh, noise | noisy | fq qf (paper) | fq qf+ (default) | best peer | qf+ vs peer |")
    print("|---|---:|---:|---:|---|---:|")
    for title, noisy, qf, qfp, peer in summary:
        ptxt = f"{peer[2]:.3f} ({peer[0]}, {peer[1]})" if peer else "–"
        gap = f"{100 * (qfp / peer[2] - 1):+.0f}%" if peer else "–"
        print(f"| {title} | {noisy:.3f} | {qf:.3f} | **{qfp:.3f}** | {ptxt} | {gap} |")


if __name__ == "__main__":
    main()
