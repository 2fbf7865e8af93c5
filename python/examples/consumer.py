"""Receives fqd's results for stream 'cam' and prints one line each (docs/PYTHON.md).

Usage: python3 consumer.py PUBLISH_ENDPOINT [LAST]    e.g. tcp://127.0.0.1:5556 4
Exits 0 after the result of frame LAST (default 4), 1 when 10 s pass without a result.
"""
import sys

import fq

endpoint = sys.argv[1]
last = int(sys.argv[2]) if len(sys.argv) > 2 else 4
with fq.Consumer(endpoint, "cam", iter_timeout_s=10) as consumer:
    print(f"waiting for results on {endpoint}", file=sys.stderr, flush=True)
    for result in consumer:  # fqd may skip a frame when a newer one of the stream is waiting
        h = result.header
        print(f"result {h['sequence']}: {h['status']}, {len(result.positions)} vertices, "
              f"{h['latency_ms']:.1f} ms, noise {h['noise_estimate']:.4f}", flush=True)
        if h["sequence"] == last:
            sys.exit(0)
sys.exit(1)
