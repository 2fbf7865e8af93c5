#!/usr/bin/env python3
"""The deployments' HTTP listeners, which bind 0.0.0.0, need the bearer token by default:
  - deploy/k8s/fqd.toml and docker/fqd.container.toml set http.token_file;
  - Kubernetes mounts that file from a Secret that is not optional (no Secret, no pod);
  - compose hands it to every fqd service as a secret from the environment;
  - fqd on the container's configuration (its sockets moved to 127.0.0.1, any free port) does
    not start without the file, and with it answers /metrics 401 without the token, 200 with
    it, and /healthz without it.

    check_http_token.py FQD SOURCE_DIR"""
import json
import os
import posixpath
import subprocess
import sys
import tempfile
import tomllib
import urllib.error
import urllib.request

import yaml


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def token_file(config_path):
    http = tomllib.load(open(config_path, "rb")).get("http", {})
    if http.get("listen", "").startswith(("127.", "[::1]", "localhost")):
        return None
    if not http.get("token_file"):
        fail(f"{config_path}: http.listen {http.get('listen')} beyond loopback without http.token_file")
    return http["token_file"]


def check_k8s(src):
    path = token_file(f"{src}/deploy/k8s/fqd.toml")
    (ss,) = [d for d in yaml.safe_load_all(open(f"{src}/deploy/k8s/statefulset.yaml")) if d and d["kind"] == "StatefulSet"]
    spec = ss["spec"]["template"]["spec"]
    (c,) = [c for c in spec["containers"] if c["name"] == "fqd"]
    mounts = [m for m in c.get("volumeMounts", []) if m["mountPath"] == posixpath.dirname(path)]
    if not mounts:
        fail(f"no volume of the fqd container is mounted at {posixpath.dirname(path)} (http.token_file {path})")
    (vol,) = [v for v in spec["volumes"] if v["name"] == mounts[0]["name"]]
    secret = vol.get("secret")
    if not secret or secret.get("optional", False):
        fail(f"http.token_file {path} does not come from a required Secret")
    keys = [i["path"] for i in secret.get("items", [])] or [posixpath.basename(path)]
    if posixpath.basename(path) not in keys:
        fail(f"the Secret volume has no file {posixpath.basename(path)}")
    return secret["secretName"]


def check_compose(src):
    path = token_file(f"{src}/docker/fqd.container.toml")
    if posixpath.dirname(path) != "/run/secrets":
        fail(f"docker/fqd.container.toml: http.token_file {path} is not a compose secret (/run/secrets/NAME)")
    name = posixpath.basename(path)
    compose = yaml.safe_load(open(f"{src}/docker/compose.yaml"))
    if "environment" not in compose.get("secrets", {}).get(name, {}):
        fail(f"compose.yaml: no secret {name} from the environment")
    fqds = [n for n, s in compose["services"].items() if n.startswith("fqd")]
    for n in fqds:
        given = [s if isinstance(s, str) else s.get("source") for s in compose["services"][n].get("secrets", [])]
        if name not in given:
            fail(f"compose.yaml: service {n} is not given the secret {name}")
    return f"{len(fqds)} compose services"


def get(url, token=None):
    req = urllib.request.Request(url, headers={"Authorization": f"Bearer {token}"} if token else {})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status
    except urllib.error.HTTPError as e:
        return e.code


def check_live(fqd, src):
    with tempfile.TemporaryDirectory() as tmp:
        text = open(f"{src}/docker/fqd.container.toml").read()
        for port in ["5555", "5556", "5557"]:
            text = text.replace(f"tcp://0.0.0.0:{port}", "tcp://127.0.0.1:*")
        text = text.replace("/run/secrets/fq_http_token", f"{tmp}/token")
        open(f"{tmp}/fqd.toml", "w").write(text)
        cmd = [fqd, "--config", f"{tmp}/fqd.toml", "--http-listen", "127.0.0.1:0", "--engine", "cpu",
               "--print-endpoints"]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        if r.returncode == 0 or "http.token_file" not in r.stderr:
            fail(f"fqd without its token file: exit {r.returncode}, expected a refusal naming it:\n{r.stderr}")
        token = "0123456789abcdef0123456789abcdef"
        open(f"{tmp}/token", "w").write(token + "\n")
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        try:
            http = json.loads(p.stdout.readline())["http"]
            got = (get(f"{http}/healthz"), get(f"{http}/metrics"), get(f"{http}/metrics", token))
        finally:
            p.terminate()
            p.wait(timeout=30)
        if got != (200, 401, 200):
            fail(f"/healthz, /metrics without and with the token answered {got}, expected (200, 401, 200)")


def main(fqd, src):
    secret = check_k8s(src)
    services = check_compose(src)
    check_live(fqd, src)
    print(f"http token: Secret {secret} in Kubernetes, {services}; the container's fqd needs it")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
