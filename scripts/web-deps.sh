#!/usr/bin/env bash
# Installs the live viewer's npm packages (three with its Draco decoder, and playwright-core for
# the viewer test) into web/node_modules, exactly as web/package-lock.json pins them.
# Installs Debian's nodejs and npm first when npm is missing. Skips npm when node_modules
# already matches the lock file. fqd runs without any of this; only its viewer page needs it.
# --no-dev leaves out the devDependencies (playwright-core: the viewer test's browser driver),
# for machines that only serve the viewer (scripts/demo.sh, the Docker images).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
web=$root/web
[[ -f $web/package-lock.json ]] || { echo "web-deps: no $web/package-lock.json, nothing to install"; exit 0; }

if ! command -v npm >/dev/null; then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  echo "web-deps: installing Debian's nodejs and npm"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends nodejs npm
fi

stamp=$web/node_modules/.fq-lock.sha256
lock=$(sha256sum "$web/package-lock.json" | cut -d' ' -f1)
# A full install serves --no-dev too; a --no-dev one is redone for a full install.
if [[ -f $stamp ]] && { [[ $(cat "$stamp") == "$lock" ]] || [[ ${1:-} == --no-dev && $(cat "$stamp") == "$lock no-dev" ]]; }; then
  echo "web-deps: web/node_modules matches package-lock.json"
  exit 0
fi
if [[ ${1:-} == --no-dev ]]; then
  (cd "$web" && npm ci --omit=dev --no-audit --no-fund --loglevel=error)
  echo "$lock no-dev" >"$stamp"
else
  (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
  echo "$lock" >"$stamp"
fi
echo "web-deps: installed $(ls "$web/node_modules" | tr '\n' ' ')"
