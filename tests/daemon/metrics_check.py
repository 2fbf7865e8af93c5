#!/usr/bin/env python3
"""Reads fqd's GET /metrics with prometheus_client's own text parser (a real parser, not ours)
and prints what it found as JSON in the words of `fqctl counters --json`:
{"streams": {id: {"frames_in": N, ..., "stages": {stage: count}}}, "families": {name: type}}.
Exits 1 with a message when the text does not parse, a series appears twice (the parser
accepts that; a Prometheus server rejects the scrape's duplicates) or a histogram is inconsistent."""
import json
import sys
import urllib.request

from prometheus_client.parser import text_string_to_metric_families

COUNTERS = ["frames_in", "frames_out", "superseded", "dropped_stale", "late", "errors", "time_limited",
            "subscriber_overflows", "bad_send_time", "temporal_resets", "untracked", "preempted",
            "preempted_others"]


def main(url):
    text = urllib.request.urlopen(url, timeout=30).read().decode("utf-8")
    streams, families = {}, {}
    buckets = {}
    seen = set()
    for family in text_string_to_metric_families(text):
        families[family.name] = family.type
        for s in family.samples:
            series = (s.name, tuple(sorted(s.labels.items())))
            if series in seen:
                sys.exit(f"series {s.name}{dict(s.labels)} appears twice")
            seen.add(series)
            stream = s.labels.get("stream")
            if s.name.endswith("_total") and s.name[3:-6] in COUNTERS:
                streams.setdefault(stream, {"stages": {}})[s.name[3:-6]] = int(s.value)
            elif s.name == "fq_stage_latency_seconds_count":
                streams.setdefault(stream, {"stages": {}})["stages"][s.labels["stage"]] = int(s.value)
            elif s.name == "fq_stage_latency_seconds_bucket":
                key = (stream, s.labels["stage"])
                buckets.setdefault(key, []).append((float(s.labels["le"]), s.value))
    for (stream, stage), b in buckets.items():
        counts = [v for _, v in sorted(b)]
        if counts != sorted(counts):
            sys.exit(f"histogram {stream}/{stage}: buckets not cumulative: {counts}")
        if sorted(b)[-1][0] != float("inf") or counts[-1] != streams[stream]["stages"][stage]:
            sys.exit(f"histogram {stream}/{stage}: +Inf bucket differs from _count")
    print(json.dumps({"streams": streams, "families": families}))


if __name__ == "__main__":
    main(sys.argv[1])
