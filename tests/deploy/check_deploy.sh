#!/usr/bin/env bash
# Deployment files: yamllint (Debian) on the Kubernetes kustomization and the compose file,
# `fqd --check-config` on every fqd configuration they carry (deploy/k8s/fqd.toml, for every
# pod's shard, and the container's /etc/fq/fqd.toml; their Secrets stood in for by
# stand_in_secrets.sh), check_k8s.py on the kustomization
# (with `kubectl kustomize` where kubectl exists), and check_http_token.py: their HTTP
# listeners need the token, from a Secret.  check_deploy.sh FQD SOURCE_DIR
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
for f in "$src/deploy/k8s/fqd.toml" "$src/docker/fqd.container.toml"; do
  "$fqd" --check-config --config "$(bash "$(dirname "$0")/stand_in_secrets.sh" "$f" "$tmp")"
done
# yamllint depends on python3-yaml, so Debian's python3 can read the manifests.
/usr/bin/python3 "$(dirname "$0")/check_k8s.py" "$fqd" "$src"
/usr/bin/python3 "$(dirname "$0")/check_http_token.py" "$fqd" "$src"
echo "deploy: yamllint clean, fqd configurations valid"
