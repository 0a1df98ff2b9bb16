#!/usr/bin/env bash
# The demo (`make demo`): installs what is missing, builds the workspace, then runs
# launch/animateBehaviourDemo.launch on a master of its own: the simulated Pepper, animateBehaviour
# (behaviour all), the recorder and the demo's driver, which enables the node for DEMO_DURATION seconds
# with one line a second, then disables it; the launch ends with the driver and the recorder leaves a plot
# of every animated joint and the base heading, and prints its path.
#   make demo                         30 s, the robot's interface of the simulated Pepper (with hands)
#   make demo DURATION=10 PLATFORM=simulator BEHAVIOUR=hands OUTPUT_DIR=/tmp/demo GESTURE=1
#   make demo NODE_ARGS="_gestureDuration:=1.5" SIM_ARGS="_feedback_rate:=20"
#   make demo STYLE=breathing DRIVER=naoqi_dcm   (the breathing style, executed as the robot's driver would)
#   make demo INTERACTION=1           half-way, the engaged preset (intensity 0.5, base still)
#   make demo CONVERSATION=1          a stand-in speech node listens 6 s, then speaks 8 s; the node follows it
#   make demo STYLE=breathing ACTUATION=joint_angles   (streamed to the simulated Pepper run as naoqi_driver)
#   make demo ROBOTS=2                two robots in robot1 and robot2 (launch/animateBehaviourDemoRobots.launch),
#                                     robot2 enabled 5 s after robot1; one plot of both, robots.png
# Environment (what the make variables set): DEMO_DURATION (s, default 30), DEMO_PLATFORM (robot or
# simulator, default robot), DEMO_BEHAVIOUR (default all), DEMO_OUTPUT_DIR (default: the workspace's demo
# folder), DEMO_GESTURE (1: a gesture on the right arm half-way), DEMO_INTERACTION (1: the engaged preset
# half-way), DEMO_CONVERSATION (1: the scripted conversation, mode auto), DEMO_ACTUATION (trajectory or
# joint_angles), DEMO_NODE_ARGS and DEMO_SIM_ARGS (private parameters of the node and of the simulated
# Pepper, `_name:=value` words; the leading `_` may be left out), DEMO_MASTER_URI (default: a master of its own on a free port, so a master you run is
# never touched), DEMO_ROS (2: the demo on ROS 2, tools/demo_ros2.sh), DEMO_ROBOTS (1 or 2).
# Exit status: 0 when the run completed, 1 when something did not start or failed, 130 on Ctrl-C.
#
# roslaunch supervises the processes. One thing is done here by hand: roslaunch stops all nodes at
# once on Ctrl-C, so it could not disable animateBehaviour before stopping it. roslaunch therefore runs
# in a session of its own (Ctrl-C reaches this script only), and on Ctrl-C this script asks the driver to
# stop (`rosnode kill`): the driver disables the node and exits, and the launch ends with it.
set -euo pipefail
case ${DEMO_ROS:-1} in
  1) ;;
  2) exec bash "$(dirname "$0")/demo_ros2.sh" ;;  # `make demo ROS=2`: the same demo on ROS 2
  *) echo "demo: error: ROS=${DEMO_ROS} (expected 1 or 2)" >&2; exit 1 ;;
esac
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"

prepare_workspace

if [ -n "${DEMO_MASTER_URI:-}" ]; then
  export ROS_MASTER_URI=$DEMO_MASTER_URI
else
  free_port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI="http://localhost:$free_port"
fi

