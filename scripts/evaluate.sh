#!/usr/bin/env bash
# The evaluation report (issue #5): builds, measures, plots. Writes CSV files, PNG plots and
# report.md to OUT_DIR (default ./evaluation) and prints the report's path.
#
# Usage: scripts/evaluate.sh [--quick] [OUT_DIR]
#   --quick   procedural scenes only, small sizes (a few seconds; what the test suite runs)
# The shared meshes are read from $VT_DATA, else ../shared/data next to the repository; when they
# are absent those parts are skipped and the report says so. VT_JOBS limits the build's jobs.
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
QUICK=()
OUT=""
for a in "$@"; do
  case "$a" in
    --quick) QUICK=(--quick) ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    -*) echo "evaluate.sh: unknown option $a" >&2; exit 2 ;;
    *) OUT=$a ;;
  esac
done
OUT=${OUT:-evaluation}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
"$HERE/build.sh" evaluate >/dev/null
source "$HERE/env.sh"
DATA=${VT_DATA:-$REPO/../shared/data}
BIN=$WS/devel/lib/virtual_tryon/evaluate
echo "evaluate.sh: measuring (this takes a few seconds with --quick, several minutes without)" >&2
"$BIN" "${QUICK[@]}" --data "$DATA" --patterns "$REPO/config/patterns" --out "$OUT" >/dev/null
/usr/bin/python3 "$HERE/plot_evaluation.py" "$OUT"
