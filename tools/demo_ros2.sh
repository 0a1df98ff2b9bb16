#!/usr/bin/env bash
# The demo on ROS 2 (`make demo ROS=2`, or DEMO_ROS=2 in the environment; tools/demo.sh hands over to this
# script): makes the ROS 2 environment (tools/ros2/setup.sh), then runs the simulated Pepper, animateBehaviour,
# the recorder and the demo's driver on ROS 2, on a domain of its own, from this clone's source. The driver enables
# the node for DEMO_DURATION seconds with one line a second, then disables it; the recorder leaves the recording
# and the plot in the output folder and prints their paths, as on ROS 1 (doc/demo.md).
#   make demo ROS=2 DURATION=10 PLATFORM=simulator BEHAVIOUR=hands OUTPUT_DIR=/tmp/demo STYLE=breathing
#   make demo ROS=2 DRIVER=naoqi_dcm INTERACTION=1 NODE_ARGS="gestureDuration:=1.5" SIM_ARGS="feedback_rate:=20"
#   make demo ROS=2 STYLE=breathing ACTUATION=joint_angles
#   make demo ROS=2 CONVERSATION=1   (a stand-in speech node listens 6 s, then speaks 8 s; the node follows it)
# Environment: the DEMO_<option> variables of tools/demo.sh but DEMO_MASTER_URI (no master); NODE_ARGS and
# SIM_ARGS words become ROS 2 parameters (`-p name:=value`).
# DEMO_DOMAIN_ID: the ROS_DOMAIN_ID to use (default: one that no process of this machine uses).
# Exit status: 0 when the run completed, 1 when something did not start or failed, 130 on Ctrl-C.
#
# No ROS 2 launch here (PyPI has none): this script starts the four programs (and the gesture player, the speech
# node), each in a session of its own, so Ctrl-C reaches this script only. On Ctrl-C it sends SIGINT to the driver,
# which disables the node and exits; then SIGINT stops the others (the recorder writes the plot). Each gets one
# SIGINT: Python restores the default action as it exits, so a second one could kill a program that is ending well.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"

STOP_TIMEOUT=30  # s for a program to end after SIGINT (the recorder draws the plot first), then SIGKILL

bash tools/ros2/setup.sh

# `_name:=value` or `name:=value` words, as ROS 2 parameters.
ros2_parameters() {
  local word result=()
  for word in $1; do
    case $word in *?:=*) ;; *) echo "demo: error: '$word' in $2 is not name:=value" >&2; return 1 ;; esac
    result+=(-p "${word#_}")
  done
  echo "${result[*]:-}"
}
case ${DEMO_GESTURE:-0} in
  1|true|yes) gesture=true ;;
  0|false|no) gesture=false ;;
  *) echo "demo: error: GESTURE=${DEMO_GESTURE} (expected 1 or 0)" >&2; exit 1 ;;
esac
case ${DEMO_CONVERSATION:-0} in
  1|true|yes) conversation=true ;;
  0|false|no) conversation=false ;;
  *) echo "demo: error: CONVERSATION=${DEMO_CONVERSATION} (expected 1 or 0)" >&2; exit 1 ;;
