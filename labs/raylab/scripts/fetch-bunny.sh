#!/usr/bin/env bash
# Fetches the Stanford bunny (69 666 triangles, OBJ) that Debian's `glmark2-data` package ships,
# for `raylab bench --mesh`. Needs no root: the package is downloaded with `apt-get download`
# and unpacked with `dpkg-deb -x` (an installed copy under /usr/share/glmark2 is used as is).
# Prints the path of the OBJ file on its last line.
#
#   bash labs/raylab/scripts/fetch-bunny.sh            # -> target/bench-data/bunny.obj
#   bash labs/raylab/scripts/fetch-bunny.sh DIR        # -> DIR/bunny.obj
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
out_dir="${1:-$root/target/bench-data}"
out="$out_dir/bunny.obj"
installed=/usr/share/glmark2/models/bunny.obj
mkdir -p "$out_dir"

if [[ -s "$out" ]]; then
    echo "already there" >&2
elif [[ -s "$installed" ]]; then
    cp "$installed" "$out"
else
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
    if ! (cd "$work" && apt-get download glmark2-data >&2); then
        echo "error: 'apt-get download glmark2-data' failed; run 'apt-get update' (as root) first," \
            "or install the package: apt-get install glmark2-data" >&2
        exit 1
    fi
    dpkg-deb -x "$work"/glmark2-data_*.deb "$work/root"
    cp "$work/root/usr/share/glmark2/models/bunny.obj" "$out"
fi

triangles="$(grep -c '^f ' "$out")"
echo "bunny: $triangles triangles" >&2
echo "$out"
