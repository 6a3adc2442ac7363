#!/usr/bin/env bash
# Installs what is missing, builds, runs every test (gtest + rostest) and prints the summary.
# Exits non-zero when anything fails.
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
"$HERE/setup.sh"
"$HERE/build.sh"
"$HERE/build.sh" tests
source "$HERE/env.sh"
cd "$WS"
rm -rf "$WS/build/test_results"
status=0
catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 run_tests -j1 || status=$?
echo "==== summary ===="
catkin_test_results --all "$WS/build/test_results" || status=1
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
