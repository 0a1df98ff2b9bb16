# The ROS 2 run-time environment of this clone (sourced, not run; bash, safe under `set -u`): the venv and the
# install space that tools/ros2/setup.sh makes in $WORKSPACE_DIR/ros2/<distribution>, and none of ROS 1's
# environment.
#   source tools/ros2/env.sh      # in a shell; WORKSPACE_DIR as tools/common.sh names it, unless already set
#   bash tools/ros2/run.sh CMD... # one command, from any shell (a ROS 1 one included)
# CSSR_ROS2_DISTRO names the distribution: one with its pinned set here, tools/ros2/requirements-<distribution>.txt
# (jazzy, the default, or kilted); each has its own folder, so both can be set up side by side.
# The caller's ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE are kept (a robot on the network needs SUBNET);
# the default range is this machine only. Exports ROS2_VENV and ROS2_INSTALL (the install's programs are in
# $ROS2_INSTALL/lib/cssr_system: there is no `ros2` command here).

if [ -z "${WORKSPACE_DIR:-}" ]; then
  # The one rule of tools/common.sh, read in a subshell; a non-empty ROS_DISTRO keeps it from sourcing ROS 1.
  WORKSPACE_DIR=$(ROS_DISTRO=none bash -c 'source "$1/../common.sh" >/dev/null && printf %s "$WORKSPACE_DIR"' \
    _ "$(dirname "${BASH_SOURCE[0]}")")
fi
export WORKSPACE_DIR
export CSSR_ROS2_DISTRO="${CSSR_ROS2_DISTRO:-jazzy}"
if [ ! -f "$(dirname "${BASH_SOURCE[0]}")/requirements-$CSSR_ROS2_DISTRO.txt" ]; then
  echo "tools/ros2/env.sh: CSSR_ROS2_DISTRO=$CSSR_ROS2_DISTRO: expected one of:" \
    "$(cd "$(dirname "${BASH_SOURCE[0]}")" && ls requirements-*.txt | sed 's/^requirements-//; s/\.txt$//' | xargs)" >&2
  return 1
fi
export ROS2_DIR="$WORKSPACE_DIR/ros2/$CSSR_ROS2_DISTRO"
export ROS2_VENV="$ROS2_DIR/venv"
export ROS2_INSTALL="$ROS2_DIR/install"

# ROS 1's variables (and those of any other ROS sourced before) would mix a second ROS into this one: ROS_* (but
# the two ROS 2 discovery settings), the search paths that its setup.bash extends, and its folders on PATH.
_ros2_env_clean() {
  local name entry path=
  for name in $(compgen -e); do
    case $name in
      ROS_DOMAIN_ID|ROS_AUTOMATIC_DISCOVERY_RANGE|ROS_STATIC_PEERS) ;;
      ROS_*|ROSLISP_*|ROSCONSOLE_*|AMENT_*|COLCON_*|CATKIN_*|PYTHONPATH|PYTHONHOME|CMAKE_PREFIX_PATH|PKG_CONFIG_PATH|\
      LD_LIBRARY_PATH|RMW_IMPLEMENTATION|VIRTUAL_ENV|_ROS_WHEELS_BOOTSTRAP_COMPLETE) unset "$name" ;;
    esac
  done
  local IFS=:
  for entry in $PATH; do
    case $entry in
      /opt/ros/*|"$WORKSPACE_DIR"/devel*|"$WORKSPACE_DIR"/ros2/*/venv/bin|"") ;;
      *) path="${path:+$path:}$entry" ;;
    esac
  done
  PATH=$path
}
_ros2_env_clean
unset -f _ros2_env_clean

# The venv's Python version names the site-packages folder: a glob, not a Python start (see below).
_ros2_site=
_ros2_libs=
for _ros2_dir in "$ROS2_VENV"/lib/python3.*/site-packages "$ROS2_VENV"/lib/python3.*/site-packages/ros_*.libs; do
  [ -d "$_ros2_dir" ] || continue
  case $_ros2_dir in
    *.libs) _ros2_libs="$_ros2_libs:$_ros2_dir" ;;
    *) _ros2_site=${_ros2_dir#"$ROS2_VENV"/} ;;
  esac
done
if [ -z "$_ros2_site" ]; then
  [ -n "${CSSR_ROS2_SETUP:-}" ] || echo "tools/ros2/env.sh: no ROS 2 venv in $ROS2_VENV: run tools/ros2/setup.sh" >&2
  _ros2_site=lib/python3/site-packages
fi

export VIRTUAL_ENV="$ROS2_VENV"
export PATH="$ROS2_VENV/bin:$PATH"
export AMENT_PREFIX_PATH="$ROS2_INSTALL:$ROS2_VENV"
export PYTHONPATH="$ROS2_INSTALL/$_ros2_site"
# The wheels' libraries: our interface packages', the venv's, and those bundled beside the wheels' modules.
export LD_LIBRARY_PATH="$ROS2_INSTALL/lib:$ROS2_VENV/lib$_ros2_libs"
# The wheels start every Python twice (a .pth file re-executes it once to set LD_LIBRARY_PATH, as above) unless
# told it is done: this saves one interpreter start per program.
export _ROS_WHEELS_BOOTSTRAP_COMPLETE=1
export RMW_IMPLEMENTATION=rmw_fastrtps_cpp
# What a ROS 2 setup.bash says, for programs that ask which ROS they run under.
export ROS_VERSION=2 ROS_PYTHON_VERSION=3 ROS_DISTRO="$CSSR_ROS2_DISTRO"
# ROS 2's own default domain (what a simulator or a driver started by hand uses); tests set one of their own.
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-0}"
export ROS_AUTOMATIC_DISCOVERY_RANGE="${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}"
# ROS 2's own log files (rcl's), inside the workspace rather than in ~/.ros.
export ROS_LOG_DIR="$ROS2_DIR/log"
unset _ros2_site _ros2_libs _ros2_dir
