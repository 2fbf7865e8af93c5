#!/usr/bin/env bash
# Copies built executables and the shared libraries they load into one folder, for a GPU host
# that has the NVIDIA driver but none of the -dev packages the build used:
#   scripts/stage.sh STAGE BINARY [BINARY...]
# gives STAGE/bin/, STAGE/lib/ and STAGE/run; on the host: STAGE/run <binary> [args...].
# The C library, the loader and the CUDA driver stay the host's own.
set -euo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 STAGE BINARY [BINARY...]" >&2; exit 2; }
stage=$1
shift
mkdir -p "$stage/bin" "$stage/lib"
for exe in "$@"; do
  [[ -x $exe ]] || { echo "stage: not an executable: $exe" >&2; exit 2; }
  cp -L "$exe" "$stage/bin/"
  ldd "$exe" | awk '$2 == "=>" && $3 ~ /^\// {print $3}' |
    grep -vE '/(libc|libm|libdl|librt|libpthread|libcuda|libnvidia-[^/]*)\.so' |
    while read -r lib; do cp -Lu "$lib" "$stage/lib/"; done
done
cat >"$stage/run" <<'RUN'
#!/usr/bin/env bash
here=$(cd "$(dirname "$0")" && pwd)
exe=$1
shift
LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" exec "$here/bin/$exe" "$@"
RUN
chmod +x "$stage/run"
echo "stage: $(du -sh "$stage" | cut -f1) in $stage"
