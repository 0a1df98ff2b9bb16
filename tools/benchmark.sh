#!/usr/bin/env bash
# `make benchmark`: the node's figures beside their targets and beside a minimal rospy reference node's, on both
# platform interfaces of the simulated Pepper (test/benchmark/benchmark.py). Not part of `make test`.
#   BENCHMARK_CYCLES (enable/disable cycles, default 30), BENCHMARK_CPU_WINDOW (s, default 20),
#   BENCHMARK_EXIT_RUNS (exits per signal, default 3), BENCHMARK_PLATFORMS (default "robot simulator"),
#   BENCHMARK_JSON (default: <workspace>/benchmark.json); the table of every platform run goes to
#   doc/benchmark-latest.md (linked from doc/performance.md),
#   BENCHMARK_SOAK (s of soak with short goals, default 0: none) and BENCHMARK_GROWTH_CYCLES (quick enable/disable
#   cycles after it, default 0): on the first platform only. BENCHMARK_PYTHON38=1: the node runs under Python 3.8
#   with Noetic's versions (the environment of tools/unit_tests_noetic_python.sh, which runs first).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
# As on a robot, where Python caches compiled modules beside their sources (Debian's are compiled at install): every
# process here loads them compiled, the node's own (src/, in __pycache__ folders that git ignores) and the workspace's
# messages included. Compiling them at every start would add 2 to 3 MB to each process's memory.
unset PYTHONDONTWRITEBYTECODE
python3 -m compileall -q src test/benchmark "$WORKSPACE_DIR/devel/lib/python3/dist-packages" > /dev/null
json=${BENCHMARK_JSON:-$WORKSPACE_DIR/benchmark.json}
rm -f "$json"
node_python=()
if [ "${BENCHMARK_PYTHON38:-0}" = 1 ]; then  # the node under Python 3.8 with Noetic's versions (make test's venv)
  venv="$WORKSPACE_DIR/venv-noetic"
  # The Python 3.8 unit tests make the environment, or bring it up to its pins (half a minute when it is).
  bash tools/unit_tests_noetic_python.sh "$WORKSPACE_DIR/unit-python38.xml" > /dev/null
  if [ ! -x "$venv/bin/python" ]; then
    echo "benchmark: no Python 3.8 environment (tools/unit_tests_noetic_python.sh could not make one)" >&2
    exit 1
  fi
  export PYTHONPATH="${PYTHONPATH:+$PYTHONPATH:}$venv/ros-modules"
  node_python=(--node-python "$venv/bin/python")
fi
soak=${BENCHMARK_SOAK:-0}
growth=${BENCHMARK_GROWTH_CYCLES:-0}
for platform in ${BENCHMARK_PLATFORMS:-robot simulator}; do
  python3 test/benchmark/benchmark.py --platform "$platform" --cycles "${BENCHMARK_CYCLES:-30}" \
    --cpu-window "${BENCHMARK_CPU_WINDOW:-20}" --exit-runs "${BENCHMARK_EXIT_RUNS:-3}" --soak "$soak" \
    --growth-cycles "$growth" --json "$json" --markdown "$REPO_DIR/doc/benchmark-latest.md" "${node_python[@]}"
  soak=0 growth=0
  echo
done
echo "all figures (JSON): $json"
