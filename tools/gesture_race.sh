#!/usr/bin/env bash
# `make gesture-race`: another node's gestures on every controller, sent at random moments against the node's goals
# (doc/soak.md, "The gesture race"); exit status 0 when every gesture SUCCEEDED, 1 when one did not.
#   RACE_ROS (1 or 2, default 1; 2 exits 3 where no Python suits the ROS 2 wheels), RACE_GESTURES (in all, default
#   100), RACE_STYLE (random or breathing, default random), RACE_SEED (default 1), RACE_FOLDER (the run's files,
#   default <workspace>/gesture-race/rosN-STYLE), RACE_JSON (its result, default <folder>.json), RACE_RESEND (1: a
#   gesture that did not succeed is sent again at once; the exit status then judges the resent ones).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
ros=${RACE_ROS:-1}
style=${RACE_STYLE:-random}
folder=${RACE_FOLDER:-$WORKSPACE_DIR/gesture-race/ros$ros-$style}
json=${RACE_JSON:-$folder.json}
rm -rf "$folder"
mkdir -p "$folder" "$(dirname "$json")"
options=(--gestures "${RACE_GESTURES:-100}" --style "$style" --seed "${RACE_SEED:-1}" --folder "$folder" --json "$json")
if [ "${RACE_RESEND:-0}" = 1 ]; then options+=(--resend); fi
case $ros in
  1) python3 -m cssr_system.ros1.gesture_race "${options[@]}" ;;
  2) setup=0
     bash tools/ros2/setup.sh > "$folder/ros2-setup.out" 2>&1 || setup=$?
     if [ "$setup" = 3 ]; then tail -n 1 "$folder/ros2-setup.out"; exit 3; fi
     if [ "$setup" != 0 ]; then tail -n 20 "$folder/ros2-setup.out"; echo "gesture race: no ROS 2 side"; exit 1; fi
     export ROS_DOMAIN_ID=${RACE_DOMAIN_ID:-$(free_ros2_domain)} ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
     bash tools/ros2/run.sh bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec python3 -m "$@"' \
       "$REPO_DIR/src" cssr_system.ros2.gesture_race "${options[@]}" ;;
  *) echo "gesture race: ROS must be 1 or 2, not $ros" >&2; exit 2 ;;
esac
