#!/usr/bin/env python3
"""The quality matrix: fq's default filter against the best setting of every other smoother,
over meshes × noise levels × noise directions × seeds, on MFNE and vertex RMSE.

    /usr/bin/python3 scripts/quality_matrix.py [--fqfilter build/clients/fqfilter/fqfilter]
        [--meshes ../shared/meshes] [--mesh fandisk,bunny,crane_0060,PATH.ply,PATH.drc,...]
        [--iso 0.05,0.1,...] [--normal 0.2,0.3] [--structured depth:0.1,correlated2:0.2,...]
        [--seeds 1,2] [--jobs N] [--fq-args "..."]
        [--peer-cache DIR] [--json FILE] [--plot docs/quality-matrix.png] [--quick]

A row is one noisy file: fqfilter adds its own noise to the clean mesh (--noise S
--noise-kind iso|normal|... --seed K, σ in mean edges of the clean mesh), writes it
(--noisy-out) and runs fq's default on it in the same call ("fq default": fqfilter's defaults
and --fq-args); then the paper's QF runs on that file, and every peer (scripts/peers.py) over its
sweep of settings. The row's "best peer" is the peer setting with the lowest MFNE. A mesh is a
name looked up in --meshes (NAME.ply, NAME.drc, or one folder down: crane_0060 is
crane/crane_0060.drc) or a path to a .ply or .drc file; a .drc is decoded with Draco's
draco_decoder to the PLY that is the clean reference, after fqfilter has confirmed that it reads
the .drc as the same vertices in the same order with the same faces. The script measures MFNE
and RMSE itself and checks them against fqfilter's report on every noisy input.

Structured rows (--structured KIND:S,...; eval/noise.h) add the noise real acquisition makes:
`depth` (a range scanner's, along one view direction, growing at grazing angles),
`correlatedL` (along the normals, correlated over L mean edges) and `rippleP` (scan-line stripes of
period P mean edges); they are summarized apart from the white rows (iso, normal).

Output: markdown on stdout (summary, matrix, clean table: every mesh filtered without noise,
against itself), --json FILE with every number, --plot FILE.png MFNE against isotropic noise
(one panel per mesh, seeds averaged) and FILE-rmse.png the same for vertex RMSE. --quick: one
small row, one setting per peer (the ctest smoke test). Rows run in --jobs worker processes;
--peer-cache DIR keeps the peers' results (scripts/peers.py says how), so that a re-run after a
change to fq runs only fq.
"""
import argparse
import concurrent.futures
import glob
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from types import SimpleNamespace

import peers  # exits 77 without Open3D
from peers import np
import quality_matrix_report as report

MESHES = ["fandisk", "bunny", "igea", "max_planck", "armadillo", "crane_0000", "crane_0060", "crane_0120"]
ISO = [0.05, 0.1, 0.15, 0.2, 0.3, 0.5]
NORMAL = [0.2, 0.3]
STRUCTURED = [("depth", 0.1), ("depth", 0.2), ("correlated2", 0.1), ("correlated2", 0.2),
              ("ripple3", 0.1), ("ripple3", 0.2)]
SEEDS = [1, 2]
MOVED = 1e-6
CLEAN = MESHES + ["dragon", "gargoyle"]  # the clean table of a default run: every shared mesh
SWEEPS = [("o3d_laplacian", [1, 2, 3, 5, 8, 12, 20, 30]),
          ("o3d_taubin", [3, 5, 10, 20, 30, 50, 100, 200]),
          ("o3d_simple", [1, 2, 3, 5, 8, 12, 20, 30]),
          ("ml_taubin", [5, 10, 20, 30, 50, 100]),
          ("ml_hc", [1, 2, 3, 5, 10, 20]),
          ("ml_twostep", [(3, 60), (10, 60), (10, 30), (30, 30)])]


def find_mesh(spec, folder):
    if spec.lower().endswith((".ply", ".drc")):
        return spec
    for pattern in (f"{spec}.ply", f"{spec}.drc", f"*/{spec}.ply", f"*/{spec}.drc"):
        found = sorted(glob.glob(os.path.join(glob.escape(folder), pattern)))
        if found:
            return found[0]
    raise SystemExit(f"quality_matrix.py: no mesh '{spec}' in {folder} (NAME.ply, NAME.drc, */NAME.*) "
                     "and not a .ply or .drc path")


