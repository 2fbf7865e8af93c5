#!/usr/bin/env python3
"""Real noise: raw range scans filtered by fq and by the other smoothers, measured against the
merged reconstruction of all the scans (the only reference real scanner noise has).

    /usr/bin/python3 scripts/scan_quality.py [--scans ../shared/meshes/scans/bunny]
        [--reference ../shared/meshes/bunny.ply] [--only bun000,top3] [--fq strength=2,...]
        [--peers o3d_laplacian,...] [--peer-cache DIR] [--json FILE] [--quick]

The scans folder holds the scans (PLY) and a .conf file whose `bmesh NAME tx ty tz qx qy qz qw`
lines bring each scan into the reference's frame: p' = R(q)ᵀ p + t (the Stanford repository's
convention). The reference defaults to the folder's name as a mesh two folders up
(scans/bunny -> bunny.ply), as ../shared/meshes lays them out.

Each scan is measured by fq.scan_error (eval/scan_error.h): normal error = mean angle between a
scan face's normal and the normal of the reference triangle nearest its centroid (radians);
distance = RMS centroid distance to the reference in the raw scan's mean edges; only faces over
the reference count, chosen once on the raw scan. The normal error at the reference's scale
compares each reference triangle with the area-weighted normal of the scan faces nearest it (the
bunny's reconstruction is 1.8 times coarser than its scans: detail finer than its triangles is
not in it). Table cells: normal error / at the reference's scale / distance. Rows: the raw scan, fq's default (fq.filter
with the keywords of --fq: fqfilter's defaults when empty), the paper's QF, and every peer of
scripts/peers.py over the quality matrix's sweeps, both the per-scan best setting (lowest normal
error) and the best fixed setting (one setting of one peer for every scan: lowest mean normal
error). fq runs through the Python module in build/python (bit-identical to fqfilter).

Output: markdown on stdout, --json FILE with every number, --render FILE.png a close-up of the
first scan (raw, fq default, the best fixed peer setting, the reference; scripts/scan_render.py).
--quick: two scans, one setting per
peer (the ctest smoke test). Exit 77 without Open3D or without the scans.
"""
import argparse
import json
import math
import os
import sys
import tempfile
import time

import peers  # exits 77 without Open3D
from peers import np
from quality_matrix import SWEEPS

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
QF = {"mode": "qf", "sigma_s": 2.0, "sigma_r": 1.0}  # peers.QF_ARGS as keywords


def import_fq(build):
    sys.path.insert(0, os.path.join(build, "python"))
    try:
        import fq
    except ImportError as e:
        sys.exit(f"scan_quality.py: cannot import fq from {build}/python ({e}); build it first (scripts/build.sh)")
    return fq


def quaternion_matrix(qx, qy, qz, qw):
    x, y, z, w = qx, qy, qz, qw
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_conf(folder):
    """{scan name: (path, R, t)} from the folder's .conf file, in the file's order."""
    confs = sorted(f for f in os.listdir(folder) if f.endswith(".conf"))
    if not confs:
        raise SystemExit(f"scan_quality.py: no .conf file in {folder}")
    scans = {}
    with open(os.path.join(folder, confs[0])) as fh:
        for number, line in enumerate(fh, 1):
            parts = line.split()
            if not parts or parts[0] != "bmesh":
                continue
            if len(parts) != 9:
                raise SystemExit(f"scan_quality.py: {confs[0]}:{number}: expected 'bmesh NAME tx ty tz qx qy qz qw'")
            t = np.array([float(x) for x in parts[2:5]])
            scans[os.path.splitext(parts[1])[0]] = (os.path.join(folder, parts[1]),
                                                     quaternion_matrix(*map(float, parts[5:9])), t)
    return scans


def load_scan(path, rotation, translation):
    """The scan's vertices in the reference's frame (p' = Rᵀp + t; row vectors: p R + t) and faces."""
    v, f = peers.load(path)
    return v @ rotation + translation, f


def fq_keywords(text):
    out = {}
    for item in filter(None, (text or "").split(",")):
        name, _, value = item.partition("=")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            out[name.strip()] = value.strip()
    return out


def peer_positions(key, path, tmp):
    """The positions one peer setting gives on the scan file (run again, not cached)."""
    p, _, text = key.partition(":")
    peer = peers.PEERS[p]
    setting = next(s for q, settings in SWEEPS if q == p for s in settings if str(s) == text)
    return peer.run(path, peer.group(setting), [peer.steps(setting)], tmp)[0][0]


