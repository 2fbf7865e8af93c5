#!/usr/bin/env python3
"""The monitoring files against fqd itself: deploy/monitoring/fqd-alerts.yml is what
render_alerts.py writes for the default job; `promtool check rules` and `promtool test rules` on
it (fqd-alerts.test.yml) and on the rules written for another job (fqd-alerts.job.test.yml);
every rule has a runbook_url whose anchor docs/DAEMON.md has; then every PromQL expression of the alert rules, the Grafana
dashboard (deploy/monitoring/fqd-dashboard.json, panels and variables) and the ```promql blocks of
docs/DAEMON.md is parsed by promtool (as a recording rule, Grafana's variables replaced) and each
metric name it reads is looked up among the families a live fqd exports on /metrics.

    check_monitoring.py FQD SOURCE_DIR

Exit 77 (skipped) only when promtool is absent (Debian package prometheus)."""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import urllib.request

import yaml

KEYWORDS = {"by", "without", "on", "ignoring", "group_left", "group_right", "bool", "and", "or", "unless",
            "offset", "inf", "nan", "atan2"}
PROMETHEUS_OWN = {"up"}  # made by Prometheus for every target, not by fqd
GRAFANA_VARS = [("$__rate_interval", "5m"), ("$__interval", "1m"), ("${datasource}", "x")]


def metric_names(expr):
    """The metric names an expression reads: identifiers outside strings, label matchers,
    durations and grouping clauses that are not functions or keywords."""
    e = re.sub(r'"(\\.|[^"\\])*"|\'(\\.|[^\'\\])*\'', '""', expr)
    e = re.sub(r"\{[^}]*\}", " ", e)
    e = re.sub(r"\[[^\]]*\]", " ", e)
    e = re.sub(r"\b(by|without|on|ignoring|group_left|group_right)\s*\([^)]*\)", " ", e)
    names = set()
    for m in re.finditer(r"[A-Za-z_:][A-Za-z0-9_:]*", e):
        word, rest = m.group(0), e[m.end():].lstrip()
        if rest.startswith("(") or word.lower() in KEYWORDS:
            continue
        if m.start() > 0 and (e[m.start() - 1].isdigit() or e[m.start() - 1] == "."):
            continue  # the exponent or unit of a number (1e9)
        names.add(word)
    return names


def grafana_to_promql(expr):
    for var, value in GRAFANA_VARS:
        expr = expr.replace(var, value)
    expr = re.sub(r"\$\{?\w+\}?", ".*", expr)  # $instance, $stream: regex matchers
    m = re.fullmatch(r"\s*label_values\((.*),\s*\w+\)\s*", expr)  # a variable's query
    return m.group(1) if m else expr


def expressions(src):
    out = []
    rules = yaml.safe_load(open(f"{src}/deploy/monitoring/fqd-alerts.yml"))
    for g in rules["groups"]:
        out += [(f"alert {r['alert']}", r["expr"]) for r in g["rules"]]
    dash = json.load(open(f"{src}/deploy/monitoring/fqd-dashboard.json"))
    for p in dash["panels"]:
        out += [(f"panel '{p['title']}'", grafana_to_promql(t["expr"])) for t in p.get("targets", [])]
    for v in dash["templating"]["list"]:
        if v["type"] == "query":
            out.append((f"variable {v['name']}", grafana_to_promql(v["query"]["query"])))
    doc = open(f"{src}/docs/DAEMON.md").read()
    blocks = re.findall(r"```promql\n(.*?)```", doc, re.S)
    if not blocks:
        sys.exit("FAIL: docs/DAEMON.md has no ```promql block")
    for b in blocks:
        for line in b.splitlines():
            line = line.split("#", 1)[0].strip()
            if line:
                out.append(("docs/DAEMON.md", line))
    return out


