#!/usr/bin/env bash
# `make benchmark`: the node's figures beside their targets and beside a minimal rospy reference node's, on both
# platform interfaces of the simulated Pepper (test/benchmark/benchmark.py). Not part of `make test`.
#   BENCHMARK_CYCLES (enable/disable cycles, default 30), BENCHMARK_CPU_WINDOW (s, default 20),
#   BENCHMARK_EXIT_RUNS (exits per signal, default 3), BENCHMARK_PLATFORMS (default "robot simulator"),
#   BENCHMARK_JSON (default: <workspace>/benchmark.json),
#   BENCHMARK_SOAK (s of soak with short goals, default 0: none) and BENCHMARK_GROWTH_CYCLES (quick enable/disable
#   cycles after it, default 0): on the first platform only.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
json=${BENCHMARK_JSON:-$WORKSPACE_DIR/benchmark.json}
rm -f "$json"
soak=${BENCHMARK_SOAK:-0}
growth=${BENCHMARK_GROWTH_CYCLES:-0}
for platform in ${BENCHMARK_PLATFORMS:-robot simulator}; do
  python3 test/benchmark/benchmark.py --platform "$platform" --cycles "${BENCHMARK_CYCLES:-30}" \
    --cpu-window "${BENCHMARK_CPU_WINDOW:-20}" --exit-runs "${BENCHMARK_EXIT_RUNS:-3}" --soak "$soak" \
    --growth-cycles "$growth" --json "$json"
  soak=0 growth=0
  echo
done
echo "all figures (JSON): $json"
