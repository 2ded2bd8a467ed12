#!/bin/sh
# Regenerates the golden records tests/golden/<scene>.csv from the dipc program of a build
# (default: build), on 1 rank. Run it when a change is meant to alter the physics or the solver
# path, look at `git diff tests/golden` and say in the commit message why the records moved.
#   tests/golden/update.sh [build-dir] [scene ...]
set -e
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
[ $# -gt 0 ] && shift
dipc="$build/src/app/dipc"
[ -x "$dipc" ] || { echo "update.sh: no dipc program at $dipc (build the dipc target first)" >&2; exit 1; }
scenes=""
for s in "$@"; do scenes="$scenes --scene $s"; done
# Open MPI refuses root and more ranks than cores unless told.
launcher="mpiexec"
if mpiexec --version 2>/dev/null | grep -q "Open MPI\|OpenRTE"; then launcher="mpiexec --oversubscribe --allow-run-as-root"; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$here/golden.py" update --dipc "$dipc" --mpiexec "$launcher" --work "$work" $scenes
