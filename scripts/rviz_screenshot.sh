#!/usr/bin/env bash
# Replays the demo bag with rviz (config/tryon.rviz) on a virtual X server and saves a screenshot
# of the screen once both fits have arrived: what `roslaunch virtual_tryon demo.launch rviz:=true`
# shows, taken headless. Needs the Debian packages rviz, xvfb and imagemagick (setup.sh installs
# the first two; `import` is ImageMagick's).
# Usage: scripts/rviz_screenshot.sh [OUT.png]   (default: doc/results/rviz_demo.png)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
OUT=$(realpath -m "${1:-$HERE/../doc/results/rviz_demo.png}")
source "$HERE/env.sh"
for tool in rviz Xvfb import; do
  command -v "$tool" >/dev/null || { echo "rviz_screenshot: $tool is not installed" >&2; exit 2; }
done
TMP=$(mktemp -d)
PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://localhost:$PORT
export ROS_LOG_DIR="$TMP/ros_log"
DISPLAY_NUMBER=$((90 + RANDOM % 100))
Xvfb ":$DISPLAY_NUMBER" -screen 0 1400x900x24 >"$TMP/xvfb.log" 2>&1 &
XVFB=$!
export DISPLAY=":$DISPLAY_NUMBER"
roslaunch -p "$PORT" virtual_tryon demo.launch rviz:=true bag:="$WS/devel/share/virtual_tryon/demo.bag" \
  >"$TMP/launch.log" 2>&1 &
LAUNCH=$!
trap 'kill -INT $LAUNCH 2>/dev/null; wait $LAUNCH 2>/dev/null || true; kill $XVFB 2>/dev/null || true; rm -rf "$TMP"' EXIT
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.2; done
/usr/bin/python3 "$HERE/record_fits.py" "$TMP/fits" --timeout 240 >/dev/null
sleep 5  # rviz draws the latched markers
import -display "$DISPLAY" -window root "$OUT"
echo "rviz_screenshot: wrote $OUT"