def render_first(fq, doc, scans, reference, path, tmp):
    import scan_render
    r = doc["rows"][0]
    v, f = load_scan(*scans[r["scan"]])
    ply = os.path.join(tmp, "render.ply")
    fq.write_mesh(ply, v, f)
    panels = [(f"{r['scan']} raw", v, f), ("fq default", np.asarray(fq.filter(v, f, **doc["meta"]["fq"]), float), f)]
    fixed = doc["summary"]["best_fixed"]
    if fixed:
        panels.append((setting_name(fixed), peer_positions(fixed, ply, tmp), f))
    panels.append(("reference", *reference))
    scan_render.render(path, panels)


def run_scan(fq, name, scan, reference, cfg, tmp):
    v, f = load_scan(*scan)
    rv, rf = reference

    def measure(positions, faces=f):
        if positions.shape != v.shape or not np.array_equal(faces, f):
            return None
        e = fq.scan_error(rv, rf, v, f, positions)
        return [e["normal_error_rad"], e["distance_mean_edges"], e["normal_error_coarse_rad"]]

    raw = fq.scan_error(rv, rf, v, f)
    row = {"scan": name, "vertices": len(v), "faces": len(f), "faces_used": raw["faces_used"],
           "raw": [raw["normal_error_rad"], raw["distance_mean_edges"], raw["normal_error_coarse_rad"]]}
    started = time.monotonic()
    filtered, info = fq.filter(v, f, return_info=True, **cfg.fq)
    row["fq_seconds"] = time.monotonic() - started
    row["fq_default"] = measure(np.asarray(filtered, dtype=np.float64))
    row["fq_info"] = info
    row["qf"] = measure(np.asarray(fq.filter(v, f, **QF), dtype=np.float64))
    path = os.path.join(tmp, f"{name}.ply")
    fq.write_mesh(path, v, f)
    found, failures = peers.peer_results(path, None, None, cfg.sweeps, tmp, cfg.cache,
                                         measure=measure)
    row["peers"] = found
    return row, failures


def best(results, keys, measure=0):
    keys = [k for k in keys if results.get(k)]
    return min(keys, key=lambda k: results[k][measure]) if keys else None


def summarize(rows, sweeps):
    """Per-scan best peer setting and the best fixed setting over all scans."""
    keys = [peers.key(p, s) for p, settings in sweeps for s in settings]
    for r in rows:
        r["best_peer"] = best(r["peers"], keys)
        r["best_peer_coarse"] = best(r["peers"], keys, 2)
    usable = [k for k in keys if all(r["peers"].get(k) for r in rows)]
    fixed = min(usable, key=lambda k: sum(r["peers"][k][0] for r in rows)) if usable else None
    ratios = [r["fq_default"][0] / r["peers"][r["best_peer"]][0] for r in rows if r["best_peer"]]
    coarse = [r["fq_default"][2] / r["peers"][r["best_peer_coarse"]][2] for r in rows if r["best_peer_coarse"]]
    return {"best_fixed": fixed,
            "fq_over_best_coarse_geomean": math.exp(sum(map(math.log, coarse)) / len(coarse)) if coarse else None,
            "fq_wins_coarse": sum(1 for x in coarse if x < 1.0),
            "fq_over_best_geomean": math.exp(sum(map(math.log, ratios)) / len(ratios)) if ratios else None,
            "fq_wins_normal": sum(1 for x in ratios if x < 1.0),
            "fq_under_raw_distance": sum(1 for r in rows if r["fq_default"][1] < r["raw"][1]),
            "scans": len(rows)}


def cell(e):
    return "—" if not e else f"{e[0]:.4f} / {e[2]:.4f} / {e[1]:.3f}"


def setting_name(k):
    p, _, s = k.partition(":")
    return f"{peers.PEERS[p].short} {s}"


