"""What scripts/peer_quality.py and scripts/quality_matrix.py share: meshes and errors measured
the way fqfilter measures them, fqfilter itself, the other smoothers, and their results cache.

Errors: MFNE (mean angle between clean and filtered face normals, faces degenerate in either mesh
skipped by eval/error_metrics.cpp's rule) and vertex RMSE over the clean mesh's bounding-box
diagonal, both as eval/error_metrics.cpp computes them.

Peers (the smoothers users already have), each named by an id that the cache keys use:
o3d_laplacian, o3d_taubin, o3d_simple (Open3D's filter_smooth_*) and ml_taubin, ml_hc,
ml_twostep (MeshLab's meshlabserver with a .mlx filter script, under xvfb-run). Every one of them
is iterative: n + m steps give exactly what n steps followed by m more give (checked on the
outputs by tests/scripts/test_quality_matrix.py), so a sweep of settings runs as one chain, each
setting's result taken on the way (MeshLab: a layer duplicated after each, saved with `-o -l`).

The cache: one JSON file per noisy file under the cache folder, named by the SHA-256 of the
noisy file's bytes, holding {"<peer>:<setting>": [mfne, rmse] or null}; <setting> is the sweep
value as Python's str() prints it ("ml_twostep:(3, 60)"); null: the peer changed the mesh's
vertex or face order, so it cannot be compared. Peers do not depend on fq, and fqfilter writes
the same noisy file for the same mesh, noise and seed, so a re-run after a change to fq runs
only fq.
"""
import hashlib
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    import open3d as o3d
except ImportError as e:  # Debian's python3-open3d lives in /usr/bin/python3's path
    print(f"{os.path.basename(sys.argv[0])}: {e}; install python3-open3d (scripts/setup-deps.sh --peers) "
          "and run with /usr/bin/python3", file=sys.stderr)
    sys.exit(77)  # "skipped" for ctest's smoke tests

# The paper's filtered quadrics at its Table 1 σ (fqfilter's defaults before qf+).
QF_ARGS = ["--mode", "qf", "--sigma-s", "2", "--sigma-r", "1"]
# eval/error_metrics.cpp's kDegenerateRatio: below |cross| / (longest edge)² a face has no normal.
DEGENERATE_RATIO = 1e-9


def machine():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    return f"{platform.machine()} {cpu}, {os.cpu_count()} hardware threads"


def fqfilter_json(fqfilter, args):
    """fqfilter's --json report of one run; its stderr in the error when it fails."""
    out = subprocess.run([fqfilter, *args, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join([fqfilter, *args])} failed ({out.returncode}): {out.stderr.strip()}")
    return json.loads(out.stdout)


def load(path):
    m = o3d.io.read_triangle_mesh(path)
    return np.asarray(m.vertices, dtype=np.float64), np.asarray(m.triangles, dtype=np.int64)


def face_normals(v, f):
    """Unit face normals and which faces have one (eval/error_metrics.cpp's face_normal)."""
    e0, e1, e2 = v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 1]]
    n = np.cross(e0, e1)
    length = np.linalg.norm(n, axis=1)
    longest2 = np.max([np.sum(e * e, axis=1) for e in (e0, e1, e2)], axis=0)
    ok = (longest2 > 0) & np.isfinite(length) & (length > DEGENERATE_RATIO * longest2)
    n[ok] /= length[ok][:, None]
    return n, ok


def mfne(clean, faces, v):
    n0, ok0 = face_normals(clean, faces)
    n1, ok1 = face_normals(v, faces)
    ok = ok0 & ok1
    c = np.linalg.norm(np.cross(n0[ok], n1[ok]), axis=1)
    return float(np.mean(np.arctan2(c, np.sum(n0[ok] * n1[ok], axis=1))))


def rmse_over_diagonal(clean, v):
    diagonal = np.linalg.norm(clean.max(axis=0) - clean.min(axis=0))
    return float(np.sqrt(np.mean(np.sum((v - clean) ** 2, axis=1))) / diagonal)


def errors(clean, faces, v, f):
    """[MFNE, vertex RMSE/diagonal] of (v, f) against the clean mesh; None when the order differs."""
    if v.shape != clean.shape or not np.array_equal(f, faces):
        return None
    return [mfne(clean, faces, v), rmse_over_diagonal(clean, v)]