def exported_names(fqd, src, tmp):
    config = f"{tmp}/fqd.toml"  # the tests' fqd (free ports on 127.0.0.1, the CPU engine) with HTTP
    open(config, "w").write(open(f"{src}/tests/daemon/child_fqd.toml").read() + '[http]\nlisten = "127.0.0.1:0"\n')
    p = subprocess.Popen([fqd, "--config", config, "--print-endpoints"], stdout=subprocess.PIPE, text=True)
    try:
        http = json.loads(p.stdout.readline())["http"]
        text = urllib.request.urlopen(http + "/metrics", timeout=30).read().decode()
    finally:
        p.terminate()
        p.wait(timeout=60)
    names = set()
    for line in text.splitlines():
        if line.startswith("# TYPE "):
            _, _, name, kind = line.split()
            names.add(name)
            if kind == "histogram":
                names |= {name + "_bucket", name + "_sum", name + "_count"}
    return names


# The job and labels fqd-alerts.job.test.yml is written for (a Kubernetes pod discovery).
OTHER_JOB = ["--job", "kubernetes-pods", "--selector", 'namespace="fq"']


def check_rendered_and_runbooks(src, mon):
    render = [sys.executable, f"{mon}/render_alerts.py"]
    rendered = subprocess.run(render, check=True, capture_output=True, text=True).stdout
    if rendered != open(f"{mon}/fqd-alerts.yml").read():
        sys.exit("FAIL: deploy/monitoring/fqd-alerts.yml is not render_alerts.py's output: edit the rules in "
                 "render_alerts.py and run deploy/monitoring/render_alerts.py -o deploy/monitoring/fqd-alerts.yml")
    doc = open(f"{src}/docs/DAEMON.md").read()
    anchors = set(re.findall(r'<a id="([^"]+)"></a>', doc))
    for g in yaml.safe_load(rendered)["groups"]:
        for r in g["rules"]:
            url = r.get("annotations", {}).get("runbook_url", "")
            if not url.startswith("docs/DAEMON.md#") or url.split("#", 1)[1] not in anchors:
                sys.exit(f"FAIL: alert {r['alert']}: runbook_url {url!r} is no anchor of docs/DAEMON.md")


def main(fqd, src):
    promtool = shutil.which("promtool")
    if not promtool:
        print("SKIP: promtool is not installed (scripts/setup-deps.sh installs Debian's prometheus)")
        return 77
    mon = f"{src}/deploy/monitoring"
    check_rendered_and_runbooks(src, mon)
    subprocess.run([promtool, "check", "rules", "fqd-alerts.yml"], cwd=mon, check=True)
    subprocess.run([promtool, "test", "rules", "fqd-alerts.test.yml"], cwd=mon, check=True)
    with tempfile.TemporaryDirectory() as tmp:  # the rules for another job, and their tests
        subprocess.run([sys.executable, f"{mon}/render_alerts.py", *OTHER_JOB, "-o", f"{tmp}/fqd-alerts.job.yml"],
                       check=True)
        shutil.copy(f"{mon}/fqd-alerts.job.test.yml", tmp)
        subprocess.run([promtool, "check", "rules", "fqd-alerts.job.yml"], cwd=tmp, check=True)
        subprocess.run([promtool, "test", "rules", "fqd-alerts.job.test.yml"], cwd=tmp, check=True)
    with tempfile.TemporaryDirectory() as tmp:
        exprs = expressions(src)
        # promtool parses each expression: a recording rule per expression.
        rules = {"groups": [{"name": "check", "rules": [{"record": f"check:{i}", "expr": e}
                                                         for i, (_, e) in enumerate(exprs)]}]}
        open(f"{tmp}/exprs.yml", "w").write(yaml.safe_dump(rules))
        subprocess.run([promtool, "check", "rules", f"{tmp}/exprs.yml"], check=True, stdout=subprocess.DEVNULL)
        exported = exported_names(fqd, src, tmp)
    unknown = []
    for where, e in exprs:
        unknown += [f"{where}: {n} (in {e.strip()})" for n in sorted(metric_names(e) - exported - PROMETHEUS_OWN)]
    if unknown:
        print("FAIL: metric names fqd does not export:\n  " + "\n  ".join(unknown), file=sys.stderr)
        return 1
    print(f"monitoring: rules as render_alerts.py writes them, with runbooks; they pass promtool check and test "
          f"for the job fqd and for {' '.join(OTHER_JOB[1::2])}; {len(exprs)} expressions parse and read only the "
          f"{len(exported)} names fqd exports")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
