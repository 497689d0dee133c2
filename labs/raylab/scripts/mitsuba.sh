#!/usr/bin/env bash
# Runs labs/raylab/scripts/mitsuba_cornell.py (the Cornell box in Mitsuba 3, and the comparison
# of images) in a virtual environment of its own, target/mitsuba-venv, made on the first run
# with PyPI's mitsuba (its scalar_rgb variant renders on the CPU) and numpy. Needs python3 with
# the venv module (Debian: python3-venv).
#
#   bash labs/raylab/scripts/mitsuba.sh render --out target/peer --spp 64 --seeds 8
#   bash labs/raylab/scripts/mitsuba.sh compare --a 'target/peer/raylab-*.exr' --b 'target/peer/mitsuba-*.exr'
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
venv="$root/target/mitsuba-venv"
if [[ ! -x "$venv/bin/python" ]] || ! "$venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
    echo "making $venv (mitsuba 3.9.1, numpy)" >&2
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet "mitsuba==3.9.1" numpy >&2
fi
exec "$venv/bin/python" "$root/labs/raylab/scripts/mitsuba_cornell.py" "$@"
