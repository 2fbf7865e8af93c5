#!/usr/bin/env bash
# The Docker images without a Docker engine (the development machines have none): each
# Dockerfile is held to scripts/setup-deps.sh and the build, and its staging step runs here.
#   - every COPY source exists; each image installs with `setup-deps.sh --build-only`, builds
#     with -DFQ_BUILD_TESTS=OFF and stages with docker/stage.sh;
#   - --build-only names no package that only tests use;
#   - the CPU image builds on Debian 12 (bookworm), the release setup-deps.sh installs for, and
#     runs on its slim variant; no CUDA image in it;
#   - docker/stage.sh into a temporary folder gives an fqd that runs on the staged libraries
#     alone, validates the container's configuration and has the viewer where fqd looks.
# check_images.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1 build=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
for df in "$src/docker/Dockerfile" "$src/docker/Dockerfile.cpu"; do
  name=${df#"$src/"}
  grep -q 'bash scripts/setup-deps.sh --build-only' "$df" || fail "$name does not install with setup-deps.sh --build-only"
  grep -q -- '-DFQ_BUILD_TESTS=OFF' "$df" || fail "$name builds the tests"
  grep -q 'bash docker/stage.sh /build' "$df" || fail "$name does not stage with docker/stage.sh"
  while read -r from; do
    for f in $from; do [[ $f == . || -e $src/$f ]] || fail "$name copies $f, which does not exist"; done
  done < <(sed -n 's/^COPY \([^-].*\) [^ ]*$/\1/p' "$df")
done
cpu=$src/docker/Dockerfile.cpu
grep -q '^ARG DEBIAN=bookworm$' "$cpu" || fail "Dockerfile.cpu is not on Debian 12 (bookworm)"
grep -q '^FROM debian:${DEBIAN}-slim AS runtime$' "$cpu" || fail "Dockerfile.cpu does not run on debian slim"
! grep -qi 'nvidia\|cuda:' "$cpu" || fail "Dockerfile.cpu names a CUDA image"
grep -q 'Debian 12' "$src/scripts/setup-deps.sh" || fail "setup-deps.sh no longer says it installs for Debian 12"
build_only=$(FQ_SETUP_LIST=1 bash "$src/scripts/setup-deps.sh" --build-only)
for p in chromium clang-14 python3-open3d libgtest-dev yamllint prometheus draco python3-pytest clang-tidy; do
  ! grep -qx "$p" <<<"$build_only" || fail "setup-deps.sh --build-only installs $p, which only tests use"
done

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash "$src/docker/stage.sh" "$build" "$tmp/fq"
[[ -f $tmp/fq/share/fq/web/index.html ]] || fail "the staged image has no viewer"
[[ ! -e $tmp/fq/include ]] || fail "the staged image carries headers"
# Only the staged libraries and the C library: what the runtime image has.
mkdir "$tmp/secrets"
config=$(bash "$(dirname "$0")/stand_in_secrets.sh" "$tmp/fq/fqd.container.toml" "$tmp/secrets")
env -i LD_LIBRARY_PATH="$tmp/fq/lib" "$tmp/fq/bin/fqd" --config "$config" --check-config
missing=$(env -i LD_LIBRARY_PATH="$tmp/fq/lib" ldd "$tmp/fq"/bin/* | grep 'not found' || true)
[[ -z $missing ]] || fail "staged binaries miss libraries: $missing"
echo "images: Dockerfiles consistent with setup-deps.sh --build-only; the staged fqd runs on $(ls "$tmp/fq/lib" | wc -l) staged libraries"
