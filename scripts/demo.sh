#!/usr/bin/env bash
# Installs what is missing, builds, and runs the resolver on the built-in procedural scene.
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: ./demo_output)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
OUT=$(realpath -m "${1:-demo_output}")
"$HERE/setup.sh"
"$HERE/build.sh" >/dev/null
source "$HERE/env.sh"
mkdir -p "$OUT"
status=0
"$WS/devel/lib/virtual_tryon/tryon" demo --out "$OUT" > "$OUT/summary.json" || status=$?
echo "demo: resolver report:"
cat "$OUT/summary.json"
echo "demo: wrote body.obj, garment_in.obj, garment_out.obj and report.json to $OUT"
exit $status
