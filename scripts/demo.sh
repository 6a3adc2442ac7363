#!/usr/bin/env bash
# The demo: installs what is missing, builds, replays the demo bag (a synthetic scan of the
# procedural body, a garment mesh placed with penetrations, a skirt pattern) through tryon_node with
# auto_fit on, and writes what comes out to a folder: body.obj, garment_resolve.obj,
# garment_drape.obj, the reports (JSON) and result.png.
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: ./demo_output)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
OUT=$(realpath -m "${1:-demo_output}")
"$HERE/setup.sh"
"$HERE/build.sh" >/dev/null
source "$HERE/env.sh"
mkdir -p "$OUT"
rm -f "$OUT"/*.obj "$OUT"/*.json "$OUT"/result.png

# A master of our own on a free port, so that the demo never talks to another ROS system.
PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://localhost:$PORT
export ROS_LOG_DIR="$OUT/ros_log"
roslaunch -p "$PORT" virtual_tryon demo.launch bag:="$WS/devel/share/virtual_tryon/demo.bag" \
  > "$OUT/node.log" 2>&1 &
LAUNCH=$!
trap 'kill -INT $LAUNCH 2>/dev/null; wait $LAUNCH 2>/dev/null || true' EXIT
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done

status=0
/usr/bin/python3 "$HERE/record_fits.py" "$OUT" --timeout 180 || status=$?
echo "demo: node log: $OUT/node.log"
grep -E "tryon_node: (scan meshed|body from|resolve:|drape:)" "$OUT/node.log" | sed 's/^/  /' || true
echo "demo: wrote body.obj, garment_resolve.obj, garment_drape.obj, report_*.json, body_report.json and result.png to $OUT"
exit $status
