#!/usr/bin/env python3
"""deploy/k8s without a cluster: the kustomization's parts exist and fit together, the pods meet
the restricted Pod Security Standard, have resource requests, scrape annotations and a
PodDisruptionBudget, a NetworkPolicy lets only labelled pods reach the control port, the image
is set by the kustomization's images: entry, every pod gets the shard its ordinal names with the
replica count, and every listed stream is served by exactly one pod. With kubectl (kustomize
built in), the rendered output is checked the same way, for the replica count as given and for
another, and for another image.

    check_k8s.py FQD SOURCE_DIR"""
import os
import shutil
import subprocess
import sys
import tempfile

import yaml


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def docs(path):
    return [d for d in yaml.safe_load_all(open(path)) if d]


def check_pod_template(ss, replicas):
    spec = ss["spec"]["template"]["spec"]
    meta = ss["spec"]["template"]["metadata"]
    pod_sc = spec.get("securityContext", {})
    if pod_sc.get("runAsNonRoot") is not True or pod_sc.get("seccompProfile", {}).get("type") != "RuntimeDefault":
        fail("restricted: the pod needs runAsNonRoot and the RuntimeDefault seccomp profile")
    if pod_sc.get("runAsUser", 0) == 0:
        fail("restricted: the pod runs as uid 0")
    (c,) = [c for c in spec["containers"] if c["name"] == "fqd"]
    sc = c.get("securityContext", {})
    if sc.get("allowPrivilegeEscalation") is not False or sc.get("capabilities", {}).get("drop") != ["ALL"]:
        fail("restricted: the container must drop ALL capabilities and disallow privilege escalation")
    if sc.get("privileged") or sc.get("capabilities", {}).get("add"):
        fail("restricted: no privileged container, no added capability")
    for v in spec.get("volumes", []):
        if "hostPath" in v:
            fail("restricted: no hostPath volume")
    req = c.get("resources", {}).get("requests", {})
    if not req.get("cpu") or not req.get("memory"):
        fail("the fqd container has no cpu and memory requests")
    ann = meta.get("annotations", {})
    if ann.get("prometheus.io/scrape") != "true" or ann.get("prometheus.io/port") != "8080":
        fail("the pods lack the prometheus.io scrape annotations")
    env = {e["name"]: e for e in c["env"]}
    if env["POD_NAME"]["valueFrom"]["fieldRef"]["fieldPath"] != "metadata.name":
        fail("POD_NAME is not the pod's name")
    if env["FQ_SHARDS"]["value"] != str(replicas):
        fail(f"FQ_SHARDS is {env['FQ_SHARDS']['value']}, the StatefulSet has {replicas} replicas")
    args = c["args"]
    if args[args.index("--shard") + 1] != "$(POD_NAME)/$(FQ_SHARDS)":
        fail("fqd is not started with --shard $(POD_NAME)/$(FQ_SHARDS)")
    return meta["labels"]


def check_network_policy(policy, pod_labels, control_label):
    """Only pods with `control_label` (a one-item dict) reach the control port; the ingest,
    publish and HTTP ports stay open to every source."""
    spec = policy["spec"]
    if any(pod_labels.get(k) != v for k, v in spec["podSelector"]["matchLabels"].items()):
        fail("the NetworkPolicy selects no fqd pod")
    if spec.get("policyTypes") != ["Ingress"]:
        fail("the NetworkPolicy must govern ingress only (fqd connects out to its producers)")
    open_ports, control_from = set(), []
    for rule in spec["ingress"]:
        ports = {p["port"] for p in rule["ports"]}
        if "from" not in rule:
            open_ports |= ports
        elif 5557 in ports:
            control_from += rule["from"]
    if open_ports != {5555, 5556, 8080}:
        fail(f"the NetworkPolicy opens ports {sorted(open_ports)} to everyone, expected 5555, 5556 and 8080")
    if not control_from or any(f.get("podSelector", {}).get("matchLabels") != control_label or "namespaceSelector" in f
                               or "ipBlock" in f for f in control_from):
        fail(f"the control port must be reachable only from pods of the namespace labelled {control_label}")


def check_rendered(objects, replicas):
    kinds = {o["kind"]: o for o in objects}
    for k in ["Namespace", "StatefulSet", "Service", "PodDisruptionBudget", "ConfigMap", "NetworkPolicy"]:
        if k not in kinds:
            fail(f"the kustomization renders no {k}")
    ns = kinds["Namespace"]["metadata"]
    if ns["labels"].get("pod-security.kubernetes.io/enforce") != "restricted":
        fail("the namespace does not enforce the restricted Pod Security Standard")
    ss = kinds["StatefulSet"]
    if ss["spec"]["replicas"] != replicas:
        fail(f"StatefulSet replicas {ss['spec']['replicas']}, expected {replicas}")
    labels = check_pod_template(ss, replicas)
    check_network_policy(kinds["NetworkPolicy"], labels, {"fq-control": "true"})
    pdb = kinds["PodDisruptionBudget"]["spec"]
    if any(labels.get(k) != v for k, v in pdb["selector"]["matchLabels"].items()):
        fail("the PodDisruptionBudget selects no fqd pod")
    cm = ss["spec"]["template"]["spec"]["volumes"][0]["configMap"]["name"]
    if cm != kinds["ConfigMap"]["metadata"]["name"]:
        fail(f"the pods mount ConfigMap {cm}, the kustomization makes {kinds['ConfigMap']['metadata']['name']}")
    for o in objects:
        if o["kind"] != "Namespace" and o["metadata"].get("namespace") != ns["name"]:
            fail(f"{o['kind']} {o['metadata']['name']} is outside namespace {ns['name']}")