def prepare_mesh(spec, cfg):
    """The mesh's clean PLY (a .drc decoded), its label and size."""
    source = find_mesh(spec, cfg.meshes)
    if not os.path.isfile(source):
        raise SystemExit(f"quality_matrix.py: {source}: no such file")
    label = os.path.splitext(os.path.basename(source))[0]
    clean = source
    if source.lower().endswith(".drc"):
        clean = os.path.join(cfg.work, label + ".ply")
        subprocess.run(["draco_decoder", "-i", source, "-o", clean], check=True, capture_output=True)
        r = peers.fqfilter_json(cfg.fqfilter, [source, "--reference", clean, "--engine", "cpu", *peers.QF_ARGS])
        seen = r["metrics"]["input"]
        if seen["mfne_rad"] != 0 or seen["rmse_over_diagonal"] != 0:
            raise SystemExit(f"quality_matrix.py: fqfilter reads {source} other than draco_decoder decodes it: {seen}")
    v, f = peers.load(clean)
    if len(f) == 0:
        raise SystemExit(f"quality_matrix.py: {source}: no triangles")
    return SimpleNamespace(label=label, source=source, clean=clean, vertices=len(v), faces=len(f))


def fq_default(cfg):
    return ["--engine", cfg.engine, *cfg.fq_args]


def noise_args(direction):
    """fqfilter's arguments for a row's noise: 'iso', 'depth', 'correlated2' (length 2), 'ripple3'."""
    kind = direction.rstrip("0123456789.")
    length = direction[len(kind):]
    return ["--noise-kind", kind] + (["--noise-length", length] if length else [])


def parse_structured(text):
    """'depth:0.1,correlated2:0.2' as [('depth', 0.1), ('correlated2', 0.2)]."""
    out = []
    for item in filter(None, (x.strip() for x in text.split(","))):
        direction, _, level = item.partition(":")
        kind = direction.rstrip("0123456789.")
        if kind not in ("depth", "correlated", "ripple") or (kind != "depth" and kind == direction):
            raise ValueError(f"'{item}': expected depth:S, correlatedL:S or rippleP:S")
        out.append((direction, float(level)))
    return out


def run_row(cfg, mesh, direction, noise, seed):
    """One noisy file: fq default (which makes it), the paper's QF, every peer setting."""
    t0 = time.time()
    tmp = tempfile.mkdtemp(dir=cfg.work, prefix=f"{mesh.label}_{direction}_{noise}_{seed}_")
    noisy = os.path.join(tmp, "noisy.ply")
    clean, faces = peers.load(mesh.clean)
    fq = peers.fqfilter_json(cfg.fqfilter, [mesh.clean, "--noise", str(noise), *noise_args(direction),
                                            "--seed", str(seed), "--noisy-out", noisy, *fq_default(cfg)])
    noisy_err = peers.check_noisy(clean, faces, noisy, fq)
    qf = peers.fqfilter_json(cfg.fqfilter, [noisy, "--reference", mesh.clean, "--engine", cfg.engine, *peers.QF_ARGS])
    t_fq = time.time() - t0
    peer_seconds = {}
    found, peer_failures = peers.peer_results(noisy, clean, faces, cfg.sweeps, tmp, cfg.cache, peer_seconds)
    digest = peers.sha256_file(noisy)
    shutil.rmtree(tmp)
    out = fq["metrics"]["output"]
    return {"mesh": mesh.label, "vertices": mesh.vertices, "direction": direction, "noise": noise, "seed": seed,
            "noisy_sha256": digest, "noisy": {"mfne": noisy_err[0], "rmse": noisy_err[1]},
            "fq_default": {"mfne": out["mfne_rad"], "rmse": out["rmse_over_diagonal"],
                           "ms": sum(p["ms"] for p in fq["timings_ms"]["passes"])},
            "fq_qf": {"mfne": qf["metrics"]["output"]["mfne_rad"],
                      "rmse": qf["metrics"]["output"]["rmse_over_diagonal"]},
            "peers": found, "peer_failures": peer_failures,
            "seconds": {"fq": t_fq, "peers": time.time() - t0 - t_fq, **peer_seconds}}


