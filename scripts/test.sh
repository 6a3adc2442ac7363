#!/usr/bin/env bash
# Installs what is missing, builds, runs every test (gtest + rostest) and prints the summary.
# Exits non-zero when anything fails.
#
# VT_SANITIZE=1 scripts/test.sh: the same suite with everything of the package (libraries, node,
# CLI, tests) built with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DVIRTUAL_TRYON_SANITIZE=ON) in its own workspace, .ws_asan/ (or $VT_WS). The rostests start
# the node from that workspace, so it runs sanitized too (the executables link the sanitizer
# runtime themselves: no LD_PRELOAD; the Python tools around them are not instrumented).
# ASan and LeakSanitizer reports go to files under .ws_asan/sanitizer_logs/ (also from the node,
# whose exit code rostest does not check); UBSan's go to stderr, so the test output is kept there
# (run_tests.out) and searched. Any report fails the run and is printed. Undefined behaviour
# aborts the process (-fno-sanitize-recover), which also fails its test. Leak suppressions:
# test/sanitizers/lsan.supp.
#
# scripts/test.sh --ci: what CI runs (.ci/run): the suite, then the same suite sanitized, then
# each libFuzzer target for 10 s. Every step runs; it fails if any step failed.
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/.." && pwd)
if [[ ${1:-} == --ci ]]; then
  status=0
  step() {
    local name=$1 t0=$SECONDS
    shift
    echo "==== ci: $name ===="
    if "$@"; then
      echo "==== ci: $name: passed ($((SECONDS - t0)) s) ===="
    else
      echo "==== ci: $name: FAILED ($((SECONDS - t0)) s) ===="
      status=1
    fi
  }
  step "tests" "$HERE/test.sh"
  step "tests under ASan + UBSan" env VT_SANITIZE=1 "$HERE/test.sh"
  step "fuzz targets, 10 s each" "$HERE/fuzz.sh" 10
  exit $status
fi
SANITIZE=${VT_SANITIZE:-0}
if [[ $SANITIZE == 1 ]]; then
  export VT_WS=${VT_WS:-$REPO/.ws_asan}
  CONFIG=(-DVIRTUAL_TRYON_SANITIZE=ON)
else
  CONFIG=(-DVIRTUAL_TRYON_SANITIZE=OFF)
fi
"$HERE/setup.sh"
"$HERE/build.sh" "${CONFIG[@]}"
"$HERE/build.sh" "${CONFIG[@]}" tests
source "$HERE/env.sh"
cd "$WS"
rm -rf "$WS/build/test_results"
if [[ $SANITIZE == 1 ]]; then
  LOGS=$WS/sanitizer_logs
  rm -rf "$LOGS"
  mkdir -p "$LOGS"
  # alloc_dealloc_mismatch=0: FCL and PCL are compiled as C++14, so their Eigen-aligned types
  # (fcl::BVHModel's nodes, ...) are allocated inside those libraries by Eigen's class operator
  # new[] (malloc), while our C++17 translation units, which inline their destructors, release
  # them with the global operator delete[] (Eigen relies on C++17 aligned new there). glibc's
  # operator delete[] is free(), so this is harmless, but ASan reports every such pair, and
  # mismatch reports cannot be suppressed by location. Every other check stays on.
  export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:alloc_dealloc_mismatch=0:check_initialization_order=1:strict_init_order=1:log_path=$LOGS/asan"
  export LSAN_OPTIONS="suppressions=$REPO/test/sanitizers/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$LOGS/ubsan"
  echo "test: sanitized build in $WS; reports go to $LOGS"
fi
status=0
if [[ $SANITIZE == 1 ]]; then
  # UBSan in a combined ASan+UBSan build ignores log_path and prints to stderr: keep the output
  # (the node's too: the launch files use output="screen") and look for reports in it.
  set -o pipefail
  catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 "${CONFIG[@]}" run_tests -j1 2>&1 | tee "$LOGS/run_tests.out" || status=$?
else
  catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 "${CONFIG[@]}" run_tests -j1 || status=$?
fi
echo "==== summary ===="
catkin_test_results --all "$WS/build/test_results" || status=1
if [[ $SANITIZE == 1 ]]; then
  if grep -E -n "runtime error:|ERROR: (AddressSanitizer|LeakSanitizer)" "$LOGS/run_tests.out" >"$LOGS/reports_in_output.txt"; then
    echo "sanitizer reports in the test output:"
    head -n 40 "$LOGS/reports_in_output.txt"
  else
    rm -f "$LOGS/reports_in_output.txt"
  fi
  reports=$(find "$LOGS" -type f ! -name run_tests.out | sort)
  if [[ -n $reports ]]; then
    status=1
    echo "==== sanitizer reports ($(echo "$reports" | wc -l) files in $LOGS) ===="
    for f in $reports; do
      echo "--- $f"
      head -n 60 "$f"
    done
  else
    echo "sanitizers: no report (AddressSanitizer, LeakSanitizer, UndefinedBehaviorSanitizer)"
  fi
fi
# A plain closing line: counts of test cases from the JUnit files.
/usr/bin/python3 - "$WS/build/test_results" <<'PY' || status=1
import sys, pathlib, xml.etree.ElementTree as ET
tests = failures = skipped = 0
files = list(pathlib.Path(sys.argv[1]).rglob("*.xml"))
for f in files:
    try:
        root = ET.parse(f).getroot()
    except ET.ParseError:
        failures += 1
        continue
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    for s in suites:
        tests += int(s.get("tests", 0))
        failures += int(s.get("failures", 0)) + int(s.get("errors", 0))
        skipped += int(s.get("skipped", 0) or s.get("disabled", 0) or 0)
passed = tests - failures - skipped
print(f"tests: {passed} passed, {failures} failed, {skipped} skipped")
sys.exit(1 if failures or tests == 0 else 0)
PY
exit $status