def markdown(doc):
    s, rows = doc["summary"], doc["rows"]
    fixed = s["best_fixed"]
    out = [f"Normal error / normal error at the reference's scale (rad) / distance (raw scan's mean edges) "
           f"against {doc['meta']['reference']}; {doc['meta']['machine']}.", "",
           f"| scan | raw | fq default (σ̂) | QF | best fixed: {setting_name(fixed) if fixed else '—'} | per-scan best peer |",
           "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        bp = r["best_peer"]
        out.append(f"| {r['scan']} | {cell(r['raw'])} | {cell(r['fq_default'])} ({r['fq_info']['noise_estimate']:.3f}) "
                   f"| {cell(r['qf'])} | {cell(r['peers'].get(fixed) if fixed else None)} "
                   f"| {cell(r['peers'].get(bp) if bp else None)} {setting_name(bp) if bp else ''} |")
    if s["fq_over_best_geomean"]:
        out += ["", f"fq default / per-scan best peer (normal error): geometric mean {s['fq_over_best_geomean']:.3f}; "
                    f"fq below the best peer on {s['fq_wins_normal']} of {s['scans']} scans; "
                    f"fq's distance below the raw scan's on {s['fq_under_raw_distance']} of {s['scans']}. "
                    f"At the reference's scale (against each scan's best peer by that measure): geometric mean "
                    f"{s['fq_over_best_coarse_geomean']:.3f}, fq below it on {s['fq_wins_coarse']} of {s['scans']}."]
    return "\n".join(out)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    meshes = os.environ.get("FQ_MESH_DIR", os.path.join(ROOT, "..", "shared", "meshes"))
    ap.add_argument("--scans", default=os.path.join(meshes, "scans", "bunny"),
                    help="folder of raw scans and their .conf (default: $FQ_MESH_DIR/scans/bunny)")
    ap.add_argument("--reference", help="the reconstruction (default: scans/NAME -> NAME.ply two folders up)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder holding python/fq")
    ap.add_argument("--only", help="comma-separated scan names (default: every scan of the .conf)")
    ap.add_argument("--fq", default="", help="fq.filter keywords for fq's row, e.g. strength=2 (default: none)")
    ap.add_argument("--peers", default=",".join(p for p, _ in SWEEPS))
    ap.add_argument("--peer-cache", help="folder keeping peer results between runs (scripts/peers.py)")
    ap.add_argument("--json")
    ap.add_argument("--render", help="PNG: a close-up of the first scan, raw and filtered, beside the reference")
    ap.add_argument("--quick", action="store_true", help="two scans, one setting per peer")
    return ap.parse_args()


def main():
    a = parse_args()
    if not os.path.isdir(a.scans):
        print(f"scan_quality.py: no scans folder {a.scans}", file=sys.stderr)
        sys.exit(77)
    folder = os.path.normpath(a.scans)
    reference_path = a.reference or os.path.join(os.path.dirname(os.path.dirname(folder)),
                                                 os.path.basename(folder) + ".ply")
    if not os.path.isfile(reference_path):
        raise SystemExit(f"scan_quality.py: no reference {reference_path} (--reference)")
    fq = import_fq(a.build)
    scans = read_conf(folder)
    names = a.only.split(",") if a.only else list(scans)
    if a.quick and not a.only:
        names = names[:2]
    unknown = [n for n in names if n not in scans]
    if unknown:
        raise SystemExit(f"scan_quality.py: not in the .conf: {', '.join(unknown)}")
    chosen = set(a.peers.split(","))
    cfg = argparse.Namespace(fq=fq_keywords(a.fq), cache=a.peer_cache,
                             sweeps=[(p, s[:1] if a.quick else s) for p, s in SWEEPS if p in chosen])
    reference = peers.load(reference_path)
    rows, failed, started = [], [], time.time()
    with tempfile.TemporaryDirectory(prefix="fq-scans-") as tmp:
        for n in names:
            print(f"scan_quality.py: {n}", file=sys.stderr, flush=True)
            row, failures = run_scan(fq, n, scans[n], reference, cfg, tmp)
            rows.append(row)
            failed += failures
    doc = {"meta": {"machine": peers.machine(), "reference": os.path.basename(reference_path),
                    "scans": folder, "fq": cfg.fq, "qf": QF, "open3d": peers.o3d.__version__,
                    "meshlab": peers.PEERS["ml_taubin"].available(),
                    "sweeps": {p: [str(s) for s in settings] for p, settings in cfg.sweeps},
                    "seconds": time.time() - started, "failed": failed},
           "rows": rows}
    doc["summary"] = summarize(rows, cfg.sweeps)
    print(markdown(doc))
    if a.render and rows:
        with tempfile.TemporaryDirectory(prefix="fq-scans-") as tmp:
            render_first(fq, doc, scans, reference, a.render, tmp)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(doc, fh, indent=1)
    for f in failed:
        print(f"scan_quality.py: {f}", file=sys.stderr)
    if failed:
        sys.exit(1)
    if a.quick and not all(r["fq_default"][0] < r["raw"][0] for r in rows):
        sys.exit("scan_quality.py: expected fq's default under the raw scan's normal error")


if __name__ == "__main__":
    main()