esac
case ${DEMO_ROBOTS:-1}/${DEMO_INTERACTION:-0}${DEMO_ACTUATION:-}$gesture$conversation in
  1/*|2/0falsefalse|2/falsefalsefalse|2/nofalsefalse) ;;
  2/*) echo "demo: error: ROBOTS=2 runs the plain demo on each robot (no GESTURE, INTERACTION, CONVERSATION or" \
         "ACTUATION)" >&2
       exit 1 ;;
  *) echo "demo: error: ROBOTS=${DEMO_ROBOTS} (expected 1 or 2)" >&2; exit 1 ;;
esac
case ${DEMO_INTERACTION:-0} in
  1|true|yes) interaction=true ;;
  0|false|no) interaction=false ;;
  *) echo "demo: error: INTERACTION=${DEMO_INTERACTION} (expected 1 or 0)" >&2; exit 1 ;;
esac
platform=${DEMO_PLATFORM:-robot}
node_parameters=(-p "platform:=$platform" -p "behaviour:=${DEMO_BEHAVIOUR:-all}")
# As launch/animateBehaviourDemo.launch sets them, so both ROS judge the goals alike.
sim_parameters=(-p "platform:=$platform" -p velocity_report:=commanded)
[ -z "${DEMO_STYLE:-}" ] || node_parameters+=(-p "motionStyle:=$DEMO_STYLE")
# The stand-in speech node's names (src/cssr_system/demo/speech.py), relative as its own are.
[ "$conversation" = false ] || node_parameters+=(-p mode:=auto -p listeningTopic:=listening -p speakingAction:=tts)
[ -z "${DEMO_DRIVER:-}" ] || sim_parameters+=(-p "driver:=$DEMO_DRIVER")
# ACTUATION=joint_angles: the simulated Pepper runs as naoqi_driver, the only driver model that executes it.
case ${DEMO_ACTUATION:-}/${DEMO_DRIVER:-naoqi_driver} in
  /*|trajectory/*) ;;
  joint_angles/naoqi_driver) node_parameters+=(-p actuation:=joint_angles); sim_parameters+=(-p driver:=naoqi_driver) ;;
  joint_angles/*) echo "demo: error: ACTUATION=joint_angles runs the simulated Pepper as naoqi_driver, not" \
                    "DRIVER=${DEMO_DRIVER}" >&2; exit 1 ;;
  *) echo "demo: error: ACTUATION=${DEMO_ACTUATION} (expected trajectory or joint_angles)" >&2; exit 1 ;;
esac
[ "${DEMO_ACTUATION:-}" != trajectory ] || node_parameters+=(-p actuation:=trajectory)
words=$(ros2_parameters "${DEMO_NODE_ARGS:-}" NODE_ARGS) || exit 1
read -r -a more <<< "$words"
node_parameters+=("${more[@]}")
words=$(ros2_parameters "${DEMO_SIM_ARGS:-}" SIM_ARGS) || exit 1
read -r -a more <<< "$words"
sim_parameters+=("${more[@]}")

output_dir=$(mkdir -p "${DEMO_OUTPUT_DIR:-$WORKSPACE_DIR/demo}" && cd "${DEMO_OUTPUT_DIR:-$WORKSPACE_DIR/demo}" && pwd)
run_log="$output_dir/ros2_demo.log"
outcome_file="$output_dir/demo_outcome.txt"
log_file="$output_dir/animateBehaviourLogFile.log"
rm -f "$outcome_file"

export ROS_DOMAIN_ID=${DEMO_DOMAIN_ID:-$(free_ros2_domain)}
# Whole lines into the shared log: each program flushes its lines itself (unbuffered output would split them).
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST RCUTILS_COLORIZED_OUTPUT=0

# start MODULE ARGUMENT...: python3 -m MODULE in the ROS 2 environment, this clone's source ahead of the install, in
# a session of its own, its output appended to the run's log. The pid ($!) is the program's: every step execs.
# SIGINT back to its default action: bash has background programs ignore it, and a program that has not set its
# handler yet should end on it.
start() {
  setsid env --default-signal=INT bash tools/ros2/run.sh \
    bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec python3 -m "$@"' "$REPO_DIR/src" "$@" \
    </dev/null >>"$run_log" 2>&1 &
}
running() { kill -0 "$1" 2>/dev/null; }
# stop_programs PID...: SIGINT to each, then SIGKILL to those still running after STOP_TIMEOUT s.
stop_programs() {
  local pid alive deadline=$((SECONDS + STOP_TIMEOUT))
  for pid in "$@"; do kill -INT "$pid" 2>/dev/null || true; done
  while :; do
    alive=()
    for pid in "$@"; do running "$pid" && alive+=("$pid"); done
    [ ${#alive[@]} -gt 0 ] || return 0
    if [ "$SECONDS" -ge "$deadline" ]; then
      echo "demo: error: killing what did not end within $STOP_TIMEOUT s of SIGINT (pids ${alive[*]})"
      kill -KILL "${alive[@]}" 2>/dev/null || true
      return 0
    fi
    sleep 0.1
  done
}

interrupted=0
trap 'interrupted=$((interrupted + 1))' INT TERM
log_step "demo: animateBehaviour on the simulated Pepper, ROS 2 (domain $ROS_DOMAIN_ID; full output: $run_log)"
: >"$run_log"
# What you see: the lines of the demo's programs, errors of any, and the last line of a Python traceback (not
# KeyboardInterrupt's: Ctrl-C while a program starts).
shown='^([A-Za-z0-9_]+/)*animateBehaviour(Demo|Recorder)|^([A-Za-z0-9_]+ )? *[0-9]+ s  '  # in a namespace: robot1/...
shown+='|^[A-Za-z]+: (error|invalid|cannot start)|\[(ERROR|FATAL)\]'
shown+='|^[A-Za-z_.]*(Error|Exception)\b'
# The display ignores Ctrl-C, so it shows the run's last lines; it ends when this sleep does.
(trap '' INT TERM; exec sleep infinity) &
display_until=$!
(trap '' INT TERM; tail -n +1 -s 0.2 -f --pid="$display_until" "$run_log" | grep --line-buffered -E "$shown" || true) &
display_pid=$!
end_display() {
  kill -KILL "$display_until" 2>/dev/null || true  # KILL: it ignores INT and TERM
  wait "$display_until" 2>/dev/null || true  # (bash's line about the killed job goes nowhere)
  wait "$display_pid" || true
}

started=()
# Should this script fail half-way, nothing it started outlives it.
trap 'stop_programs "${started[@]}"; end_display' EXIT
[ "$interrupted" = 0 ] || exit 130  # Ctrl-C already: nothing to start
# ROBOTS=2: each robot's four programs in a namespace of their own (robot1, robot2), with the shipped files, its
# recording and log in a folder of its own; robot2 is enabled 5 s after robot1, so robot1 is disabled first.
robots=("")
[ "${DEMO_ROBOTS:-1}" = 1 ] || robots=(robot1 robot2)
sims=() nodes=() recorders=() drivers=() players=()
for index in "${!robots[@]}"; do
  robot=${robots[$index]} namespace=() folder=$output_dir
  if [ -n "$robot" ]; then
    namespace=(-r "__ns:=/$robot") folder="$output_dir/$robot"
    mkdir -p "$folder"
  fi
  start cssr_system.ros2.simulated_pepper_node --ros-args "${namespace[@]}" "${sim_parameters[@]}"
  sims+=($!) started+=($!)
  start cssr_system.ros2.animate_behaviour_main --ros-args "${namespace[@]}" \
    -p "logFile:=$folder/animateBehaviourLogFile.log" "${node_parameters[@]}"
  nodes+=($!) started+=($!)
  start cssr_system.ros2.recorder_node --ros-args "${namespace[@]}" -p "output_dir:=$folder" \
    -p "log_file:=$folder/animateBehaviourLogFile.log" -p "platform:=$platform"
  recorders+=($!) started+=($!)
  if [ "$gesture" = true ]; then  # another node's gesture half-way: not watched, it ends on its own
    start cssr_system.ros2.gesture_player --ros-args "${namespace[@]}" -p "platform:=$platform"
    players+=($!) started+=($!)
  fi
  if [ "$conversation" = true ]; then  # a stand-in speech node: listens, then speaks, when the driver says
    start cssr_system.ros2.speech_player --ros-args "${namespace[@]}"
    players+=($!) started+=($!)
  fi
  start cssr_system.ros2.demo_driver --ros-args "${namespace[@]}" -p "duration:=${DEMO_DURATION:-30}" \
    -p "delay:=$((index * 5)).0" -p "platform:=$platform" -p "interaction:=$interaction" -p "gesture:=$gesture" \
    -p "conversation:=$conversation" \
    -p "log_file:=$folder/animateBehaviourLogFile.log" -p "outcome_file:=$folder/demo_outcome.txt"
  drivers+=($!) started+=($!)
done
any_running() { local pid; for pid in "$@"; do running "$pid" && return 0; done; return 1; }
all_running() { local pid; for pid in "$@"; do running "$pid" || return 1; done; return 0; }

failed=
stop_sent=0
while any_running "${drivers[@]}"; do
  if [ "$interrupted" -gt 1 ]; then  # a second Ctrl-C: no more waiting for the drivers; the nodes stop the robots
    break
  elif [ "$interrupted" = 1 ] && [ "$stop_sent" = 0 ]; then
    echo "demo: stopping: the driver disables animateBehaviour first"
    kill -INT "${drivers[@]}" 2>/dev/null || true
    stop_sent=1
  fi
  if ! all_running "${sims[@]}" "${nodes[@]}"; then
    break
  fi
  sleep 0.1 & wait $! || true
done
# Both run until stopped below: one that has ended failed (a bad parameter, a crash).
all_running "${nodes[@]}" || failed="an animateBehaviour node stopped"
all_running "${sims[@]}" || failed="a simulated Pepper stopped"
stop_programs "${drivers[@]}"
driver_status=0
for pid in "${drivers[@]}"; do
  status=0
  wait "$pid" || status=$?
  [ "$driver_status" != 0 ] || driver_status=$status
done
stop_programs "${recorders[@]}" "${players[@]}" "${nodes[@]}" "${sims[@]}"
recorder_status=0
for pid in "${recorders[@]}"; do wait "$pid" || recorder_status=$?; done
end_display
trap - INT TERM EXIT

if [ "$interrupted" -gt 0 ]; then
  exit 130
fi
if [ -n "$failed" ]; then
  echo "demo: error: $failed before the end; see the lines above and $run_log"
  exit 1
fi
if [ "$driver_status" = 130 ]; then  # stopped, not by Ctrl-C here
  echo "demo: error: the demo's driver was stopped before the end; see $run_log"
  exit 1
fi
if [ "$driver_status" != 0 ]; then
  echo "demo: error: the run did not complete; see the lines above and $run_log"
  exit 1
fi
if [ "$recorder_status" != 0 ]; then
  echo "demo: error: the recorder wrote no plot; see the lines above and $run_log"
  exit 1
fi
if [ "${#robots[@]}" = 2 ]; then  # one plot of both robots on one time axis
  bash tools/ros2/run.sh \
    bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec python3 scripts/plotAnimation.py "$@"' "$REPO_DIR/src" \
    "$output_dir/robot1/animation.json" "$output_dir/robot2/animation.json" -o "$output_dir/robots.png" || exit 1
fi
# Pepper's figure moving as recorded, beside each plot (doc/figure.md).
for recording in "$output_dir"/animation.json "$output_dir"/robot*/animation.json; do
  [ ! -f "$recording" ] || bash tools/ros2/run.sh \
    bash -c 'PYTHONPATH="$0${PYTHONPATH:+:$PYTHONPATH}" exec python3 scripts/pepperFigure.py "$@"' "$REPO_DIR/src" \
    "$recording" -o "${recording%.json}.gif" || exit 1
done