def check_noisy(clean, faces, noisy_path, report):
    """The noisy file as read here measures what fqfilter measured on it (its --json report)."""
    if not os.path.isfile(noisy_path):
        raise RuntimeError(f"fqfilter wrote no noisy file {noisy_path}")
    nv, nf = load(noisy_path)
    ours = errors(clean, faces, nv, nf)
    if ours is None:
        raise RuntimeError(f"{noisy_path}: vertex or face order differs from the clean mesh")
    theirs = report["metrics"]["input"]
    if abs(ours[0] - theirs["mfne_rad"]) > 1e-4 or abs(ours[1] - theirs["rmse_over_diagonal"]) > 1e-4 * ours[1] + 1e-12:
        raise RuntimeError(f"{noisy_path}: MFNE/RMSE here {ours} against fqfilter's "
                           f"{theirs['mfne_rad']}/{theirs['rmse_over_diagonal']}")
    return ours


# --- peers: each runs a chain of cumulative step counts, returning (v, f) after each ---

def _o3d_chain(kind):
    def run(noisy_path, _group, counts, _tmp):
        m, done, outs = o3d.io.read_triangle_mesh(noisy_path), 0, []
        for n in counts:
            if kind == "laplacian":
                m = m.filter_smooth_laplacian(number_of_iterations=n - done, lambda_filter=0.5)
            else:
                m = getattr(m, f"filter_smooth_{kind}")(number_of_iterations=n - done)
            done = n
            outs.append((np.asarray(m.vertices, dtype=np.float64).copy(),
                         np.asarray(m.triangles, dtype=np.int64).copy()))
        return outs
    return run


def _mlx_filter(name, params):
    return f' <filter name="{name}">\n' + "".join(
        f'  <Param type="{t}" value="{v}" name="{n}"/>\n' for t, n, v in params) + " </filter>\n"


def _ml_taubin(_group, n):
    return _mlx_filter("Taubin Smooth", [("RichFloat", "lambda", 0.5), ("RichFloat", "mu", -0.53),
                                         ("RichInt", "stepSmoothNum", n), ("RichBool", "Selected", "false")])


def _ml_hc(_group, n):
    return ' <filter name="HC Laplacian Smooth"/>\n' * n


def _ml_twostep(angle, n):
    return _mlx_filter("TwoStep Smooth", [("RichInt", "stepSmoothNum", n), ("RichFloat", "normalThr", angle),
                                          ("RichInt", "stepNormalNum", 20), ("RichInt", "stepFitNum", 20),
                                          ("RichBool", "Selected", "false")])


def _meshlab(noisy_path, body, outs, tmp):
    """One meshlabserver run of a filter script; outs[i] is written from layer i."""
    script = os.path.join(tmp, "peer.mlx")
    with open(script, "w") as fh:
        fh.write(f"<!DOCTYPE FilterScript>\n<FilterScript>\n{body}</FilterScript>\n")
    args = ["-i", noisy_path, "-s", script]
    for i, out in enumerate(outs):
        args += ["-o", out, "-l", str(i)]
    # Parallel workers each start their own X server: distinct first display numbers keep
    # xvfb-run -a from racing for the same one; one retry covers a race that happens anyway.
    cmd = ["xvfb-run", "-a", "-n", str(100 + os.getpid() % 4000), "meshlabserver", *args]
    for _ in range(2):
        for out in outs:
            if os.path.exists(out):
                os.remove(out)
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
        if r.returncode == 0 and all(os.path.exists(o) for o in outs):
            return
    tail = (r.stdout + r.stderr).strip().splitlines()[-1:]
    raise RuntimeError(f"meshlabserver exit {r.returncode} on {os.path.basename(noisy_path)}: {' '.join(tail)}")


def _meshlab_chain(piece, layers=True):
    """The chain in one meshlabserver run, the mesh duplicated into a new layer after each
    setting and every layer saved; or (layers=False: TwoStep asserts on a duplicated layer, which
    lacks its vertex-face adjacency) one run per setting on the previous setting's output."""
    def run(noisy_path, group, counts, tmp):
        outs = [os.path.join(tmp, f"peer_out_{i}.ply") for i in range(len(counts))]
        steps = [n - done for n, done in zip(counts, [0, *counts])]
        if layers:
            dup = ' <filter name="Duplicate Current layer"/>\n'
            _meshlab(noisy_path, dup.join(piece(group, n) for n in steps), outs, tmp)
        else:
            for src, n, out in zip([noisy_path, *outs], steps, outs):
                _meshlab(src, piece(group, n), [out], tmp)
        return [load(o) for o in outs]
    return run


