"""scripts/quality_matrix.py's results as a document: each row's best peer, the summary, the
markdown tables and the pictures."""
import ast
import math
import os

import peers

RMSE_UNIT = 1e-3  # the tables give vertex RMSE in thousandths of the clean bounding-box diagonal


def row_name(r):
    return f"{r['mesh']} {r['direction']} {r['noise']:g} seed {r['seed']}"


def peer_text(k):
    """'ml_twostep:(3, 60)' as 'MeshLab TwoStep (steps, angle 3, 60°)'."""
    p, setting = k.split(":", 1)
    peer = peers.PEERS[p]
    return f"{peer.short} ({peer.what} {peer.text(ast.literal_eval(setting))})"


def judge_row(r):
    """Adds the row's best peer (lowest MFNE), lowest peer RMSE and fq/peer MFNE ratio."""
    scored = [(k, v) for k, v in r["peers"].items() if v]
    r["best_peer"] = r["lowest_peer_rmse"] = r["ratio"] = None
    if scored:
        k, (m, e) = min(scored, key=lambda kv: kv[1][0])
        r["best_peer"] = {"peer": k, "mfne": m, "rmse": e}
        k, (m, e) = min(scored, key=lambda kv: kv[1][1])
        r["lowest_peer_rmse"] = {"peer": k, "mfne": m, "rmse": e}
        best = r["best_peer"]["mfne"]
        r["ratio"] = r["fq_default"]["mfne"] / best if best > 0 else None


def not_monotone(rows):
    """Rows whose fq MFNE is above the next noisier row's (same mesh, seed and direction)."""
    groups = {}
    for r in rows:
        groups.setdefault((r["mesh"], r["seed"], r["direction"]), []).append(r)
    bad = []
    for group in groups.values():
        group.sort(key=lambda r: r["noise"])
        bad += [row_name(a) for a, b in zip(group, group[1:]) if a["fq_default"]["mfne"] > b["fq_default"]["mfne"]]
    return bad


def summary(rows):
    judged = [r for r in rows if r["ratio"] is not None]
    worst = max(judged, key=lambda r: r["ratio"], default=None)
    log_mean = sum(math.log(r["ratio"]) for r in judged) / len(judged) if judged else None
    return {
        "rows": len(rows), "rows_judged": len(judged),
        "rows_won": sum(r["ratio"] < 1 for r in judged),
        "geomean_fq_over_peer_mfne": math.exp(log_mean) if judged else None,
        "worst_row": {"row": row_name(worst), "ratio": worst["ratio"]} if worst else None,
        "rmse_above_noisy": [row_name(r) for r in rows if r["fq_default"]["rmse"] > r["noisy"]["rmse"]],
        "rmse_above_1.1_best_peer": [row_name(r) for r in judged
                                     if r["fq_default"]["rmse"] > 1.1 * r["best_peer"]["rmse"]],
        "mfne_not_monotone": not_monotone(rows),
        "peer_failures": [f"{row_name(r)}: {f}" for r in rows for f in r["peer_failures"]],
    }


WHITE = ("iso", "normal")  # the other directions are structured noise (scripts/quality_matrix.py)


def build(meta, rows, clean):
    for r in rows:
        judge_row(r)
    white = [r for r in rows if r["direction"] in WHITE]
    structured = [r for r in rows if r["direction"] not in WHITE]
    doc = {"meta": meta, "summary": summary(white), "rows": rows, "clean": clean}
    if structured:
        doc["summary_structured"] = summary(structured)
    return doc


def _summary_md(s):
    if not s["rows_judged"]:
        return "No row has a peer result.\n"
    lines = [f"**fq default wins {s['rows_won']} of {s['rows_judged']} rows** (MFNE under the best peer setting); "
             f"geometric mean of fq/peer MFNE **{s['geomean_fq_over_peer_mfne']:.3f}**; worst row "
             f"{s['worst_row']['row']} ({s['worst_row']['ratio']:.2f}); fq's RMSE above the noisy input's on "
             f"{len(s['rmse_above_noisy'])} rows, above 1.1 × the best peer's on "
             f"{len(s['rmse_above_1.1_best_peer'])}; "
             f"MFNE not monotone in the noise on {len(s['mfne_not_monotone'])} rows.", ""]
    for title, k in (("RMSE above the noisy input's", "rmse_above_noisy"),
                     ("RMSE above 1.1 × the best peer's", "rmse_above_1.1_best_peer"),
                     ("MFNE above the next noisier row's", "mfne_not_monotone"),
                     ("Peer runs that failed (their settings left out)", "peer_failures")):
        if s[k]:
            lines.append(f"- {title}: {', '.join(s[k])}")
    return "\n".join(lines) + "\n"


