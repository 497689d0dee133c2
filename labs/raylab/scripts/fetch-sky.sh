#!/usr/bin/env bash
# Fetches one of the CC0 latitude–longitude skies of Debian's `blender-data` package (city,
# sunset, sunrise, courtyard, forest, night, studio, interior) and rewrites it in half floats
# with ZIP compression, which raylab reads (Blender ships them DWAB-compressed in 32-bit
# floats). Needs no root: the
# package is downloaded with `apt-get download`, unpacked with `dpkg-deb -x`, and converted by
# the OpenEXR library from PyPI in a virtual environment under target/. Prints the path of the
# EXR file on its last line. labs/lab12/probes/README.md says where lab 12's sky comes from.
#
#   bash labs/raylab/scripts/fetch-sky.sh city           # -> target/probes/city.exr
#   bash labs/raylab/scripts/fetch-sky.sh forest DIR     # -> DIR/forest.exr
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
name="${1:?usage: fetch-sky.sh NAME [DIR]}"
out_dir="${2:-$root/target/probes}"
out="$out_dir/$name.exr"
venv="$root/target/probe-venv"
mkdir -p "$out_dir"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
if ! (cd "$work" && apt-get download blender-data >&2); then
    echo "error: 'apt-get download blender-data' failed; run 'apt-get update' (as root) first" >&2
    exit 1
fi
dpkg-deb -x "$work"/blender-data_*.deb "$work/root"
source="$work/root/usr/share/blender/datafiles/studiolights/world/$name.exr"
if [[ ! -s "$source" ]]; then
    echo "error: blender-data has no sky '$name'; it has:" \
        "$(ls "$work/root/usr/share/blender/datafiles/studiolights/world" | sed 's/\.exr$//' | tr '\n' ' ')" >&2
    exit 1
fi
if [[ ! -x "$venv/bin/python" ]]; then
    python3 -m venv "$venv" >&2
    "$venv/bin/pip" install --quiet 'OpenEXR==3.5.*' 'numpy<3' >&2
fi
"$venv/bin/python" - "$source" "$out" <<'PY'
import sys
import OpenEXR

source, out = sys.argv[1], sys.argv[2]
with OpenEXR.File(source) as f:
    channels = {name: c.pixels.astype("float16") for name, c in f.channels().items()}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, channels).write(out)
PY
echo "$name: $(sha256sum "$source" | cut -d' ' -f1) (blender-data), written as half floats with ZIP compression" >&2
echo "$out"
