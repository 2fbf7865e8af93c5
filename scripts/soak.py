#!/usr/bin/env python3
"""Soak test of fqd: heavy and light streams together, with garbage, for a while, sampled and judged.

Starts fqd (a temporary config on free 127.0.0.1 ports, its HTTP listener on for /metrics) and
one fqpub per stream, of three kinds:
  heavy  large meshes (bunny from ../shared/meshes) with filtering and clustering, at a low rate
         with a large budget;
  light  small noisy meshes (fandisk, max_planck) filtered at a higher rate with a tight budget;
  bad    one stream whose frames ask for more neighbour work than fqd allows: every frame is an
         error result (the alert check's positive control);
beside a junk sender (messages on ever new topics, malformed frames, bad stream ids, about 200
a second, through python3-zmq) and, where Debian's `prometheus` is installed, a Prometheus
server that scrapes fqd's /metrics every second and evaluates deploy/monitoring/fqd-alerts.yml.
Every INTERVAL seconds it samples fqd's RSS, GPU memory in use (nvidia-smi, when there is a GPU)
and the counters (`fqctl counters --json`). At the end it prints a table and checks:
  - RSS flat: its peak over the second half of the samples after warm-up within --rss-slack-mb
    of its peak over the first half (GPU memory: the last sample against the first after warm-up);
  - every stream's counters add up: frames_in == frames_out + errors + superseded +
    dropped_stale + preempted + refused + dropped_memory;
  - the heavy and light streams got results, no error result, and (from 100 results on, where
    it is not just their maximum) a receive->publish p99 within their budget + --p99-slack-ms;
    the bad stream got error results only;
  - preemption by fqd's rule: fqd counts every stop on the stopped stream (`preempted`) and on
    the stream whose waiting frame it was for (`preempted_others`); the two sums agree (every
    stop served another stream's waiting frame), none was for the bad stream, and a stream was
    stopped only if its own frames do not meet its budget (late results, or a median engine
    time or receive->publish over the budget): a stream whose frames meet it is never stopped.
    With --quick (one heavy stream) also: every stop was for a light stream, none stopped one;
  - alerts, asked of Prometheus (/api/v1/rules, and ALERTS over the run through /api/v1/query):
    the rules loaded and fqd was scraped, no per-stream error alert (FqdStreamErrors) was
    pending or firing for a stream the soak fed only good frames, and it was for the bad one.

    /usr/bin/python3 scripts/soak.py --build build --minutes 10 [--heavy 1 --light 2] [--engine cuda]
    /usr/bin/python3 scripts/soak.py --build build --quick      # about 50 s: the ctest fq_soak_quick
Exit status 0 when every check holds, 1 when one fails, 77 with --quick when python3-zmq or a
binary it needs is missing (a skip to ctest).
"""
import argparse, json, os, shutil, signal, socket, subprocess, sys, tempfile, time, urllib.parse, urllib.request

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
MESH_DIR = os.environ.get("FQ_MESH_DIR", os.path.join(ROOT, "..", "shared", "meshes"))
RULES = os.path.join(ROOT, "deploy", "monitoring", "fqd-alerts.yml")
ERROR_ALERTS = ("FqdStreamErrors",)  # the per-stream alerts on error results
SKIP = 77
COMPUTE = ("filter", "cluster", "filter_and_cluster")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def gpu_mb(pid):
    try:
        out = subprocess.run(["nvidia-smi", "--query-compute-apps=pid,used_memory", "--format=csv,noheader,nounits"],
                             capture_output=True, text=True, timeout=10).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    for line in out.splitlines():
        p, mb = [x.strip() for x in line.split(",")]
        if p == str(pid):
            return float(mb)
    return 0.0


