#!/usr/bin/env bash
# fqd run from an installed prefix (the fq_package_install step's): the viewer, the example
# configuration, the systemd unit and the docs are there; fqd started from / with no web_root
# serves the installed viewer at / and its three.js files; the example configuration is valid
# and the installed unit verifies with its prefix's paths.  installed_fqd.sh PREFIX SOURCE_DIR
set -euo pipefail
prefix=$1 src=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
for f in bin/fqd share/fq/web/index.html share/fq/web/viewer.js share/fq/web/frame_decode.js \
         share/fq/web/node_modules/three/build/three.module.js \
         share/fq/web/node_modules/three/examples/jsm/libs/draco/draco_decoder.wasm \
         share/doc/fq/examples/fqd.toml share/doc/fq/DAEMON.md share/doc/fq/README.md \
         lib/systemd/system/fqd.service; do
  [[ -f $prefix/$f ]] || fail "$f is not installed"
done
[[ ! -e $prefix/share/fq/web/node_modules/playwright-core ]] || fail "the test-only playwright-core is installed"
unit=$prefix/lib/systemd/system/fqd.service
grep -qx "ExecStart=$prefix/bin/fqd" "$unit" || fail "the unit does not start $prefix/bin/fqd: $(grep ExecStart= "$unit")"
grep -q "Documentation=file://$prefix/share/doc/fq/DAEMON.md" "$unit" || fail "the unit's Documentation= is not the installed DAEMON.md"
if command -v systemd-analyze >/dev/null; then
  out=$(systemd-analyze verify "$unit" 2>&1) && [[ -z $out ]] || fail "systemd-analyze verify: $out"
fi
(cd / && "$prefix/bin/fqd" --config "$prefix/share/doc/fq/examples/fqd.toml" --check-config) || fail "example config"

tmp=$(mktemp -d)
fqd_pid=
cleanup() { [[ -n $fqd_pid ]] && kill "$fqd_pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
# The tests' fqd (free ports on 127.0.0.1, the CPU engine), with HTTP and no web_root.
{ cat "$src/tests/daemon/child_fqd.toml"; printf '[http]\nlisten = "127.0.0.1:0"\n'; } >"$tmp/fqd.toml"
# From /, with no web_root: only the install's own location can give the viewer.
(cd / && exec "$prefix/bin/fqd" --config "$tmp/fqd.toml" --endpoints-file "$tmp/endpoints.json") &
fqd_pid=$!
for _ in $(seq 300); do [[ -s $tmp/endpoints.json ]] && break; sleep 0.1; done
[[ -s $tmp/endpoints.json ]] || fail "fqd did not start"
/usr/bin/python3 - "$tmp/endpoints.json" <<'PY'
import json, sys, urllib.request
base = json.load(open(sys.argv[1]))["http"]
def get(path):
    with urllib.request.urlopen(base + path, timeout=30) as r:
        return r.status, r.read()
status, index = get("/")
assert status == 200 and b"importmap" in index, (status, index[:200])
for asset in ["/viewer.js", "/frame_decode.js", "/node_modules/three/build/three.module.js",
              "/node_modules/three/build/three.core.js", "/node_modules/three/examples/jsm/controls/OrbitControls.js",
              "/node_modules/three/examples/jsm/libs/draco/draco_wasm_wrapper.js"]:
    status, body = get(asset)
    assert status == 200 and len(body) > 1000, (asset, status, len(body))
print(f"installed fqd at {base}: / and the viewer's assets served from the prefix")
PY
kill -TERM "$fqd_pid"
wait "$fqd_pid" || fail "fqd exited $? after SIGTERM"
fqd_pid=