def _matrix_md(rows):
    u = lambda x: f"{x / RMSE_UNIT:.3f}"  # noqa: E731
    lines = ["| mesh | noise | seed | noisy MFNE | noisy RMSE | fq MFNE | fq RMSE | QF MFNE | best peer (lowest MFNE) "
             "| peer MFNE | peer RMSE | lowest peer RMSE | fq/peer MFNE |",
             "|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|"]
    for r in rows:
        fq, n, b, lo = r["fq_default"], r["noisy"], r["best_peer"], r["lowest_peer_rmse"]
        fq_rmse = f"**{u(fq['rmse'])}**" if fq["rmse"] > n["rmse"] else u(fq["rmse"])
        ratio = "–" if r["ratio"] is None else f"**{r['ratio']:.2f}**" if r["ratio"] >= 1 else f"{r['ratio']:.2f}"
        peer = [peer_text(b["peer"]), f"{b['mfne']:.3f}", u(b["rmse"]), u(lo["rmse"]), ratio] if b else ["–"] * 5
        cells = [r["mesh"], f"{r['direction']} {r['noise']:g}", str(r["seed"]), f"{n['mfne']:.3f}", u(n["rmse"]),
                 f"{fq['mfne']:.3f}", fq_rmse, f"{r['fq_qf']['mfne']:.3f}", *peer]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _clean_md(clean):
    lines = ["| mesh | vertices | fq default MFNE (rad) | vertices moved | fq default RMSE | QF MFNE (rad) |",
             "|---|---:|---:|---:|---:|---:|"]
    for c in clean:
        fq = c["fq_default"]
        moved = "?" if fq["moved"] is None else f"{fq['moved']:,}"
        lines.append(f"| {c['mesh']} | {c['vertices']:,} | {fq['mfne']:.3f} | {moved} | {fq['rmse'] / RMSE_UNIT:.3f} "
                     f"| {c['fq_qf']['mfne']:.3f} |")
    return "\n".join(lines) + "\n"


def markdown(doc):
    m = doc["meta"]
    fq = "fqfilter's defaults" + (f" with `{' '.join(m['fq_args'])}`" if m["fq_args"] else "")
    out = [f"Machine: {m['machine']}; {m['fqfilter']}, {m['engine']} engine; Open3D {m['open3d']}; "
           f"{'meshlabserver under xvfb-run' if m['meshlab'] else 'MeshLab not found (its peers only where cached)'}; "
           f"peers {', '.join(m['sweeps'])}; "
           f"seeds {', '.join(map(str, m['seeds']))}; fq default = {fq}; QF = `{' '.join(m['qf_args'])}`; "
           f"{m['jobs']} jobs, {m['seconds']:.0f} s.", ""]
    if doc["rows"]:
        out += ["#### Summary (white noise: iso and normal rows)", "", _summary_md(doc["summary"])]
        if "summary_structured" in doc:
            out += ["#### Summary (structured noise: depth, correlated and ripple rows)", "",
                    _summary_md(doc["summary_structured"])]
        out += [
                "#### fq default against the best peer setting of each row", "",
                "MFNE in radians; RMSE: vertex RMSE in thousandths of the clean bounding-box diagonal. "
                "Bold: fq loses the row (fq/peer ≥ 1), or its RMSE is above the noisy input's.", "",
                _matrix_md(doc["rows"])]
    if m["failed"]:
        out += ["**Rows that failed** (not in the tables): " + "; ".join(f"{n}: {e}" for n, e in m["failed"]), ""]
    if doc["clean"]:
        out += ["#### Clean meshes filtered, against themselves", "", _clean_md(doc["clean"])]
    return "\n".join(out)


def plot(doc, path):
    """MFNE (path) and vertex RMSE (path's stem + '-rmse.png') against isotropic noise, one panel
    per mesh, seeds averaged: fq default, the best peer setting of each row, the noisy input."""
    import matplotlib
    matplotlib.use("Agg")
    import quality_matrix_plot
    stem, ext = os.path.splitext(path)
    quality_matrix_plot.draw(doc, "mfne", path)
    quality_matrix_plot.draw(doc, "rmse", f"{stem}-rmse{ext or '.png'}")
