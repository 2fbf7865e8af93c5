"""Ctrl-C (SIGINT) stops a running engine call through fq's cancel token."""
import os
import signal
import subprocess
import sys
import time

# A sphere of about 1.5 million vertices: filtering it takes many seconds on 2 threads, so the
# interrupt lands inside the engine run, and an uncancelled run could not end in time.
SCRIPT = """
import sys
import numpy as np
import fq

n = 1200
theta, phi = np.meshgrid(np.linspace(0.1, np.pi - 0.1, n), np.linspace(0, 2 * np.pi, n, endpoint=False),
                         indexing="ij")
V = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1).reshape(-1, 3)
i, j = np.meshgrid(np.arange(n - 1), np.arange(n), indexing="ij")
a, b = (i * n + j).ravel(), (i * n + (j + 1) % n).ravel()
F = np.concatenate([np.stack([a, a + n, b], 1), np.stack([b, a + n, b + n], 1)])
V = fq.add_noise(V, F, 0.3)
print("filtering", flush=True)
try:
    fq.filter(V, F, engine="cpu", threads=2, sigma_s=3.0)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    small = fq.filter(V[:3], np.array([[0, 1, 2]]), engine="cpu", threads=2)  # the engine still works
    sys.exit(3 if small.shape == (3, 3) else 4)
print("finished", flush=True)
"""


def test_sigint_stops_a_running_filter():
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    child = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env)
    assert child.stdout.readline().strip() == "filtering"
    time.sleep(1.5)  # well inside the engine run
    child.send_signal(signal.SIGINT)
    sent = time.monotonic()
    out, err = child.communicate(timeout=60)
    waited = time.monotonic() - sent
    assert child.returncode == 3, f"exit {child.returncode}: {out} {err}"
    assert "interrupted" in out
    # The engine stops at its next check (between chunks of its loops); without the cancel
    # token the call would run to its end, tens of seconds on two threads.
    assert waited < 3.0, f"took {waited:.1f} s to stop"
