#!/usr/bin/env bash
# Deployment files: yamllint (Debian) on the Kubernetes manifests and the compose file, and
# `fqd --check-config` on every fqd configuration they carry (the ConfigMap's TOML entries
# and the container's /etc/fq/fqd.toml).  check_deploy.sh FQD SOURCE_DIR
# Exit 77 (skipped) only when yamllint is absent.
set -euo pipefail
fqd=$1 src=$2
if ! command -v yamllint >/dev/null; then
  echo "SKIP: yamllint is not installed (scripts/setup-deps.sh installs Debian's yamllint)"
  exit 77
fi
yamllint -s -c "$src/.yamllint" "$src/deploy/k8s" "$src/docker/compose.yaml"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# yamllint depends on python3-yaml, so Debian's python3 can read the ConfigMap.
/usr/bin/python3 - "$src/deploy/k8s/configmap.yaml" "$tmp" <<'PY'
import sys, yaml
for doc in yaml.safe_load_all(open(sys.argv[1])):
    for name, text in doc.get("data", {}).items():
        open(f"{sys.argv[2]}/{name}", "w").write(text)
PY
n=0
for f in "$tmp"/*.toml "$src/docker/fqd.container.toml"; do
  "$fqd" --check-config --config "$f"
  n=$((n + 1))
done
((n >= 3)) || { echo "FAIL: expected the ConfigMap's entries and the container config, checked $n" >&2; exit 1; }
echo "deploy: yamllint clean, $n fqd configurations valid"
