#!/usr/bin/env bash
# The Dockerfile's run-time stage installs exactly the Debian packages whose shared libraries the
# binaries and libraries load (ldd, then dpkg -S), leaving out what debian:12-slim already has.
#   check_runtime_packages.sh DOCKERFILE BINARY...
set -euo pipefail
dockerfile=$1
shift
in_base="libc6 libgcc-s1 libstdc++6"

listed=$(sed -n '/^# RUNTIME_PACKAGES/,/^# END RUNTIME_PACKAGES/p' "$dockerfile" |
  grep -v '^#' | tr ' \\' '\n\n' | grep -E '^lib|^zlib' | sort -u)
needed=$(for b in "$@"; do ldd "$b" | awk '/=>/ {print $3}'; done | sort -u |
  while read -r lib; do dpkg -S "$(readlink -f "$lib")" 2>/dev/null || dpkg -S "$lib"; done |
  cut -d: -f1 | sort -u)
needed=$(comm -23 <(echo "$needed") <(tr ' ' '\n' <<<"$in_base" | sort))

missing=$(comm -23 <(echo "$needed") <(echo "$listed"))
extra=$(comm -13 <(echo "$needed") <(echo "$listed"))
echo "needed: $(echo $needed)"
[[ -z "$missing" ]] || { echo "Dockerfile lacks run-time packages: $(echo $missing)" >&2; exit 1; }
[[ -z "$extra" ]] || { echo "Dockerfile installs packages nothing loads: $(echo $extra)" >&2; exit 1; }
echo "Dockerfile run-time packages match the binaries"
