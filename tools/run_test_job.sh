#!/usr/bin/env bash
# One job of tools/run_tests.sh's lanes: RESULTS_DIR and either test/system (the system tests, pytest), a soak test
# (test/soak/test_NAME.py, pytest) or a rostest file (test/NAME.test). Its output goes to RESULTS_DIR/rostest/NAME.out,
# its JUnit results below RESULTS_DIR (a soak test's in RESULTS_DIR/NAME.xml); prints one line, `ok` or `FAILED`
# with the output's last lines.
set -uo pipefail
results_dir=$1
job=$2
name=$(basename "$(basename "$job" .test)" .py)
out="$results_dir/rostest/$name.out"
if [ "$job" = test/system ]; then
  python3 -m pytest test/system -q -p no:cacheprovider --junitxml="$results_dir/system.xml" > "$out" 2>&1
  status=$?
elif [[ $job == test/soak/* ]]; then
  python3 -m pytest "$job" -q -p no:cacheprovider --junitxml="$results_dir/${name#test_}.xml" > "$out" 2>&1
  status=$?
else
  rostest --results-base-dir "$results_dir/rostest" cssr_system "$name.test" > "$out" 2>&1
  status=$?
fi
if [ "$status" = 0 ]; then
  echo "  $job: ok"
else
  echo "  $job: FAILED (output: $out)"
  tail -n 30 "$out"
fi
