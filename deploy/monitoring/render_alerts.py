#!/usr/bin/env python3
"""Writes fqd's Prometheus alert rules for one scrape job, mixin style: the rules are below, the
job is a parameter. Rules that read Prometheus' `up` or the process_* families (which every
target exports) select fqd's targets by the job, and the others read only fq_* names.

    render_alerts.py                                  # deploy/monitoring/fqd-alerts.yml (job="fqd")
    render_alerts.py --job kubernetes-pods --selector 'namespace="fq"' -o fqd-alerts.yml
    render_alerts.py --runbook-base https://docs.example/fq/DAEMON.md -o fqd-alerts.yml

--job names the job of Prometheus' scrape configuration that finds fqd (`fqd` for a static
one; `kubernetes-pods` for pods found by their prometheus.io/scrape annotation, as
deploy/k8s's are); --selector adds label matchers for a job that scrapes more than fqd (the
labels its relabeling gives, e.g. namespace="fq"). Each rule's runbook_url is --runbook-base
(default: the repository's docs/DAEMON.md) and the anchor of the alert's section there.
tests/deploy/check_monitoring.py checks that the committed fqd-alerts.yml is this script's
output for the defaults."""
import argparse
import re
import sys

RULES = r"""# Prometheus alert rules for fqd (load with rule_files: in prometheus.yml), written by
# deploy/monitoring/render_alerts.py for @SELECTOR@: edit the rules there, and write this file
# again with it (`render_alerts.py --job NAME` for another scrape job). They read only what fqd
# exports on /metrics (docs/DAEMON.md, "Metrics an SRE alerts on") and Prometheus' own `up`;
# tests/deploy/check_monitoring.py runs `promtool check rules` and `promtool test rules`
# (fqd-alerts.test.yml) on them and checks every metric name against a live fqd.
# Labels: `instance` (the scrape target), `stream` (fqd's stream id), `reason`, `engine`.
# runbook_url: the alert's section of docs/DAEMON.md ("Alert runbook").
groups:
  - name: fqd
    rules:
      - alert: FqdDown
        expr: up{@SELECTOR@} == 0
        for: 2m
        labels: {severity: critical}
        annotations:
          summary: "fqd {{ $labels.instance }} is not answering /metrics"
          description: "Prometheus could not scrape fqd for 2 minutes: the process is down, or its HTTP listener is."
          runbook_url: "@RUNBOOK@#runbook-fqddown"

      - alert: FqdAbsent
        expr: absent(up{@SELECTOR@})
        for: 10m
        labels: {severity: critical}
        annotations:
          summary: "no fqd target is scraped (up{@SELECTOR_TEXT@} has no series)"
          description: >-
            Prometheus scrapes no target matching these labels, so FqdDown cannot fire: fqd is not
            deployed, its scrape configuration is missing, or the rules were written for another job
            (deploy/monitoring/render_alerts.py --job).
          runbook_url: "@RUNBOOK@#runbook-fqdabsent"

      - alert: FqdRestartLoop
        expr: changes(process_start_time_seconds{@SELECTOR@}[30m]) > 2
        labels: {severity: critical}
        annotations:
          summary: "fqd {{ $labels.instance }} restarted {{ $value }} times in 30 minutes"
          description: "Look at the log's first lines (version, configuration, what is off) and the last ones before each exit."
          runbook_url: "@RUNBOOK@#runbook-fqdrestartloop"

      - alert: FqdStreamMostlyLate
        expr: |
          sum by (instance, stream) (rate(fq_late_total[5m]))
            / sum by (instance, stream) (rate(fq_frames_out_total[5m])) > 0.5
        for: 5m
        labels: {severity: warning}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: most results late"
          description: >-
            More than half of the stream's results missed its budget (budget_ms) for 5 minutes. fqd's
            log has a warning per [stats] interval naming the likeliest cause (the engine, waiting for
            an engine, or the rest of the pipeline).
          runbook_url: "@RUNBOOK@#runbook-fqdstreammostlylate"

      - alert: FqdStreamLatencyOverBudget
        expr: |
          histogram_quantile(0.99,
            sum by (instance, stream, le) (rate(fq_stage_latency_seconds_bucket{stage="receive_to_publish"}[5m])))
            > on (instance, stream) fq_stream_budget_seconds
        for: 10m
        labels: {severity: warning}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: receive->publish p99 over its budget"
          runbook_url: "@RUNBOOK@#runbook-fqdstreamlatencyoverbudget"

      - alert: FqdFramesDropped
        expr: |
          sum by (instance, stream) (rate(fq_superseded_total[5m]) + rate(fq_dropped_stale_total[5m]))
            / sum by (instance, stream) (rate(fq_frames_in_total[5m])) > 0.2
        for: 10m
        labels: {severity: warning}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: over 20% of frames dropped (superseded or stale)"
          description: "The engines do not keep up with the stream's frame rate; results come at a lower rate than frames."
          runbook_url: "@RUNBOOK@#runbook-fqdframesdropped"

      - alert: FqdStreamErrors
        expr: sum by (instance, stream) (rate(fq_errors_total[5m])) > 0
        for: 5m
        labels: {severity: warning}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: error results"
          description: "Bad frames, invalid parameters, the engine time limit or an engine failure; fqd's log names each."
          runbook_url: "@RUNBOOK@#runbook-fqdstreamerrors"

      - alert: FqdStreamPreempted
        expr: |
          sum by (instance, stream) (rate(fq_preempted_total[5m]))
            / sum by (instance, stream) (rate(fq_frames_in_total[5m])) > 0.1
        for: 10m
        labels: {severity: warning}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: over 10% of frames preempted"
          description: >-
            fqd stops a frame on an engine only when it cannot meet its budget and another stream's
            frame would miss its own behind it. The stream's frames take longer than its budget_ms on
            an engine that other streams need: raise its budget, lighten its parameters, or add an engine.
          runbook_url: "@RUNBOOK@#runbook-fqdstreampreempted"

      - alert: FqdRefusingFrames
        expr: sum by (instance, reason) (rate(fq_refused_total[5m])) > 0
        for: 5m
        labels: {severity: warning}
        annotations:
          summary: "fqd {{ $labels.instance }} refuses messages or peers ({{ $labels.reason }})"
          description: >-
            A producer sends frames fqd does not admit (not_allowed: not in caps.allowed_streams;
            too_many_streams: caps.max_streams reached; unauthenticated: CURVE key not listed;
            oversized: a message over its size bound; subscriptions: a subscriber over its caps; ...).
            The producer believes them sent.
          runbook_url: "@RUNBOOK@#runbook-fqdrefusingframes"

      - alert: FqdEngineSaturated
        expr: rate(fq_engine_busy_seconds_total[10m]) > 0.9
        for: 15m
        labels: {severity: warning}
        annotations:
          summary: "engine {{ $labels.engine }} ({{ $labels.index }}) on {{ $labels.instance }} busy over 90%"
          description: "No headroom: more frames or streams will be superseded or late. Add an engine or an fqd (--shard)."
          runbook_url: "@RUNBOOK@#runbook-fqdenginesaturated"

      - alert: FqdSubscriberOverflows
        expr: sum by (instance, stream) (rate(fq_subscriber_overflows_total[5m])) > 0
        for: 10m
        labels: {severity: info}
        annotations:
          summary: "stream {{ $labels.stream }} on {{ $labels.instance }}: a subscriber does not keep up"
          runbook_url: "@RUNBOOK@#runbook-fqdsubscriberoverflows"

      - alert: FqdFileDescriptorsNearLimit
        expr: process_open_fds{@SELECTOR@} / process_max_fds{@SELECTOR@} > 0.8
        for: 10m
        labels: {severity: warning}
        annotations:
          summary: "fqd {{ $labels.instance }} uses over 80% of its file descriptors"
          runbook_url: "@RUNBOOK@#runbook-fqdfiledescriptorsnearlimit"

      - alert: FqdGpuMemoryHigh
        expr: fq_gpu_memory_used_bytes / fq_gpu_memory_total_bytes > 0.9
        for: 10m
        labels: {severity: warning}
        annotations:
          summary: "GPU {{ $labels.gpu }} on {{ $labels.instance }}: over 90% of device memory in use"
          runbook_url: "@RUNBOOK@#runbook-fqdgpumemoryhigh"
"""

