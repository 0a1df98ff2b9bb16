#!/usr/bin/env bash
# `make benchmark`: the node's latency figures (README: "Tests") against the simulated Pepper, on both
# platforms' interfaces. Prints a table per platform; not part of `make test`.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace
for platform in robot simulator; do
  rostest --text "$REPO_DIR/test/benchmark/latency_benchmark.test" platform:="$platform" \
    cycles:="${BENCHMARK_CYCLES:-50}" 2>&1 | sed -n '/latency benchmark/,/^next goal/p'
done
