#!/usr/bin/env bash
# `make benchmark`: the node's figures beside their targets and beside a minimal reference node's, on both platform
# interfaces of the simulated Pepper: ROS 1 (test/benchmark/benchmark.py, a rospy reference) or, with
# BENCHMARK_ROS=2, ROS 2 (test/benchmark/benchmark_ros2.py, an rclpy reference, in the environment of
# tools/ros2/setup.sh on a ROS_DOMAIN_ID of its own: BENCHMARK_DOMAIN_ID, else one no process here uses). Not part of
# `make test`.
#   BENCHMARK_CYCLES (enable/disable cycles, default 30), BENCHMARK_CPU_WINDOW (s, default 20),
#   BENCHMARK_EXIT_RUNS (exits per signal, default 3), BENCHMARK_PLATFORMS (default "robot simulator"),
#   BENCHMARK_JSON (default: <workspace>/benchmark.json, <workspace>/benchmark-ros2.json for ROS 2); the table of
#   every platform run goes to the front-end's section of doc/benchmark-latest.md (linked from doc/performance.md),
#   BENCHMARK_SOAK (s of soak with short goals, default 0: none) and BENCHMARK_GROWTH_CYCLES (quick enable/disable
#   cycles after it, default 0): on the first platform only. BENCHMARK_PYTHON38=1 (ROS 1 only): the node runs under
#   Python 3.8 with Noetic's versions (the environment of tools/unit_tests_noetic_python.sh, which runs first).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
# As on a robot, where Python caches compiled modules beside their sources (Debian's are compiled at install): every
# process here loads them compiled, the node's own (src/, in __pycache__ folders that git ignores) and the workspace's
# messages included. Compiling them at every start would add 2 to 3 MB to each process's memory.
unset PYTHONDONTWRITEBYTECODE
ros=${BENCHMARK_ROS:-1}
soak=${BENCHMARK_SOAK:-0}
growth=${BENCHMARK_GROWTH_CYCLES:-0}
options() {  # the options of one platform's run
  echo --platform "$1" --cycles "${BENCHMARK_CYCLES:-30}" --cpu-window "${BENCHMARK_CPU_WINDOW:-20}" \
    --exit-runs "${BENCHMARK_EXIT_RUNS:-3}" --soak "$soak" --growth-cycles "$growth"
}
case $ros in
  1) ;;
  2) [ "${BENCHMARK_PYTHON38:-0}" = 0 ] || { echo "benchmark: PYTHON38=1 is for ROS 1 only" >&2; exit 2; }
     setup_output="$WORKSPACE_DIR/benchmark-ros2-setup.out"
     setup=0
     bash tools/ros2/setup.sh > "$setup_output" 2>&1 || setup=$?
     if [ "$setup" = 3 ]; then tail -n 1 "$setup_output"; exit 3; fi  # no Python for the ROS 2 wheels
     if [ "$setup" != 0 ]; then
       tail -n 20 "$setup_output"; echo "benchmark: the ROS 2 side could not be made"; exit 1
     fi
     export ROS_DOMAIN_ID=${BENCHMARK_DOMAIN_ID:-$(free_ros2_domain)} ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
     # The node, the reference and the simulated Pepper run from this clone's source, compiled, in ROS 2's Python.
     in_ros2() {
       bash tools/ros2/run.sh bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec "$@"' "$REPO_DIR/src" "$@"
     }
     in_ros2 python3 -m compileall -q src test/benchmark > /dev/null
     json=${BENCHMARK_JSON:-$WORKSPACE_DIR/benchmark-ros2.json}
     rm -f "$json"
     for platform in ${BENCHMARK_PLATFORMS:-robot simulator}; do
       read -r -a words <<< "$(options "$platform")"
       in_ros2 python3 test/benchmark/benchmark_ros2.py "${words[@]}" --json "$json" \
         --markdown "$REPO_DIR/doc/benchmark-latest.md"
       soak=0 growth=0
       echo
     done
     echo "all figures (JSON): $json"
     exit 0 ;;
  *) echo "benchmark: ROS must be 1 or 2, not $ros" >&2; exit 2 ;;
esac
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
for platform in ${BENCHMARK_PLATFORMS:-robot simulator}; do
  read -r -a words <<< "$(options "$platform")"
  python3 test/benchmark/benchmark.py "${words[@]}" --json "$json" --markdown "$REPO_DIR/doc/benchmark-latest.md" \
    "${node_python[@]}"
  soak=0 growth=0
  echo
done
echo "all figures (JSON): $json"