# `_name:=value` words; a word `name:=value` gets its `_` (a private parameter, as rosrun takes it).
private_parameters() {
  local word result=()
  for word in $1; do
    case $word in *?:=*) ;; *) echo "demo: error: '$word' in $2 is not _name:=value" >&2; return 1 ;; esac
    case $word in _*) result+=("$word") ;; *) result+=("_$word") ;; esac
  done
  echo "${result[*]:-}"
}
# STYLE and DRIVER are shortcuts for the node's motionStyle and the simulated Pepper's driver model.
[ -z "${DEMO_STYLE:-}" ] || DEMO_NODE_ARGS="${DEMO_NODE_ARGS:-} _motionStyle:=$DEMO_STYLE"
[ -z "${DEMO_DRIVER:-}" ] || DEMO_SIM_ARGS="${DEMO_SIM_ARGS:-} _driver:=$DEMO_DRIVER"
# The launch file reads them from the environment (roslaunch refuses ':=' in an arg's value).
DEMO_NODE_ARGS=$(private_parameters "${DEMO_NODE_ARGS:-}" NODE_ARGS)
DEMO_SIM_ARGS=$(private_parameters "${DEMO_SIM_ARGS:-}" SIM_ARGS)
export DEMO_NODE_ARGS DEMO_SIM_ARGS
# GESTURE=1, INTERACTION=1 and CONVERSATION=1: true or false for the launch.
switch() {
  case $2 in
    1|true|yes) echo true ;;
    0|false|no|"") echo false ;;
    *) echo "demo: error: $1=$2 (expected 1 or 0)" >&2; return 1 ;;
  esac
}
gesture=$(switch GESTURE "${DEMO_GESTURE:-0}")
# ACTUATION=joint_angles: the launch file starts the node with it and the simulated Pepper as naoqi_driver, the
# only driver model that executes /joint_angles.
case ${DEMO_ACTUATION:-}/${DEMO_DRIVER:-naoqi_driver} in
  /*|trajectory/*|joint_angles/naoqi_driver) ;;
  joint_angles/*) echo "demo: error: ACTUATION=joint_angles runs the simulated Pepper as naoqi_driver, not" \
                    "DRIVER=${DEMO_DRIVER}" >&2; exit 1 ;;
  *) echo "demo: error: ACTUATION=${DEMO_ACTUATION} (expected trajectory or joint_angles)" >&2; exit 1 ;;
esac
interaction=$(switch INTERACTION "${DEMO_INTERACTION:-0}")
conversation=$(switch CONVERSATION "${DEMO_CONVERSATION:-0}")
output_dir=$(mkdir -p "${DEMO_OUTPUT_DIR:-$WORKSPACE_DIR/demo}" && cd "${DEMO_OUTPUT_DIR:-$WORKSPACE_DIR/demo}" && pwd)
launch_log="$output_dir/roslaunch.log"
outcome_file="$output_dir/demo_outcome.txt"
rm -f "$outcome_file" "$outcome_file.robot1"
case ${DEMO_ROBOTS:-1} in
  1) launch=(animateBehaviourDemo.launch gesture:="$gesture" interaction:="$interaction" conversation:="$conversation"
             actuation:="${DEMO_ACTUATION:-}" log_file:="$output_dir/animateBehaviourLogFile.log")
     drivers=(/animateBehaviourDemo) ;;
  2) [ "$gesture$interaction$conversation${DEMO_ACTUATION:-}" = falsefalsefalse ] || {
       echo "demo: error: ROBOTS=2 runs the plain demo on each robot (no GESTURE, INTERACTION, CONVERSATION or" \
         "ACTUATION)" >&2
       exit 1; }
     launch=(animateBehaviourDemoRobots.launch)
     drivers=(/robot1/animateBehaviourDemo /robot2/animateBehaviourDemo) ;;
  *) echo "demo: error: ROBOTS=${DEMO_ROBOTS} (expected 1 or 2)" >&2; exit 1 ;;
esac

log_step "demo: animateBehaviour on the simulated Pepper (master $ROS_MASTER_URI; full output: $launch_log)"
# Until the handler below is set, Ctrl-C is ignored here, and the processes started now inherit that:
# the display always shows the end of the run, and roslaunch sets its own handlers.
trap '' INT TERM
: >"$launch_log"  # exists, empty, before the display tails it: the launch appends from its own process
setsid roslaunch cssr_system "${launch[@]}" \
  duration:="${DEMO_DURATION:-30}" platform:="${DEMO_PLATFORM:-robot}" behaviour:="${DEMO_BEHAVIOUR:-all}" \
  output_dir:="$output_dir" outcome_file:="$outcome_file" \
  </dev/null >>"$launch_log" 2>&1 &
launch_pid=$!

# What you see: the lines of the demo's nodes, errors of any node, and roslaunch's own errors.
shown='^([A-Za-z0-9_]+/)*animateBehaviour(Demo|Recorder)|^([A-Za-z0-9_]+ )? *[0-9]+ s  '  # in a namespace: robot1/...
shown+='|^[A-Za-z]+: (error|invalid)|\[(ERROR|FATAL)\]|process has died'
shown+='|RLException|^ERROR|^Invalid|^Resource not found'
(tail -n +1 -s 0.2 -f --pid="$launch_pid" "$launch_log" | grep --line-buffered -E "$shown" || true) &
display_pid=$!

interrupted=0
trap 'interrupted=$((interrupted + 1))' INT TERM
stop_sent=0
while kill -0 "$launch_pid" 2>/dev/null; do
  if [ "$interrupted" -gt "$stop_sent" ]; then
    if [ "$stop_sent" = 0 ]; then
      echo "demo: stopping: the driver disables animateBehaviour first"
      # Before the driver has started, nothing is enabled: roslaunch stops everything.
      rosnode kill "${drivers[@]}" >/dev/null 2>&1 || interrupted=2
    fi
    stop_sent=$interrupted
  fi
  if [ "$stop_sent" -gt 1 ]; then  # a second Ctrl-C, or no driver yet; the node stops the robot itself
    kill -INT "$launch_pid" 2>/dev/null || true  # repeated: roslaunch ignores it until its handler is set
  fi
  sleep 0.2 & wait $! || true
done
wait "$launch_pid" || true
wait "$display_pid" || true
trap - INT TERM

if [ "$interrupted" -gt 0 ]; then
  exit 130
fi
outcomes=("$outcome_file")
[ "${DEMO_ROBOTS:-1}" = 1 ] || outcomes=("$outcome_file.robot1" "$outcome_file")
for outcome in "${outcomes[@]}"; do
  if [ ! -s "$outcome" ]; then
    echo "demo: error: a driver of the demo did not report how the run ended; see $launch_log"
    exit 1
  fi
  read -r status reason < "$outcome"
  if [ "$status" = 130 ]; then  # the driver was stopped, not by Ctrl-C here: a required node of the launch ended
    echo "demo: error: a node of the demo stopped before the end ($reason); see the lines above and $launch_log"
    exit 1
  fi
  [ "$status" = 0 ] || exit "$status"
done
if [ "${DEMO_ROBOTS:-1}" = 2 ]; then  # one plot of both robots on one time axis
  python3 scripts/plotAnimation.py "$output_dir/robot1/animation.json" "$output_dir/robot2/animation.json" \
    -o "$output_dir/robots.png" || exit 1
fi
# Pepper's figure moving as recorded, beside each plot (doc/figure.md).
for recording in "$output_dir"/animation.json "$output_dir"/robot*/animation.json; do
  [ ! -f "$recording" ] || python3 scripts/pepperFigure.py "$recording" -o "${recording%.json}.gif" || exit 1
done
exit 0
