#!/usr/bin/env python3
"""Soak test of fqd: good streams plus junk traffic for a while, sampled.

Starts fqd (a temporary config on free 127.0.0.1 ports), fqpub streams at a fixed rate, and a
junk sender (messages on ever new topics, malformed frames, bad stream ids) through
python3-zmq, then samples every INTERVAL seconds: fqd's RSS, GPU memory in use (nvidia-smi,
when there is a GPU), and the counters through `fqctl counters --json`. At the end it prints
a table and checks that RSS and GPU memory stayed flat (last sample within --rss-slack-mb of
the first one after warm-up), the latencies stayed bounded, and the counters are consistent:
frames_in == frames_out + errors + superseded + dropped_stale + preempted + refused for every
stream.

    /usr/bin/python3 scripts/soak.py --build build --minutes 10 [--engine cuda]
Exit status 0 when every check holds.
"""
import argparse, json, os, signal, socket, subprocess, sys, tempfile, time


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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--mesh", default=os.path.join(os.path.dirname(__file__), "..", "data", "fandisk.ply"))
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--interval", type=float, default=30.0)
    ap.add_argument("--streams", type=int, default=2)
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--engine", default="cpu")
    ap.add_argument("--rss-slack-mb", type=float, default=32.0)
    ap.add_argument("--p99-limit-ms", type=float, default=2000.0)
    ap.add_argument("--no-junk", action="store_true",
                    help="no junk sender (for a host without python3-zmq; the streams and samples run as ever)")
    a = ap.parse_args()
    if not a.no_junk:
        try:
            import zmq  # noqa: F401  (the junk sender's; checked here for a clear message)
        except ImportError:
            sys.exit("soak.py: the junk sender needs pyzmq (Debian: python3-zmq); or pass --no-junk")
    exe = lambda name: os.path.join(a.build, "daemon" if name == "fqd" else "clients/" + name, name)
    ports = {k: free_port() for k in ("ingest", "publish", "control")}
    ep = {k: f"tcp://127.0.0.1:{p}" for k, p in ports.items()}
    tmp = tempfile.mkdtemp(prefix="fq_soak_")
    cfg = os.path.join(tmp, "fqd.toml")
    with open(cfg, "w") as f:
        f.write(f'[endpoints]\ningest = "{ep["ingest"]}"\npublish = "{ep["publish"]}"\ncontrol = "{ep["control"]}"\n'
                f'[http]\nlisten = ""\n[engine]\nkind = "{a.engine}"\n[caps]\nstream_idle_s = 20.0\n'
                f'[defaults]\nbudget_ms = 1000.0\ncompute = "filter_and_cluster"\n')
    seconds = a.minutes * 60
    stop_at = time.time() + seconds
    fqd = subprocess.Popen([exe("fqd"), "--config", cfg], stdout=subprocess.DEVNULL, stderr=open(os.path.join(tmp, "fqd.log"), "w"))
    time.sleep(2)
    pubs = [subprocess.Popen([exe("fqpub"), a.mesh, "-e", ep["ingest"], "-s", f"soak{i}", "--fps", str(a.fps),
                              "--noise", "0.2", "-d", str(seconds)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            for i in range(a.streams)]
    import multiprocessing
    junk = None if a.no_junk else multiprocessing.Process(target=junk_sender, args=(ep["ingest"], stop_at))
    if junk:
        junk.start()
    samples = []
    t0 = time.time()
    while time.time() < stop_at:
        time.sleep(min(a.interval, max(0.0, stop_at - time.time())))
        out = subprocess.run([exe("fqctl"), "-c", ep["control"], "counters", "--json"], capture_output=True, text=True)
        counters = json.loads(out.stdout) if out.returncode == 0 else {"streams": []}
        samples.append((time.time() - t0, rss_mb(fqd.pid), gpu_mb(fqd.pid), counters))
        print(f"t={samples[-1][0]:6.0f}s rss={samples[-1][1]:7.1f} MB gpu={samples[-1][2]} MB "
              f"streams={len(counters['streams'])}", flush=True)
    for p in pubs:
        p.wait(timeout=60)
    if junk:
        junk.join(timeout=10)
    time.sleep(3)  # let the last frames settle
    final = json.loads(subprocess.run([exe("fqctl"), "-c", ep["control"], "counters", "--json"],
                                      capture_output=True, text=True).stdout)
    final_rss = rss_mb(fqd.pid)
    fqd.send_signal(signal.SIGTERM)
    fqd.wait(timeout=30)
    ok = True
    warm = samples[min(1, len(samples) - 1)]
    print(f"\n| check | value | result |\n|---|---|---|")
    grew = final_rss - warm[1]
    print(f"| RSS after warm-up -> end | {warm[1]:.1f} -> {final_rss:.1f} MB (max {max(s[1] for s in samples):.1f}) | "
          f"{'flat' if grew <= a.rss_slack_mb else 'GREW'} |")
    ok &= grew <= a.rss_slack_mb
    if warm[2] is not None:
        g = [s[2] for s in samples if s[2] is not None]
        print(f"| GPU memory after warm-up -> end | {g[min(1, len(g) - 1)]} -> {g[-1]} MB | "
              f"{'flat' if g[-1] - g[min(1, len(g) - 1)] <= a.rss_slack_mb else 'GREW'} |")
    for s in final["streams"]:
        if not s["stream"].startswith("soak"):
            continue
        settled = s["frames_in"] == (s["frames_out"] + s["errors"] + s["superseded"] + s["dropped_stale"]
                                     + s.get("preempted", 0) + s.get("refused", 0))
        p99 = s["stages"].get("receive_to_publish", {}).get("p99_ms", float("nan"))
        print(f"| {s['stream']}: in / out / errors / superseded / stale / late | {s['frames_in']} / {s['frames_out']} / "
              f"{s['errors']} / {s['superseded']} / {s['dropped_stale']} / {s['late']} | "
              f"{'consistent' if settled else 'INCONSISTENT'} |")
        print(f"| {s['stream']}: receive->publish p99 | {p99:.1f} ms | {'bounded' if p99 <= a.p99_limit_ms else 'OVER'} |")
        ok &= settled and p99 <= a.p99_limit_ms and s["frames_out"] > 0
    print(f"\nsoak: {'PASS' if ok else 'FAIL'} ({a.minutes:g} min, {a.streams} streams at {a.fps:g} fps, engine {a.engine}, {'no junk' if a.no_junk else 'junk traffic'})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
