#!/usr/bin/env bash
# Installs Dolos, the plagiarism detector `raylab similarity` runs, into target/dolos of this
# repository (or the directory given as the first argument): the versions pinned in
# labs/raylab/similarity/package-lock.json, from the npm registry, and the script that calls it.
# Needs Node.js 18 or later and npm, and a C++ compiler, make and Python for the Rust parser
# (node-gyp builds it): apt-get install nodejs npm g++ make python3.
#
# The library is built once per machine, like a package the system installs: its node_modules
# is kept in ${RAYLAB_CACHE:-~/.cache/raylab}/dolos-<hash of the lock file>, and target/dolos
# links to it, so a fresh clone or another checkout with the same pins installs in a second.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
source_dir="$root/labs/raylab/similarity"
dest="${1:-$root/target/dolos}"

for program in node npm; do
    if ! command -v "$program" >/dev/null 2>&1; then
        echo "error: $program is not installed (apt-get install nodejs npm)" >&2
        exit 1
    fi
done

cache="${RAYLAB_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/raylab}"
pins="$(sha256sum "$source_dir/package-lock.json" | cut -c1-16)"
built="$cache/dolos-$pins"
if [ ! -d "$built/node_modules/@dodona/dolos-lib" ]; then
    # Built aside and moved into place whole: an interrupted or concurrent install leaves no
    # half-built library under the name the next install trusts.
    mkdir -p "$cache"
    staging="$(mktemp -d "$cache/dolos-$pins.XXXXXX")"
    cp "$source_dir/package.json" "$source_dir/package-lock.json" "$staging/"
    (cd "$staging" && npm ci --no-audit --no-fund --loglevel=error)
    if ! mv -T "$staging" "$built" 2>/dev/null; then
        rm -rf "$staging"
    fi
fi

mkdir -p "$dest"
cp "$source_dir/package.json" "$source_dir/package-lock.json" "$source_dir/compare.mjs" "$dest/"
if [ "$(readlink "$dest/node_modules" 2>/dev/null)" != "$built/node_modules" ]; then
    rm -rf "$dest/node_modules"
    ln -s "$built/node_modules" "$dest/node_modules"
fi

# A smoke test: two copies of a Rust function must be found identical.
check="$(mktemp -d)"
trap 'rm -rf "$check"' EXIT
printf 'fn area(w: f64, h: f64) -> f64 {\n    let a = w * h;\n    if a > 0.0 { a } else { -a }\n}\n' >"$check/a.rs"
cp "$check/a.rs" "$check/b.rs"
printf '{"language":"rust","template":null,"files":["%s","%s"]}' "$check/a.rs" "$check/b.rs" >"$check/manifest.json"
answer="$(node "$dest/compare.mjs" "$check/manifest.json" || true)"
if [[ "$answer" != *'"similarity":1'* ]]; then
    echo "error: Dolos was installed in $dest but does not compare Rust files (remove $built to build it again)" >&2
    exit 1
fi
echo "Dolos $(node -p "require('$dest/node_modules/@dodona/dolos-lib/package.json').version") installed in $dest (built in $built)"
