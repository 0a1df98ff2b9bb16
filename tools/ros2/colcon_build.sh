#!/usr/bin/env bash
# Builds the ament packages of ros2/ with colcon, as doc/ros2.md's "Build in a colcon workspace" tells a user
# without a ROS 2 distribution to (the distribution's venv activated, then `colcon build --base-paths
# <repository>/ros2`), in a colcon workspace of its own: $WORKSPACE_DIR/ros2/<distribution>/colcon (build/, install/,
# log/; the distribution: CSSR_ROS2_DISTRO, as for tools/ros2/setup.sh, which must have made the venv first). make
# test runs it, and test/ros2/test_colcon_install_ros2.py starts the node from its install/. tools/ros2/setup.sh's
# cmake builds are not used: the build sees the venv and nothing else, as a user's shell would. colcon builds only
# what changed since its last build here.
#   bash tools/ros2/colcon_build.sh      # prints colcon's output and how long it took
set -euo pipefail
tools_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
source "$tools_dir/../common.sh"  # REPO_DIR, WORKSPACE_DIR, install_missing
export CSSR_ROS2_SETUP=1  # env.sh: no advice to run setup.sh when there is no venv; said below
source "$tools_dir/env.sh"    # ROS2_DIR and ROS2_VENV of the distribution (its variables are dropped below)
[ -f "$ROS2_VENV/bin/activate" ] || { echo "no ROS 2 venv in $ROS2_VENV: run tools/ros2/setup.sh first" >&2; exit 1; }
# colcon's default CMake generator is Unix Makefiles.
install_missing make cmake g++

colcon_dir="$ROS2_DIR/colcon"
mkdir -p "$colcon_dir"
# One build at a time in a workspace (make test's and a test's own): a second one waits, then finds little to do.
exec 9> "$colcon_dir/.lock"
flock 9

started=$SECONDS
# The recipe's lines, from an empty environment (as tools/ros2/run.sh starts one), in the workspace's folder: the
# venv stands in for /opt/ros/<distribution>, whose setup.bash would set the ament prefix and ROS_VERSION.
env -i HOME="$HOME" PATH=/usr/local/bin:/usr/bin:/bin TERM="${TERM:-dumb}" LANG="${LANG:-C.UTF-8}" \
  bash -c 'set -eo pipefail  # not -u: a venv activate and a colcon setup file may read unset variables
    source "$1/bin/activate"
    export AMENT_PREFIX_PATH="$VIRTUAL_ENV" ROS_VERSION=2 ROS_DISTRO="$4"
    cd "$2"
    colcon build --base-paths "$3/ros2"' _ "$ROS2_VENV" "$colcon_dir" "$REPO_DIR" "$CSSR_ROS2_DISTRO"
echo "ROS 2 $CSSR_ROS2_DISTRO: built with colcon in $((SECONDS - started)) s, installed in $colcon_dir/install"