def junk_sender(endpoint, stop_at):
    """A child process: floods junk at about 200 messages a second until stop_at."""
    import zmq
    ctx = zmq.Context()
    s = ctx.socket(zmq.PUSH)
    s.setsockopt(zmq.LINGER, 0)
    s.setsockopt(zmq.SNDHWM, 1000)
    s.connect(endpoint)
    i = 0
    while time.time() < stop_at:
        kind = i % 3
        try:
            if kind == 0:
                s.send_multipart([f"junk-{i}".encode()], zmq.NOBLOCK)           # one part: malformed
            elif kind == 1:
                s.send_multipart([b"\xff\xfe" + str(i).encode(), b"x", b"y"], zmq.NOBLOCK)  # bad id
            else:
                s.send_multipart([f"junk-{i}".encode(), b"\x08\x02", b"DRACO"], zmq.NOBLOCK)
        except zmq.Again:
            pass
        i += 1
        time.sleep(0.005)


def mesh_path(name):
    """A mesh by name: a path as given, else data/NAME, else the shared meshes' NAME (None: absent)."""
    for p in (name, os.path.join(ROOT, "data", name), os.path.join(MESH_DIR, name)):
        if os.path.isfile(p):
            return os.path.abspath(p)
    return None


def stream_plan(a):
    """The soak's streams: dicts of id, kind, mesh, fps, budget_ms, compute and fqpub's extra options."""
    def meshes(names):
        found = [m for m in (mesh_path(n) for n in names.split(",")) if m]
        return found or [mesh_path("fandisk.ply")]
    heavy, light = meshes(a.heavy_mesh), meshes(a.light_mesh)
    plan = [dict(id=f"heavy{i}", kind="heavy", mesh=heavy[i % len(heavy)], fps=a.heavy_fps,
                 budget_ms=a.heavy_budget_ms, compute=a.heavy_compute, extra=[]) for i in range(a.heavy)]
    plan += [dict(id=f"light{i}", kind="light", mesh=light[i % len(light)], fps=a.light_fps,
                  budget_ms=a.light_budget_ms, compute=a.light_compute, extra=[]) for i in range(a.light)]
    if not a.no_bad:  # 1e4 mean edges: far over caps.max_neighbour_work, refused before the engine
        plan.append(dict(id="bad0", kind="bad", mesh=mesh_path("fandisk.ply"), fps=1.0, budget_ms=1000.0,
                         compute="filter", extra=["--mode", "qf", "--sigma-s", "10000"]))
    return plan


def write_config(path, ep, http_port, engine, plan):
    with open(path, "w") as f:
        f.write(f'[endpoints]\ningest = "{ep["ingest"]}"\npublish = "{ep["publish"]}"\ncontrol = "{ep["control"]}"\n'
                f'[http]\nlisten = "127.0.0.1:{http_port}"\n[engine]\nkind = "{engine}"\n'
                f'[caps]\nstream_idle_s = 20.0\n[defaults]\nbudget_ms = 1000.0\ncompute = "filter_and_cluster"\n')
        for s in plan:
            f.write(f'[streams.{s["id"]}]\nbudget_ms = {s["budget_ms"]}\ncompute = "{s["compute"]}"\n')