DEFAULT_RUNBOOK = "docs/DAEMON.md"


def render(job="fqd", selector="", runbook_base=DEFAULT_RUNBOOK):
    """The rules file's text for the scrape job `job` and extra label matchers `selector`."""
    if not re.fullmatch(r"[A-Za-z0-9_.:/-]+", job):
        raise ValueError(f"--job {job!r}: a Prometheus job name (letters, digits, _ . : / -)")
    matchers = f'job="{job}"' + (f",{selector}" if selector else "")
    if '"' in runbook_base or "\\" in runbook_base:
        raise ValueError("--runbook-base: no quotes or backslashes")
    # In the summary the matchers are inside a double-quoted YAML string.
    return (RULES.replace("@SELECTOR_TEXT@", matchers.replace('"', '\\"'))
            .replace("@SELECTOR@", matchers).replace("@RUNBOOK@", runbook_base))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--job", default="fqd", help="the scrape job that finds fqd (default: fqd)")
    ap.add_argument("--selector", default="", help='more label matchers for fqd\'s targets, e.g. namespace="fq"')
    ap.add_argument("--runbook-base", default=DEFAULT_RUNBOOK,
                    help=f"the runbook's URL, without the anchor (default: {DEFAULT_RUNBOOK})")
    ap.add_argument("-o", "--output", help="the file to write (default: stdout)")
    a = ap.parse_args(argv)
    try:
        text = render(a.job, a.selector, a.runbook_base)
    except ValueError as e:
        ap.error(str(e))
    if a.output:
        with open(a.output, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