def run_clean(cfg, mesh):
    """The clean mesh filtered, against itself: fq default (and how many vertices it moved), QF."""
    tmp = tempfile.mkdtemp(dir=cfg.work, prefix=f"{mesh.label}_clean_")
    out_path = os.path.join(tmp, "out.ply")
    fq = peers.fqfilter_json(cfg.fqfilter, [mesh.clean, out_path, "--reference", mesh.clean, *fq_default(cfg)])
    qf = peers.fqfilter_json(cfg.fqfilter, [mesh.clean, "--reference", mesh.clean, "--engine", cfg.engine,
                                            *peers.QF_ARGS])
    clean, _ = peers.load(mesh.clean)
    out, _ = peers.load(out_path)
    shutil.rmtree(tmp)
    # An unmoved vertex comes back within float round-off of the normalization (2e-8 of the
    # diagonal on fandisk and the bunny); "moved" is more than MOVED of the diagonal.
    diagonal = np.linalg.norm(clean.max(axis=0) - clean.min(axis=0))
    moved = int((np.linalg.norm(out - clean, axis=1) > MOVED * diagonal).sum()) if out.shape == clean.shape else None
    return {"mesh": mesh.label, "vertices": mesh.vertices,
            "fq_default": {"mfne": fq["metrics"]["output"]["mfne_rad"],
                           "rmse": fq["metrics"]["output"]["rmse_over_diagonal"], "moved": moved},
            "fq_qf": {"mfne": qf["metrics"]["output"]["mfne_rad"]}}


def run_all(cfg, jobs, tasks):
    """Runs (function, args) tasks on `jobs` processes, the largest meshes first; results in task
    order, failures as (task text, error) (the rest still runs)."""
    order = sorted(range(len(tasks)), key=lambda i: -tasks[i][1][0].vertices)
    results, failed = [None] * len(tasks), []
    t0 = time.time()
    with concurrent.futures.ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(tasks[i][0], cfg, *tasks[i][1]): i for i in order}
        for n, fut in enumerate(concurrent.futures.as_completed(futures), 1):
            i = futures[fut]
            name = " ".join(str(a.label if hasattr(a, "label") else a) for a in tasks[i][1])
            try:
                results[i] = fut.result()
            except Exception as e:  # a failed row is reported and counted, the others still run
                failed.append((name, str(e)))
            print(f"[{n}/{len(tasks)} {time.time() - t0:.0f} s] {name}{' FAILED' if results[i] is None else ''}",
                  file=sys.stderr, flush=True)
    return [r for r in results if r is not None], failed


def floats(text):
    return [float(x) for x in text.split(",") if x.strip()]


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fqfilter", default="build/clients/fqfilter/fqfilter")
    ap.add_argument("--meshes", default=os.path.join("..", "shared", "meshes"), help="folder of the named meshes")
    ap.add_argument("--mesh", help=f"names or .ply/.drc paths, comma separated (default {','.join(MESHES)})")
    ap.add_argument("--iso", help=f"isotropic noise levels in mean edges (default {','.join(map(str, ISO))})")
    ap.add_argument("--normal", help=f"normal-direction noise levels (default {','.join(map(str, NORMAL))}); "
                    "'' for none")
    ap.add_argument("--structured", help="structured noise rows KIND:S, comma separated (default "
                    f"{','.join(f'{d}:{s:g}' for d, s in STRUCTURED)}); '' for none")
    ap.add_argument("--seeds", help=f"noise seeds (default {','.join(map(str, SEEDS))})")
    ap.add_argument("--clean-mesh", help="meshes of the clean table (default: every shared mesh, or those of "
                    "--mesh when it is given); '' for none")
    ap.add_argument("--jobs", type=int, default=os.cpu_count(), help="worker processes")
    ap.add_argument("--engine", default="cpu", choices=["cpu", "cuda", "auto"], help="fqfilter's engine")
    ap.add_argument("--fq-args", default="", help="extra fqfilter arguments for fq default (e.g. \"--sigma-s 2\")")
    ap.add_argument("--peers", default=",".join(p for p, _ in SWEEPS),
                    help="peers to run, comma separated (default: all; MeshLab's TwoStep takes most of a cold run)")
    ap.add_argument("--peer-cache", help="folder keeping peer results between runs (scripts/peers.py)")
    ap.add_argument("--json", help="write every number to this file")
    ap.add_argument("--plot", help="MFNE picture (PNG); the RMSE picture goes beside it as NAME-rmse.png")
    ap.add_argument("--quick", action="store_true", help="one setting per peer and, unless given, one small row "
                    "(fandisk, iso 0.2, seed 1): the smoke test")
    a = ap.parse_args()
    if a.clean_mesh is None:
        a.clean_mesh = ",".join(CLEAN) if a.mesh is None and not a.quick else (a.mesh or "fandisk")
    row = ("fandisk", [0.2], [], "", [1]) if a.quick else (
        ",".join(MESHES), ISO, NORMAL, ",".join(f"{d}:{s:g}" for d, s in STRUCTURED), SEEDS)
    for name, default in zip(("mesh", "iso", "normal", "structured", "seeds"), row):
        if getattr(a, name) is None:
            setattr(a, name, default if isinstance(default, str) else ",".join(map(str, default)))
    try:
        a.noises = [("iso", s) for s in floats(a.iso)] + [("normal", s) for s in floats(a.normal)]
        a.noises += parse_structured(a.structured)
        a.seed_list = [int(s) for s in a.seeds.split(",") if s.strip()]
    except ValueError as e:
        ap.error(f"--iso, --normal, --structured, --seeds: {e}")
    if any(s <= 0 for _, s in a.noises):
        ap.error("noise levels must be above 0 (the clean table is the noise-free case)")
    unknown = set(a.peers.split(",")) - {p for p, _ in SWEEPS}
    if unknown:
        ap.error(f"--peers: unknown {', '.join(sorted(unknown))} (known: {', '.join(p for p, _ in SWEEPS)})")
    if a.jobs < 1:
        ap.error("--jobs must be at least 1")
    if not os.access(a.fqfilter, os.X_OK):
        ap.error(f"--fqfilter {a.fqfilter}: not an executable")
    return a