class Prometheus:
    """Debian's prometheus on a free 127.0.0.1 port: scrapes fqd every second, evaluates the rules."""

    def __init__(self, binary, tmp, fqd_http_port):
        self.port = free_port()
        cfg = os.path.join(tmp, "prometheus.yml")
        with open(cfg, "w") as f:
            f.write("global:\n  scrape_interval: 1s\n  scrape_timeout: 1s\n  evaluation_interval: 1s\n"
                    f"rule_files:\n  - {RULES}\n"
                    f"scrape_configs:\n  - job_name: fqd\n    static_configs:\n"
                    f"      - targets: ['127.0.0.1:{fqd_http_port}']\n")
        self.log = open(os.path.join(tmp, "prometheus.log"), "w")
        self.proc = subprocess.Popen([binary, f"--config.file={cfg}", f"--storage.tsdb.path={os.path.join(tmp, 'tsdb')}",
                                      f"--web.listen-address=127.0.0.1:{self.port}", "--log.level=warn"],
                                     stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 30
        while time.time() < deadline:
            try:
                if urllib.request.urlopen(f"http://127.0.0.1:{self.port}/-/ready", timeout=2).status == 200:
                    return
            except OSError:
                time.sleep(0.3)
        raise RuntimeError(f"prometheus did not get ready within 30 s (log: {self.log.name})")

    def api(self, path, **params):
        url = f"http://127.0.0.1:{self.port}/api/v1/{path}"
        if params:
            url += "?" + urllib.parse.urlencode(params)
        reply = json.load(urllib.request.urlopen(url, timeout=10))
        if reply.get("status") != "success":
            raise RuntimeError(f"prometheus {path}: {reply}")
        return reply["data"]

    def query(self, expr):
        return self.api("query", query=expr)["result"]

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self.log.close()


def fqctl_counters(exe, control):
    out = subprocess.run([exe("fqctl"), "-c", control, "counters", "--json"], capture_output=True, text=True)
    return json.loads(out.stdout) if out.returncode == 0 else {"streams": []}


def settled(s):
    return s["frames_in"] == (s["frames_out"] + s["errors"] + s["superseded"] + s["dropped_stale"]
                              + s.get("preempted", 0) + s.get("refused", 0) + s.get("dropped_memory", 0))


def wait_settled(exe, control, ids, limit_s=20.0):
    """The counters once every soak stream's frames have an outcome (or after limit_s)."""
    deadline = time.time() + limit_s
    while True:
        final = fqctl_counters(exe, control)
        mine = {s["stream"]: s for s in final["streams"] if s["stream"] in ids}
        if (len(mine) == len(ids) and all(settled(s) for s in mine.values())) or time.time() > deadline:
            return mine
        time.sleep(0.5)


class Table:
    def __init__(self):
        self.ok = True
        print("\n| check | value | result |\n|---|---|---|")

    def row(self, check, value, good, yes, no):
        print(f"| {check} | {value} | {yes if good else no} |", flush=True)
        self.ok &= bool(good)


def judge_streams(t, plan, final, slack_ms):
    for p in plan:
        s = final.get(p["id"])
        if s is None:
            t.row(f"{p['id']} ({p['kind']})", "no counters", False, "", "MISSING")
            continue
        t.row(f"{p['id']} ({p['kind']}): in / out / errors / superseded / stale / preempted / late",
              f"{s['frames_in']} / {s['frames_out']} / {s['errors']} / {s['superseded']} / {s['dropped_stale']} / "
              f"{s.get('preempted', 0)} / {s['late']}", settled(s) and s["frames_in"] > 0, "consistent", "INCONSISTENT")
        if p["kind"] == "bad":
            t.row(f"{p['id']} (bad): error results", f"{s['errors']} errors, {s['frames_out']} results",
                  s["errors"] > 0 and s["frames_out"] == 0, "every frame an error", "NOT AS SENT")
            continue
        p99 = s["stages"].get("receive_to_publish", {}).get("p99_ms", float("nan"))
        engine = s["stages"].get("engine", {}).get("p50_ms", float("nan"))
        # Under 100 results the p99 is their maximum, one stall of a loaded host: shown, not judged.
        few = s["frames_out"] < 100
        t.row(f"{p['id']} ({p['kind']}): receive->publish p99 (budget {p['budget_ms']:g} ms)",
              f"{p99:.1f} ms (engine p50 {engine:.0f} ms)",
              s["frames_out"] > 0 and s["errors"] == 0 and (few or p99 <= p["budget_ms"] + slack_ms),
              f"not judged ({s['frames_out']} results)" if few else "bounded", "OVER" if s["errors"] == 0 else "ERRORS")


def over_budget(p, s):
    """What fqd reports that says the stream's frames do not meet its budget ('' when they do):
    results published late, or a median engine time or receive->publish over the budget, or no
    result at all."""
    why = [f"{s['late']} late"] if s["late"] else []
    for stage in ("engine", "receive_to_publish"):
        p50 = s["stages"].get(stage, {}).get("p50_ms", 0.0)
        if p50 > p["budget_ms"]:
            why.append(f"{stage.replace('_to_', '->')} p50 {p50:.0f} ms")
    if s["frames_out"] == 0:
        why.append("no result")
    return ", ".join(why)


def judge_preemption(t, plan, final, quick):
    """fqd's rule: every stop served another stream's waiting frame, none the bad stream's, and a
    stream is stopped only when its own frames do not meet its budget. With --quick (one heavy
    stream beside the light ones) also: every stop was for a light stream, none stopped one."""
    if any("preempted_others" not in s for s in final.values()):
        t.row("preemption accounted", "fqd exports no preempted_others", False, "", "CANNOT JUDGE")
        return
    kind = {p["id"]: p["kind"] for p in plan}
    stops = sum(s["preempted"] for s in final.values())
    given = {k: sum(s["preempted_others"] for i, s in final.items() if kind[i] == k) for k in ("heavy", "light", "bad")}
    t.row("preemption: frames stopped / stopped for light / for heavy / for bad",
          f"{stops} / {given['light']} / {given['heavy']} / {given['bad']}",
          stops == sum(given.values()) and given["bad"] == 0 and (not quick or given["heavy"] == 0),
          "each for another stream's frame", "NOT ACCOUNTED" if stops != sum(given.values()) else "FOR THE WRONG STREAM")
    for p in plan:
        s = final.get(p["id"])
        if s is None or not (s["preempted"] or p["kind"] == "light"):
            continue
        why = over_budget(p, s)
        barred = p["kind"] == "bad" or (quick and p["kind"] == "light")
        t.row(f"{p['id']} ({p['kind']}): preempted / stopped for it / its frames against budget {p['budget_ms']:g} ms",
              f"{s['preempted']} / {s['preempted_others']} / {why or 'within'}",
              s["preempted"] == 0 or (bool(why) and not barred), "never stopped" if s["preempted"] == 0 else
              "stopped over budget", f"{p['kind'].upper()} STREAM STOPPED" if barred else "STOPPED WITHIN BUDGET")


def alerts_seen(prom, seconds):
    """{(alertname, stream or ''): set of states} over the last `seconds`, from the ALERTS series."""
    seen = {}
    for r in prom.query(f"max_over_time(ALERTS[{int(seconds) + 5}s])"):
        m = r["metric"]
        seen.setdefault((m["alertname"], m.get("stream", "")), set()).add(m["alertstate"])
    for a in prom.api("alerts")["alerts"]:  # and those active now
        seen.setdefault((a["labels"]["alertname"], a["labels"].get("stream", "")), set()).add(a["state"])
    return seen


def judge_alerts(t, prom, plan, seconds):
    groups = prom.api("rules")["groups"]
    rules = [r for g in groups for r in g["rules"] if r.get("type") == "alerting"]
    unhealthy = [r["name"] for r in rules if r.get("health") != "ok"]
    scrapes = prom.query(f"count_over_time(up{{job=\"fqd\"}}[{int(seconds) + 5}s])")
    ups = prom.query(f"min_over_time(up{{job=\"fqd\"}}[{int(seconds) + 5}s])")
    n = int(float(scrapes[0]["value"][1])) if scrapes else 0
    t.row("prometheus: alert rules loaded / fqd scrapes (all up)", f"{len(rules)} rules / {n} scrapes",
          rules and not unhealthy and n > 0 and ups and float(ups[0]["value"][1]) == 1, "evaluated",
          f"NOT EVALUATED {unhealthy}")
    seen = alerts_seen(prom, seconds)
    healthy = {p["id"] for p in plan if p["kind"] != "bad"}
    wrong = sorted(f"{a}{{stream={s}}} {'/'.join(sorted(st))}" for (a, s), st in seen.items()
                   if a in ERROR_ALERTS and s in healthy)
    t.row("per-stream error alerts for healthy streams (pending or firing)", ", ".join(wrong) or "none", not wrong,
          "none", "FIRED")
    bad = {p["id"] for p in plan if p["kind"] == "bad"}
    for i in sorted(bad):
        st = seen.get((ERROR_ALERTS[0], i), set())
        t.row(f"{ERROR_ALERTS[0]} for {i} (fed only bad frames)", "/".join(sorted(st)) or "not seen", bool(st),
              "seen", "MISSED")
    other = sorted(f"{a}{{stream={s}}} {'/'.join(sorted(st))}" if s else f"{a} {'/'.join(sorted(st))}"
                   for (a, s), st in seen.items() if not (a in ERROR_ALERTS and s in healthy | bad))
    print(f"| other alerts pending or firing (not judged) | {', '.join(other) or 'none'} | - |", flush=True)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--interval", type=float, default=30.0, help="seconds between samples")
    ap.add_argument("--quick", action="store_true",
                    help="40 s of streams, sampled every 10 s (the ctest); exit 77 when python3-zmq or a binary is missing")
    ap.add_argument("--heavy", type=int, default=1, help="heavy streams")
    ap.add_argument("--heavy-mesh", default="bunny.ply", help="comma-separated, one per stream in turn")
    ap.add_argument("--heavy-fps", type=float, default=1.0)
    ap.add_argument("--heavy-budget-ms", type=float, default=2000.0)
    ap.add_argument("--heavy-compute", default="filter_and_cluster", choices=COMPUTE)
    ap.add_argument("--light", type=int, default=2, help="light streams")
    ap.add_argument("--light-mesh", default="fandisk.ply,max_planck.ply", help="comma-separated, one per stream in turn")
    ap.add_argument("--light-fps", type=float, default=5.0)
    ap.add_argument("--light-budget-ms", type=float, default=400.0)
    ap.add_argument("--light-compute", default="filter", choices=COMPUTE)
    ap.add_argument("--no-bad", action="store_true", help="no stream of bad frames (and no positive control of the alerts)")
    ap.add_argument("--engine", default="cpu")
    ap.add_argument("--rss-slack-mb", type=float, default=32.0)
    ap.add_argument("--p99-slack-ms", type=float, default=2000.0, help="a stream's p99 may pass its budget by this much")
    ap.add_argument("--prometheus", default=shutil.which("prometheus") or "",
                    help="the prometheus binary (default: on PATH; none: the alert check is skipped)")
    ap.add_argument("--no-junk", action="store_true",
                    help="no junk sender (for a host without python3-zmq; the streams and samples run as ever)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folder (logs, configs, Prometheus data)")
    a = ap.parse_args()
    if a.quick:
        a.minutes, a.interval = 40 / 60, 10.0
    return a


def check_tools(a, exe):
    """None when everything the run needs is there, else why not."""
    missing = [n for n in ("fqd", "fqpub", "fqctl") if not os.access(exe(n), os.X_OK)]
    if missing:
        return f"no {', '.join(missing)} under {a.build} (build the targets fqd fqpub fqctl)"
    if not a.no_junk:
        try:
            import zmq  # noqa: F401  (the junk sender's; checked here for a clear message)
        except ImportError:
            return "the junk sender needs pyzmq (Debian: python3-zmq); or pass --no-junk"
    return None


def main():
    a = parse_args()
    exe = lambda name: os.path.join(a.build, "daemon" if name == "fqd" else "clients/" + name, name)
    why = check_tools(a, exe)
    if why:
        print(f"soak.py: {why}", file=sys.stderr)
        return SKIP if a.quick else 2
    plan = stream_plan(a)
    ep = {k: f"tcp://127.0.0.1:{free_port()}" for k in ("ingest", "publish", "control")}
    http_port = free_port()
    tmp = tempfile.mkdtemp(prefix="soak-")
    write_config(os.path.join(tmp, "fqd.toml"), ep, http_port, a.engine, plan)
    for p in plan:
        print(f"{p['id']}: {p['kind']}, {os.path.basename(p['mesh'])} at {p['fps']:g} fps, budget {p['budget_ms']:g} ms, "
              f"{p['compute']}", flush=True)
    ok = run(a, exe, plan, ep, http_port, tmp)
    print(f"\nsoak: {'PASS' if ok else 'FAIL'} ({a.minutes * 60:g} s, {a.heavy} heavy + {a.light} light streams"
          f"{'' if a.no_bad else ' + 1 bad'}, engine {a.engine}, {'no junk' if a.no_junk else 'junk traffic'}; "
          f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f})")
    if ok and not a.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    else:
        print(f"soak: logs and configs in {tmp}")
    return 0 if ok else 1


