#!/usr/bin/env bash
# Runs tryon_node under load for longer than the test suite does: CLIENTS clients call
# ~resolve_penetration and ~drape at once while bodies and garments stream at 10 Hz, every answer
# checked; prints throughput, latency and the node's memory after warm-up and at the end.
# Usage: scripts/load_test.sh [SECONDS] [CLIENTS]   (default 60 s, 3 clients)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SECONDS_RUN=${1:-60}
CLIENTS=${2:-3}
"$HERE/setup.sh" >/dev/null
"$HERE/build.sh" tests >/dev/null
source "$HERE/env.sh"
PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://localhost:$PORT
roscore -p "$PORT" >/dev/null 2>&1 &
CORE=$!
trap 'kill $NODE $CORE 2>/dev/null || true; wait 2>/dev/null || true' EXIT
NODE=
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
roslaunch virtual_tryon tryon.launch >/dev/null 2>&1 &
NODE=$!
"$WS/devel/lib/virtual_tryon/load_test" _duration:="$SECONDS_RUN" _clients:="$CLIENTS" \
  _max_rss_growth_mb:=64 | grep -E "^load:|OK|FAILED|Failure|Expected|actual"
