#!/usr/bin/env bash
# Installs what cssr_system needs to build, run and test: ROS 1 from the system's packages
# (Debian's own ROS 1, or ros-noetic-* where /opt/ros/noetic exists) and, in a private virtual
# environment, the Python 3.8 compatibility checker. Installs only what is missing.
set -euo pipefail
source "$(dirname "$0")/common.sh"

if [ -f "$NOETIC_SETUP" ]; then
  packages=(
    ros-noetic-ros-base ros-noetic-actionlib ros-noetic-control-msgs ros-noetic-trajectory-msgs
    ros-noetic-geometry-msgs ros-noetic-sensor-msgs ros-noetic-nav-msgs ros-noetic-std-msgs
    ros-noetic-message-generation ros-noetic-message-runtime ros-noetic-rostest
    ros-noetic-roslaunch ros-noetic-rosservice ros-noetic-std-srvs ros-noetic-diagnostic-msgs python3-catkin-lint
    ros-noetic-dynamic-reconfigure
    python3-numpy python3-matplotlib python3-pytest python3-hypothesis python3-venv python3-flake8
  )
else
  packages=(
    ros-core-dev catkin rosbash python3-rospy python3-actionlib python3-actionlib-msgs
    python3-rostest python3-roslaunch python3-rosservice ros-actionlib-msgs
    ros-message-generation ros-message-runtime ros-std-msgs ros-trajectory-msgs ros-geometry-msgs
    ros-sensor-msgs ros-nav-msgs python3-trajectory-msgs python3-geometry-msgs
    python3-sensor-msgs python3-nav-msgs python3-std-msgs python3-std-srvs python3-diagnostic-msgs catkin-lint
    python3-dynamic-reconfigure libdynamic-reconfigure-config-init-mutex-dev
    python3-numpy python3-matplotlib python3-pytest python3-hypothesis python3-venv python3-flake8
  )
fi

install_missing "${packages[@]}"

VERMIN_VERSION=1.9.2
venv="$WORKSPACE_DIR/venv"
if ! "$venv/bin/vermin" --version 2>/dev/null | grep -q "$VERMIN_VERSION"; then
  log_step "installing vermin $VERMIN_VERSION into $venv"
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check "vermin==$VERMIN_VERSION"
fi
