"""Sends a mesh to fqd as a capture would: N noisy frames on stream 'cam' (docs/PYTHON.md).

Usage: python3 producer.py INGEST_ENDPOINT MESH [FRAMES]    e.g. tcp://127.0.0.1:5555 data/fandisk.ply 5
"""
import sys

import fq

endpoint, path = sys.argv[1], sys.argv[2]
frames = int(sys.argv[3]) if len(sys.argv) > 3 else 5
V, F = fq.read_mesh(path)
with fq.Producer(endpoint, "cam") as producer:
    for i in range(frames):
        noisy = fq.add_noise(V, F, 0.2, seed=i)  # a new capture of the same surface
        sequence = producer.send(noisy, F, timeout_s=10)
        print(f"sent frame {sequence}: {len(noisy)} vertices", flush=True)
