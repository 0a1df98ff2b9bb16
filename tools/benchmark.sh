#!/usr/bin/env bash
# `make benchmark`: the node's figures beside their targets and beside a minimal rospy reference node's, on both
# platform interfaces of the simulated Pepper (test/benchmark/benchmark.py). Not part of `make test`.
#   BENCHMARK_CYCLES (enable/disable cycles, default 30), BENCHMARK_CPU_WINDOW (s, default 10),
#   BENCHMARK_SOAK (s of soak with short goals, default 0: none), BENCHMARK_GROWTH_CYCLES (quick cycles after it),
#   BENCHMARK_JSON (default: <workspace>/benchmark.json), BENCHMARK_PLATFORMS (default "robot simulator").
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
json=${BENCHMARK_JSON:-$WORKSPACE_DIR/benchmark.json}
rm -f "$json"
for platform in ${BENCHMARK_PLATFORMS:-robot simulator}; do
  python3 test/benchmark/benchmark.py --platform "$platform" --cycles "${BENCHMARK_CYCLES:-30}" \
    --cpu-window "${BENCHMARK_CPU_WINDOW:-10}" --soak "${BENCHMARK_SOAK:-0}" \
    --growth-cycles "${BENCHMARK_GROWTH_CYCLES:-0}" --json "$json"
  echo
done
