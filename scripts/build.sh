#!/usr/bin/env bash
# Builds the package in a catkin workspace kept in .ws/ (ignored by git), or in $VT_WS.
# Usage: scripts/build.sh [extra catkin_make arguments]
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WS=${VT_WS:-$REPO/.ws}
mkdir -p "$WS/src"
ln -sfn "$REPO" "$WS/src/virtual_tryon"
cd "$WS"
set +u
source /opt/ros/*/setup.bash 2>/dev/null || true
set -u
JOBS=${VT_JOBS:-$(nproc)}
catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release -j"$JOBS" "$@"
