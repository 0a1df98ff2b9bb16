#!/usr/bin/env bash
# The demo (`make demo`): installs what is missing, builds the workspace, then runs
# scripts/animateBehaviourDemo.py: a private master, the simulated Pepper and animateBehaviour
# (behaviour all), enabled for DEMO_DURATION seconds with one line a second, then disabled; it
# leaves a plot of every animated joint and the base heading and prints its path.
#   make demo                         30 s, the robot's interface of the simulated Pepper (with hands)
#   make demo DURATION=10 PLATFORM=simulator    or: DEMO_DURATION=10 DEMO_PLATFORM=simulator make demo
# Environment: DEMO_DURATION (s, default 30), DEMO_PLATFORM (robot or simulator, default robot),
# DEMO_BEHAVIOUR (default all), DEMO_OUTPUT_DIR (default: the workspace's demo folder), DEMO_MASTER_URI (default: a
# master of its own on a free port, so a master you run is never touched).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"

prepare_workspace

if [ -n "${DEMO_MASTER_URI:-}" ]; then
  export ROS_MASTER_URI=$DEMO_MASTER_URI
else
  free_port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI="http://localhost:$free_port"
fi

log_step "demo: animateBehaviour on the simulated Pepper"
# exec: Ctrl-C and the exit status belong to the demo itself, which stops everything it started.
exec python3 "$REPO_DIR/scripts/animateBehaviourDemo.py" \
  --duration "${DEMO_DURATION:-30}" \
  --platform "${DEMO_PLATFORM:-robot}" \
  --behaviour "${DEMO_BEHAVIOUR:-all}" \
  --output-dir "${DEMO_OUTPUT_DIR:-$WORKSPACE_DIR/demo}"
