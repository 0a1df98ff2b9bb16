#!/usr/bin/env bash
# `make soak`: the node under compressed use on the simulated Pepper, its process sampled every 10 s (doc/soak.md).
# Not part of `make test` (its 3-minute version is: test/soak/). Each figure is printed beside its target; the run's
# JSON goes to <workspace>/soak/soak-rosN.json and the report of both front-ends' latest runs to doc/soak-latest.md
# (the sections of a front-end not run this time are kept).
#   SOAK_DURATION (minutes judged, default 60), SOAK_WARM_UP (minutes before them, not judged, default 10),
#   SOAK_ROS (1 or 2, default 1; 2 exits 3 where no Python suits the ROS 2 wheels),
#   SOAK_SEED (the churn's, default 1), SOAK_RESTART_MINUTES (between restarts of the simulated Pepper, default 10),
#   SOAK_SIM_CLOCK (ROS 1: 1, the default, adds a second robot on a simulated clock from mid-warm-up; 0: none),
#   SOAK_REPORT (default doc/soak-latest.md; "" for none), SOAK_TRACEMALLOC (1: the node's allocations traced, a
#   snapshot every 5 minutes in the run's folder; tools/soak_snapshots.py compares them), SOAK_DOMAIN_ID (ROS 2's;
#   default: one no process of this machine uses), SOAK_FOLDER (the run's files, default <workspace>/soak/rosN),
#   SOAK_JSON (its result, default <workspace>/soak/soak-rosN.json).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
ros=${SOAK_ROS:-1}
export CSSR_TRACEMALLOC=${SOAK_TRACEMALLOC:-0}
results="$WORKSPACE_DIR/soak"
folder=${SOAK_FOLDER:-$results/ros$ros}
json=${SOAK_JSON:-$results/soak-ros$ros.json}
rm -rf "$folder"
mkdir -p "$folder" "$(dirname "$json")"
setup_output="$folder/ros2-setup.out"  # beside the run: the folder exists, also where SOAK_FOLDER puts it elsewhere
options=(--minutes "${SOAK_DURATION:-60}" --warm-up "${SOAK_WARM_UP:-10}" --seed "${SOAK_SEED:-1}"
         --restart-minutes "${SOAK_RESTART_MINUTES:-10}" --sim-clock "${SOAK_SIM_CLOCK:-1}"
         --folder "$folder" --json "$json")
# The ROS 1 run's second robot, on a simulated clock, has its result beside the run's: none left from an earlier run.
[ "$ros" != 1 ] || rm -f "${json%.json}-sim-clock.json"
case $ros in
  1) python3 -m cssr_system.ros1.soak_driver "${options[@]}" ;;
  2) setup=0
     bash tools/ros2/setup.sh > "$setup_output" 2>&1 || setup=$?
     if [ "$setup" = 3 ]; then tail -n 1 "$setup_output"; exit 3; fi  # no Python for the ROS 2 wheels
     if [ "$setup" != 0 ]; then
       tail -n 20 "$setup_output"; echo "soak: the ROS 2 side could not be made"; exit 1
     fi
     export ROS_DOMAIN_ID=${SOAK_DOMAIN_ID:-$(free_ros2_domain)} ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
     bash tools/ros2/run.sh bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec python3 -m "$@"' \
       "$REPO_DIR/src" cssr_system.ros2.soak_driver "${options[@]}" ;;
  *) echo "soak: ROS must be 1 or 2, not $ros" >&2; exit 2 ;;
esac
report=${SOAK_REPORT-doc/soak-latest.md}
if [ -n "$report" ]; then
  python3 -m cssr_system.soak.report --markdown "$report" "$results/soak-ros1.json" \
    "$results/soak-ros1-sim-clock.json" "$results/soak-ros2.json"
fi
