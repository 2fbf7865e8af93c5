#!/usr/bin/env bash
# The build stage's last step in both images (Dockerfile: CUDA, Dockerfile.cpu: Debian slim):
# `cmake --install` of BUILD into /opt/fq (tools, the viewer under share/fq/web where fqd finds
# it, the docs), the shared libraries the tools load (found with ldd, so that the runtime stage
# needs no package list of its own: the same -dev packages scripts/setup-deps.sh installs
# provide them), the sample data and the container's fqd configuration.
#   docker/stage.sh BUILD [DEST]    (DEST: /opt/fq; tests/deploy stages into a temporary folder)
set -euo pipefail
build=$1 dest=${2:-/opt/fq}
cmake --install "$build" --prefix "$dest" >/dev/null
rm -rf "$dest/include" "$dest/lib/cmake" "$dest/lib/pkgconfig" "$dest"/lib/*.a "$dest/lib/systemd" "$dest"/lib/python*
mkdir -p "$dest/lib"
# The shared libraries the binaries load, as scripts/stage.sh finds them for a GPU host (the C
# library, the loader and the NVIDIA driver's libraries come from the runtime image and the host).
root=$(cd "$(dirname "$0")/.." && pwd)
libs=$(mktemp -d)
bash "$root/scripts/stage.sh" "$libs" "$dest"/bin/* >/dev/null
mv "$libs"/lib/* "$dest/lib/"
rm -rf "$libs"
cp -r "$root/data" "$dest/data"
cp "$root/docker/fqd.container.toml" "$dest/fqd.container.toml"
