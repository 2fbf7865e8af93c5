#!/usr/bin/env bash
# The C++ client examples (clients/examples) against the installed fqd (tests/daemon/child_fqd.toml:
# free ports of 127.0.0.1, the CPU engine): the consumer compiled with pkg-config fq-client (step
# client_pkgconfig), the producer built with find_package(fq COMPONENTS client) (step client_cmake).
# The consumer must get the results of the 5 frames, in order, OK, every vertex of them close to
# the producer's torus: closer on the whole (rms) than the noise the producer added (sigma 0.03).
# Usage: client_examples.sh PREFIX SOURCE_DIR WORK (WORK: the steps' build folders)
set -euo pipefail
prefix=$1 src=$2 work=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d)
fqd_pid= consumer_pid=
cleanup() {
  [[ -z $consumer_pid ]] || kill "$consumer_pid" 2>/dev/null || true
  [[ -z $fqd_pid ]] || kill "$fqd_pid" 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
cp "$src/tests/daemon/child_fqd.toml" "$tmp/fqd.toml"
OMP_WAIT_POLICY=passive "$prefix/bin/fqd" --config "$tmp/fqd.toml" --endpoints-file "$tmp/endpoints.json" &
fqd_pid=$!
for _ in $(seq 300); do [[ -s $tmp/endpoints.json ]] && break; sleep 0.1; done
[[ -s $tmp/endpoints.json ]] || fail "fqd did not start"
endpoint() {
  /usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' \
    "$tmp/endpoints.json" "$1"
}

"$work/client_pkgconfig/consumer" "$(endpoint publish)" 4 >"$tmp/results" 2>"$tmp/consumer.err" &
consumer_pid=$!
for _ in $(seq 100); do grep -qs "^waiting for results" "$tmp/consumer.err" && break; sleep 0.1; done
grep -qs "^waiting for results" "$tmp/consumer.err" || fail "no consumer: $(cat "$tmp/consumer.err")"
# 1 frame a second: fqd keeps only a stream's newest waiting frame, and a result took up to 0.85 s
# at 5 a second while other builds loaded the 2-core development machine (frames 1 and 3 superseded).
"$work/client_cmake/producer" "$(endpoint ingest)" 5 1 >"$tmp/sent" || fail "the producer exited $?"
wait "$consumer_pid" || fail "the consumer exited $?: $(cat "$tmp/consumer.err")"
consumer_pid=
cat "$tmp/sent" "$tmp/results"
diff <(printf 'sent frame %d: 4608 vertices\n' 0 1 2 3 4) "$tmp/sent" || fail "the producer printed the above"
# result N: OK, 4608 vertices, L ms, off the torus rms R max M
awk '$1 != "result" || $2 != NR - 1 ":" || $3 != "OK," || $4 != 4608 { bad = 1 }
     !($(NF - 2) < 0.02 && $NF < 0.1) { bad = 1 }
     END { exit bad || NR != 5 }' "$tmp/results" || fail "expected frames 0..4: OK, rms < 0.02, max < 0.1"
kill -TERM "$fqd_pid"
wait "$fqd_pid" || fail "fqd exited $? after SIGTERM"
fqd_pid=
