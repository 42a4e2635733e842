#!/usr/bin/env bash
# Install the Debian packages slipstep needs (ci/apt-packages.txt, or the list given as the first
# argument, e.g. ci/apt-bench.txt), only if some are missing.
# A machine that already has all of them never touches apt (a single dpkg-query, ~30 ms).
set -euo pipefail
cd "$(dirname "$0")/.."
list=${1:-ci/apt-packages.txt}

mapfile -t pkgs < <(grep -v '^\s*\(#\|$\)' "$list")

missing=()
for p in "${pkgs[@]}"; do
    status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
    [[ $status == ii* ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
    echo "setup-apt: all ${#pkgs[@]} Debian packages of $list present"
    exit 0
fi

echo "setup-apt: missing: ${missing[*]}"
sudo=()
if ((EUID != 0)); then
    command -v sudo >/dev/null || { echo "setup-apt: not root and no sudo; install as root: apt-get install ${missing[*]}" >&2; exit 1; }
    sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
# Wait (up to 15 min) instead of failing if another apt/dpkg holds the lock.
lock=(-o DPkg::Lock::Timeout=900)
"${sudo[@]}" apt-get "${lock[@]}" update -qq
"${sudo[@]}" apt-get "${lock[@]}" install -y -qq "${pkgs[@]}"