def run(a, exe, plan, ep, http_port, tmp):
    seconds = a.minutes * 60
    fqd = subprocess.Popen([exe("fqd"), "--config", os.path.join(tmp, "fqd.toml")], stdout=subprocess.DEVNULL,
                           stderr=open(os.path.join(tmp, "fqd.log"), "w"))
    prom = None
    try:
        time.sleep(1)
        if a.prometheus:
            prom = Prometheus(a.prometheus, tmp, http_port)
        else:
            print("soak: no prometheus binary (Debian: prometheus): the alert check is skipped", flush=True)
        t = soak(a, exe, plan, ep, fqd, seconds, tmp)
        if prom:
            time.sleep(3)  # a last scrape and evaluation of the settled counters
            judge_alerts(t, prom, plan, seconds + 30)
        return t.ok
    finally:
        if prom:
            prom.stop()
        fqd.send_signal(signal.SIGTERM)
        fqd.wait(timeout=30)


def soak(a, exe, plan, ep, fqd, seconds, tmp):
    stop_at = time.time() + seconds
    pubs = [subprocess.Popen([exe("fqpub"), p["mesh"], "-e", ep["ingest"], "-s", p["id"], "--fps", str(p["fps"]),
                              "--noise", "0.2", "--seed", str(1000 * i), "-d", str(seconds)] + p["extra"],
                             stdout=subprocess.DEVNULL, stderr=open(os.path.join(tmp, f"fqpub-{p['id']}.log"), "w"))
            for i, p in enumerate(plan)]
    import multiprocessing
    junk = None if a.no_junk else multiprocessing.Process(target=junk_sender, args=(ep["ingest"], stop_at))
    if junk:
        junk.start()
    samples, t0 = [], time.time()
    while time.time() < stop_at:
        time.sleep(min(a.interval, max(0.0, stop_at - time.time())))
        counters = fqctl_counters(exe, ep["control"])
        samples.append((time.time() - t0, rss_mb(fqd.pid), gpu_mb(fqd.pid), counters))
        print(f"t={samples[-1][0]:6.0f}s rss={samples[-1][1]:7.1f} MB gpu={samples[-1][2]} MB "
              f"streams={len(counters['streams'])} load={os.getloadavg()[0]:.2f}", flush=True)
    for p in pubs:
        p.wait(timeout=60)
    if junk:
        junk.join(timeout=10)
    final = wait_settled(exe, ep["control"], {p["id"] for p in plan})
    with open(os.path.join(tmp, "counters.json"), "w") as f:
        json.dump(final, f, indent=1)
    final_rss = rss_mb(fqd.pid)
    t = Table()
    # Peaks, not single samples: with frames of very different sizes the pools hand pages back
    # (malloc_trim after a small frame follows a huge one), so one sample may be taken in a
    # trough 50 MB under the others (bunny and igea beside the light streams: 161, 113, 161 MB).
    after = [s[1] for s in samples[1:]] + [final_rss]
    half = max(1, len(after) // 2)
    early, late = max(after[:half]), max(after[half:] or after)
    t.row("RSS peak after warm-up, first half -> second half", f"{early:.1f} -> {late:.1f} MB "
          f"(samples {min(after):.1f} to {max(after):.1f}, end {final_rss:.1f})", late - early <= a.rss_slack_mb,
          "flat", "GREW")
    if samples[0][2] is not None:
        g = [s[2] for s in samples if s[2] is not None]
        t.row("GPU memory after warm-up -> end", f"{g[min(1, len(g) - 1)]} -> {g[-1]} MB",
              g[-1] - g[min(1, len(g) - 1)] <= a.rss_slack_mb, "flat", "GREW")
    judge_streams(t, plan, final, a.p99_slack_ms)
    judge_preemption(t, plan, final, a.quick)
    return t


if __name__ == "__main__":
    sys.exit(main())
