#!/usr/bin/env bash
# Installs Dolos, the plagiarism detector `raylab similarity` runs, into target/dolos of this
# repository (or the directory given as the first argument): the versions pinned in
# labs/raylab/similarity/package-lock.json, from the npm registry, and the script that calls it.
# Needs Node.js 18 or later and npm, and a C++ compiler, make and Python for the Rust parser
# (node-gyp builds it): apt-get install nodejs npm g++ make python3. Installing again is quick
# when the pinned versions are installed already.
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

mkdir -p "$dest"
if ! cmp -s "$source_dir/package-lock.json" "$dest/package-lock.json" \
    || [ ! -d "$dest/node_modules/@dodona/dolos-lib" ]; then
    cp "$source_dir/package.json" "$source_dir/package-lock.json" "$dest/"
    (cd "$dest" && npm ci --no-audit --no-fund --loglevel=error)
fi
cp "$source_dir/compare.mjs" "$dest/"

# A smoke test: two copies of a Rust function must be found identical.
check="$(mktemp -d)"
trap 'rm -rf "$check"' EXIT
printf 'fn area(w: f64, h: f64) -> f64 {\n    let a = w * h;\n    if a > 0.0 { a } else { -a }\n}\n' >"$check/a.rs"
cp "$check/a.rs" "$check/b.rs"
printf '{"language":"rust","template":null,"files":["%s","%s"]}' "$check/a.rs" "$check/b.rs" >"$check/manifest.json"
answer="$(node "$dest/compare.mjs" "$check/manifest.json" || true)"
if [[ "$answer" != *'"similarity":1'* ]]; then
    echo "error: Dolos was installed in $dest but does not compare Rust files" >&2
    exit 1
fi
echo "Dolos $(node -p "require('$dest/node_modules/@dodona/dolos-lib/package.json').version") installed in $dest"
