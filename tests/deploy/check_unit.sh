#!/usr/bin/env bash
# The systemd unit: `systemd-analyze verify` (with ExecStart pointed at the fqd under test, so
# that the binary it names exists) and `systemd-analyze security` at 4.0 or below (the unit
# was 8.3 EXPOSED before it was sandboxed); its LoadCredential= examples verified in force too.
# check_unit.sh UNIT FQD
# Exit 77 (skipped) where systemd-analyze is absent.
set -euo pipefail
unit=$1 fqd=$2
if ! command -v systemd-analyze >/dev/null; then
  echo "SKIP: systemd-analyze is not installed"
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/credentials"
# packaging/fqd.service.in (paths as @VARIABLES@) or an installed unit.
sed -e "s|@FQ_FQD_PATH@|$fqd|g" -e "s|@FQ_DOC_PATH@|/usr/share/doc/fq|g" -e "s|^ExecStart=[^ ]*fqd|ExecStart=$fqd|" \
  "$unit" >"$tmp/fqd.service"
grep -qx 'Type=notify' "$tmp/fqd.service" || { echo "FAIL: the unit is not Type=notify" >&2; exit 1; }
grep -qx 'RestartPreventExitStatus=2' "$tmp/fqd.service" || { echo "FAIL: exit status 2 is restarted" >&2; exit 1; }
for name in http_token curve_key; do
  grep -q "^#LoadCredential=$name:/" "$tmp/fqd.service" ||
    { echo "FAIL: the unit has no LoadCredential= example for $name" >&2; exit 1; }
done
# The unit as written, and with its LoadCredential= examples in force (as an operator enables
# them). verify prints problems and exits 0 for some of them: any output is a failure here.
sed 's/^#LoadCredential=/LoadCredential=/' "$tmp/fqd.service" >"$tmp/credentials/fqd.service"
for u in "$tmp/fqd.service" "$tmp/credentials/fqd.service"; do
  out=$(systemd-analyze verify "$u" 2>&1) || { echo "$out" >&2; exit 1; }
  [[ -z $out ]] || { echo "FAIL: systemd-analyze verify $u: $out" >&2; exit 1; }
done
security=$(systemd-analyze security --offline=true "$tmp/fqd.service" 2>&1)
level=$(sed -n 's/.*Overall exposure level for fqd.service: \([0-9.]*\).*/\1/p' <<<"$security")
[[ -n $level ]] || { echo "$security" >&2; echo "FAIL: no exposure level" >&2; exit 1; }
if awk -v l="$level" 'BEGIN { exit !(l > 4.0) }'; then
  grep '✗' <<<"$security" >&2 || true
  echo "FAIL: systemd-analyze security rates the unit $level, above 4.0" >&2
  exit 1
fi
echo "unit: verify clean (also with its LoadCredential= lines), systemd-analyze security $level (at most 4.0)"
