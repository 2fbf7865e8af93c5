#!/usr/bin/env bash
# A deployment's fqd configuration names Secrets mounted only where it runs (/run/secrets/...),
# and `fqd --check-config` reads every file a configuration names. This writes a copy of CONFIG
# into DIR with each such path replaced by a stand-in token in DIR, and prints the copy's path.
#   stand_in_secrets.sh CONFIG DIR
set -euo pipefail
config=$1 dir=$2
printf '%s\n' 0123456789abcdef0123456789abcdef >"$dir/stand_in_token"
copy="$dir/$(basename "$config")"
sed "s#/run/secrets/[^\"]*#$dir/stand_in_token#g" "$config" >"$copy"
echo "$copy"