def main():
    a = parse_args()
    started = time.time()
    with tempfile.TemporaryDirectory(prefix="fq_matrix_") as work:
        cfg = SimpleNamespace(fqfilter=a.fqfilter, meshes=a.meshes, engine=a.engine, fq_args=shlex.split(a.fq_args),
                              cache=a.peer_cache, work=work,
                              sweeps=[(p, s[:1] if a.quick else s) for p, s in SWEEPS if p in a.peers.split(",")])
        names = [m for m in a.mesh.split(",") if m]
        clean_names = [c for c in a.clean_mesh.split(",") if c]
        meshes = {m: prepare_mesh(m, cfg) for m in dict.fromkeys(names + clean_names)}
        labels = [m.label for m in meshes.values()]
        if len(set(labels)) != len(labels):
            raise SystemExit(f"quality_matrix.py: two meshes with one name among {labels}")
        tasks = [(run_row, (meshes[m], d, s, k))
                 for m in dict.fromkeys(names) for d, s in a.noises for k in a.seed_list]
        tasks += [(run_clean, (meshes[m],)) for m in dict.fromkeys(clean_names)]
        if not peers.PEERS["ml_taubin"].available():
            print("(meshlabserver or xvfb-run not found: MeshLab peers only from the cache)", file=sys.stderr)
        results, failed = run_all(cfg, a.jobs, tasks)
    rows = [r for r in results if "direction" in r]
    clean = [r for r in results if "direction" not in r]
    meta = {"machine": peers.machine(), "open3d": peers.o3d.__version__,
            "meshlab": peers.PEERS["ml_taubin"].available(),
            "fqfilter": subprocess.run([a.fqfilter, "--version"], capture_output=True, text=True).stdout.strip(),
            "engine": a.engine, "fq_args": cfg.fq_args, "qf_args": peers.QF_ARGS, "seeds": a.seed_list,
            "sweeps": {p: [str(s) for s in settings] for p, settings in cfg.sweeps},
            "jobs": a.jobs, "seconds": time.time() - started, "failed": failed}
    doc = report.build(meta, rows, clean)
    print(report.markdown(doc))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(doc, fh, indent=1)
    if a.plot and rows:
        report.plot(doc, a.plot)
    for name, error in failed:
        print(f"quality_matrix.py: {name}: {error}", file=sys.stderr)
    if failed:
        sys.exit(1)
    if a.quick and rows:
        r = rows[0]
        if not r["fq_default"]["mfne"] < r["noisy"]["mfne"] or not doc["rows"][0]["best_peer"]:
            sys.exit("quality_matrix.py: expected fq default under the noisy input and a best peer on the smoke row")


if __name__ == "__main__":
    main()
