#!/usr/bin/env bash
# `make motion-report`: figures of each motion style, on the ideal controller, on the model of the robot's driver
# and on naoqi_driver fed by the joint_angles actuation, from a computed 60 s run at the shipped configuration
# (behaviour body, robot). Options: MOTION_REPORT_ARGS, e.g. "--seconds 120 --seed 3 --config my.ini".
# See src/cssr_system/motion/report.py.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"
prepare_workspace > /dev/null
# shellcheck disable=SC2086
python3 -c 'import sys; from cssr_system.motion.report import main; sys.exit(main(sys.argv[1:]))' \
  ${MOTION_REPORT_ARGS:-}
