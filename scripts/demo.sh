#!/usr/bin/env bash
# The demo: installs what is missing, builds, replays the demo bag (a synthetic scan of the
# procedural body, a garment mesh placed with penetrations, a skirt pattern) through tryon_node with
# auto_fit on, and writes what comes out to a folder: body.obj, garment_resolve.obj,
# garment_drape.obj, the reports (JSON), result.png, and the fit maps fit_drape_front/side/back.png
# (the skirt on the node's body, coloured by its springs' strain, rendered by VTK under Xvfb).
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: ./demo_output)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
OUT=$(realpath -m "${1:-demo_output}")
"$HERE/setup.sh"
"$HERE/build.sh" >/dev/null
source "$HERE/env.sh"
mkdir -p "$OUT"
rm -f "$OUT"/*.obj "$OUT"/*.json "$OUT"/*.png

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
# The fit map: the demo's skirt draped again by the tryon command on the body the node meshed
# (the same core, the same defaults), with its pictures.
if [[ -f $OUT/body.obj ]]; then
  "$WS/devel/lib/virtual_tryon/tryon" drape --body "$OUT/body.obj" \
    --pattern "$HERE/../config/patterns/procedural/skirt.yaml" --out "$OUT/garment_drape_cli.obj" \
    --render "$OUT/fit_drape" --title "demo skirt on the meshed scan" >"$OUT/report_drape_cli.json" || status=$?
fi
echo "demo: node log: $OUT/node.log"
grep -E "tryon_node: (scan meshed|body from|resolve:|drape:)" "$OUT/node.log" | sed 's/^/  /' || true
echo "demo: wrote body.obj, garment_resolve.obj, garment_drape.obj, report_*.json, body_report.json, result.png and fit_drape_{front,side,back}.png to $OUT"
exit $status