def check_shards(fqd, config, replicas):
    served = {}
    for k in range(replicas):
        out = subprocess.run([fqd, "--config", config, "--shard", f"fqd-{k}/{replicas}", "--shard-map", str(replicas)],
                             check=True, capture_output=True, text=True).stdout
        for line in out.splitlines():  # the streams pod k keeps, with the shard each hashes to
            stream, ordinal = line.split()
            if int(ordinal) != k:
                fail(f"pod {k} of {replicas} keeps {stream}, which hashes to {ordinal}")
            served.setdefault(stream, set()).add(k)
        with tempfile.TemporaryDirectory() as tmp:  # the pod's Secrets stood in for: --check-config reads them
            stand_in = subprocess.run(["bash", f"{os.path.dirname(os.path.abspath(__file__))}/stand_in_secrets.sh",
                                       config, tmp], check=True, capture_output=True, text=True).stdout.strip()
            subprocess.run([fqd, "--config", stand_in, "--shard", f"fqd-{k}/{replicas}", "--check-config"],
                           check=True, stdout=subprocess.DEVNULL)
    streams = yaml.safe_load("x: " + open(config).read().split("streams = ", 1)[1].split("\n", 1)[0])["x"]
    if sorted(served) != sorted(streams) or any(len(v) != 1 for v in served.values()):
        fail(f"streams not served by exactly one of {replicas} pods: {served}")


def main(fqd, src):
    k8s = f"{src}/deploy/k8s"
    kz = yaml.safe_load(open(f"{k8s}/kustomization.yaml"))
    objects = []
    for r in kz["resources"]:
        objects += docs(f"{k8s}/{r}")
    for gen in kz["configMapGenerator"]:
        for f in gen["files"]:
            if not os.path.isfile(f"{k8s}/{f}"):
                fail(f"configMapGenerator file {f} is missing")
        objects.append({"kind": "ConfigMap", "metadata": {"name": gen["name"], "namespace": kz["namespace"]}})
    (replicas,) = [r["count"] for r in kz["replicas"] if r["name"] == "fqd"]
    for o in objects:  # what kustomize does with namespace: and replicas:
        if o["kind"] != "Namespace":
            o["metadata"]["namespace"] = kz["namespace"]
        if o["kind"] == "StatefulSet":
            o["spec"]["replicas"] = replicas
            for c in o["spec"]["template"]["spec"]["containers"]:
                for e in c["env"]:
                    if e["name"] == "FQ_SHARDS":
                        e["value"] = str(replicas)
    (rep,) = kz["replacements"]
    if rep["source"]["fieldPath"] != "spec.replicas" or "env.[name=FQ_SHARDS].value" not in rep["targets"][0]["fieldPaths"][0]:
        fail("the replica count does not reach FQ_SHARDS")
    (image,) = [c["image"] for o in objects if o["kind"] == "StatefulSet" for c in o["spec"]["template"]["spec"]["containers"]]
    if not any(image.split(":")[0] == i["name"] for i in kz.get("images", [])):
        fail(f"kustomization.yaml has no images: entry for {image.split(':')[0]} (the image to edit)")
    check_rendered(objects, replicas)
    check_shards(fqd, f"{k8s}/fqd.toml", replicas)
    rendered = "kustomize-free checks only (no kubectl)"
    if shutil.which("kubectl"):
        for count in [replicas, replicas + 1]:
            with tempfile.TemporaryDirectory() as tmp:
                shutil.copytree(k8s, f"{tmp}/k8s")
                text = open(f"{tmp}/k8s/kustomization.yaml").read().replace(f"count: {replicas}", f"count: {count}")
                open(f"{tmp}/k8s/kustomization.yaml", "w").write(text)
                out = subprocess.run(["kubectl", "kustomize", f"{tmp}/k8s"], check=True, capture_output=True, text=True)
                check_rendered([d for d in yaml.safe_load_all(out.stdout) if d], count)
            check_shards(fqd, f"{k8s}/fqd.toml", count)
        # The images: entry is what sets the pods' image.
        with tempfile.TemporaryDirectory() as tmp:
            shutil.copytree(k8s, f"{tmp}/k8s")
            kz_tmp = yaml.safe_load(open(f"{tmp}/k8s/kustomization.yaml"))
            kz_tmp["images"] = [dict(i, newName="registry.test/fq-x", newTag="t1") for i in kz_tmp["images"]]
            open(f"{tmp}/k8s/kustomization.yaml", "w").write(yaml.safe_dump(kz_tmp))
            out = subprocess.run(["kubectl", "kustomize", f"{tmp}/k8s"], check=True, capture_output=True, text=True)
            (ss,) = [d for d in yaml.safe_load_all(out.stdout) if d and d["kind"] == "StatefulSet"]
            if ss["spec"]["template"]["spec"]["containers"][0]["image"] != "registry.test/fq-x:t1":
                fail("the images: entry of kustomization.yaml does not set the fqd container's image")
        rendered = (f"kubectl kustomize renders it for {replicas} and {replicas + 1} replicas, with the "
                    "NetworkPolicy and the image from images:")
    print(f"k8s: restricted pods, requests, scrape annotations, PDB, {replicas} shards; {rendered}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
