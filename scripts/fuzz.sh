#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -fsanitize=fuzzer,address,undefined) in .ws_fuzz/ (ignored
# by git; VT_FUZZ_DIR overrides it) and runs each for SECONDS (default 5) on its seed corpus:
#   fuzz_polygon_mesh  serialized pcl_msgs/PolygonMesh -> fromMsg, validate, validateBody
#   fuzz_point_cloud   serialized sensor_msgs/PointCloud2 -> pointCloudToPoints (normals too)
#   fuzz_mesh_io       OBJ / PLY / STL files -> readMesh, validateBody
#   fuzz_pattern_yaml  pattern YAML -> parsePatternYaml, write and read back, meshPattern
#   fuzz_pattern_garmentcode  GarmentCode JSON -> parseGarmentCodeJson, meshPattern
#   fuzz_point_cache   Point Cache 2 -> parsePointCache, written back to the same bytes
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]   (TARGET without the fuzz_ prefix; default all)
# Each target's corpus grows in .ws_fuzz/corpus/TARGET; crashes, leaks and UB are written to
# .ws_fuzz/artifacts/ and make the script exit non-zero. VT_FUZZ_JOBS (default 1) runs that many
# targets at once.
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/.." && pwd)
SECONDS_EACH=${1:-5}
shift || true
TARGETS=("$@")
if ((${#TARGETS[@]} == 0)); then TARGETS=(polygon_mesh point_cloud mesh_io pattern_yaml pattern_garmentcode point_cache); fi
DIR=${VT_FUZZ_DIR:-$REPO/.ws_fuzz}
BUILD=$DIR/build
JOBS=${VT_FUZZ_JOBS:-1}

"$HERE/setup.sh"
mkdir -p "$BUILD" "$DIR/artifacts"
CC=clang CXX=clang++ cmake -S "$REPO/test/fuzz" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD" -j"${VT_JOBS:-$(nproc)}" -- --no-print-directory >/dev/null

# Seeds: the text ones from the repository, the binary ones made by make_seeds.
SEEDS=$DIR/seeds
rm -rf "$SEEDS"
"$BUILD/make_seeds" "$SEEDS" >/dev/null
mkdir -p "$SEEDS/pattern_yaml" "$SEEDS/pattern_garmentcode" "$SEEDS/point_cache"
cp "$REPO"/test/fuzz/corpus/mesh_io/* "$SEEDS/mesh_io/"
cp "$REPO"/test/fuzz/corpus/pattern_yaml/* "$SEEDS/pattern_yaml/"
cp "$REPO"/test/fuzz/corpus/pattern_garmentcode/* "$SEEDS/pattern_garmentcode/"
cp "$REPO"/test/fuzz/corpus/point_cache/* "$SEEDS/point_cache/"
for f in "$REPO"/config/patterns/*/*.yaml; do
  cp "$f" "$SEEDS/pattern_yaml/$(basename "$(dirname "$f")")_$(basename "$f")"
done

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
run_one() {
  local t=$1
  mkdir -p "$DIR/corpus/$t" "$DIR/artifacts/$t"
  local log=$DIR/fuzz_$t.log
  local status=0
  # -rss_limit_mb: the targets allocate at most a few hundred MB for any accepted input.
  "$BUILD/fuzz_$t" "$DIR/corpus/$t" "$SEEDS/$t" -max_total_time="$SECONDS_EACH" \
    -artifact_prefix="$DIR/artifacts/$t/" -rss_limit_mb=2048 -timeout=25 -max_len=8192 \
    -print_final_stats=1 >"$log" 2>&1 || status=$?
  local execs
  execs=$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  if ((status == 0)); then
    echo "fuzz: $t: ${execs:-?} executions in ${SECONDS_EACH} s, no finding (corpus $(ls "$DIR/corpus/$t" | wc -l) inputs)"
  else
    echo "fuzz: $t: FAILED (exit $status) after ${execs:-?} executions; log $log, artifacts in $DIR/artifacts/$t/"
    grep -m5 -E 'ERROR|SUMMARY|runtime error' "$log" || true
  fi
  return $status
}

status=0
pids=()
names=()
for t in "${TARGETS[@]}"; do
  run_one "$t" &
  pids+=($!)
  names+=("$t")
  if ((${#pids[@]} >= JOBS)); then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