class Peer:
    def __init__(self, label, short, what, run, meshlab=False, group=lambda s: None, steps=lambda s: s,
                 text=str):
        self.label, self.short, self.what, self.run, self.meshlab = label, short, what, run, meshlab
        self.group, self.steps, self.text = group, steps, text

    def available(self):
        return not self.meshlab or bool(shutil.which("meshlabserver") and shutil.which("xvfb-run"))

    def chains(self, settings):
        """Settings that one chain computes: same group, rising step counts."""
        groups = {}
        for s in sorted(set(settings), key=self.steps):
            groups.setdefault(self.group(s), []).append(s)
        return list(groups.items())


PEERS = {
    "o3d_laplacian": Peer("Open3D Laplacian (λ 0.5)", "Open3D Laplacian", "iterations", _o3d_chain("laplacian")),
    "o3d_taubin": Peer("Open3D Taubin", "Open3D Taubin", "iterations", _o3d_chain("taubin")),
    "o3d_simple": Peer("Open3D simple (1-ring mean)", "Open3D simple", "iterations", _o3d_chain("simple")),
    "ml_taubin": Peer("MeshLab Taubin (λ 0.5, μ −0.53)", "MeshLab Taubin", "steps", _meshlab_chain(_ml_taubin),
                      meshlab=True),
    "ml_hc": Peer("MeshLab HC Laplacian", "MeshLab HC", "passes", _meshlab_chain(_ml_hc), meshlab=True),
    "ml_twostep": Peer("MeshLab TwoStep (20 normal, 20 fit)", "MeshLab TwoStep", "steps, angle",
                       _meshlab_chain(_ml_twostep, layers=False), meshlab=True,
                       group=lambda s: s[1], steps=lambda s: s[0], text=lambda s: f"{s[0]}, {s[1]}°"),
}


def key(peer, setting):
    return f"{peer}:{setting}"


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _update_cache(path, fresh):
    """Adds fresh results to the cache file (rewritten whole, renamed into place)."""
    data = {}
    if os.path.exists(path):
        with open(path) as fh:
            data = json.load(fh)
    data.update(fresh)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump(data, fh, indent=0, sort_keys=True)
    os.replace(tmp, path)


def peer_results(noisy_path, clean, faces, sweeps, tmp, cache_dir=None, seconds=None, measure=None):
    """{"<peer>:<setting>": [mfne, rmse] or None} for every setting of sweeps [(peer, settings)]
    on the noisy file, from the cache where it has them, and the peer runs that failed (their
    settings left out, not cached). Settings of a peer that cannot run here (MeshLab missing)
    and are not cached are left out. seconds, when given, receives each peer's run time.
    measure(v, f), when given, replaces errors(clean, faces, v, f) (a scan measured against a
    surface it shares no vertices with: scripts/scan_quality.py; keep its cache apart)."""
    if measure is None:
        def measure(v, f):
            return errors(clean, faces, v, f)
    cache_path, cached = None, {}
    if cache_dir:
        os.makedirs(cache_dir, exist_ok=True)
        cache_path = os.path.join(cache_dir, sha256_file(noisy_path) + ".json")
        if os.path.exists(cache_path):
            with open(cache_path) as fh:
                cached = json.load(fh)
    results = {key(p, s): cached[key(p, s)] for p, settings in sweeps for s in settings if key(p, s) in cached}
    fresh, failures = {}, []
    for p, settings in sweeps:
        peer = PEERS[p]
        missing = [s for s in settings if key(p, s) not in cached]
        if not missing or not peer.available():
            continue
        started = time.monotonic()
        for group, chain in peer.chains(missing):
            try:
                outs = peer.run(noisy_path, group, [peer.steps(s) for s in chain], tmp)
            except (RuntimeError, OSError, subprocess.SubprocessError) as e:  # the other peers still run
                failures.append(f"{p} {', '.join(map(str, chain))}: {e}")
                continue
            for s, (v, f) in zip(chain, outs):
                fresh[key(p, s)] = measure(v, f)
        if seconds is not None:
            seconds[p] = time.monotonic() - started
    if cache_path and fresh:
        _update_cache(cache_path, fresh)
    results.update(fresh)
    return results, failures
