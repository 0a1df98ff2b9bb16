# Shared settings of the set-up, build, test and demo scripts (sourced, not run).
# Puts the system Python first (a pyenv or virtualenv python3 has no rospy), points ROS at a private
# workspace inside the repository, and sources ROS Noetic where it is installed.

REPO_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WORKSPACE_DIR="$REPO_DIR/.workspace"
RESULTS_DIR="$WORKSPACE_DIR/test_results"
NOETIC_SETUP=/opt/ros/noetic/setup.bash

export PYENV_VERSION=system
export PATH="/usr/bin:/bin:$PATH"
export PYTHONDONTWRITEBYTECODE=1
if [ -f "$NOETIC_SETUP" ] && [ -z "${ROS_DISTRO:-}" ]; then
  set +u
  # shellcheck disable=SC1090
  source "$NOETIC_SETUP"
fi

log_step() { printf '\n==> %s\n' "$*"; }

source_workspace() {
  # ROS's setup scripts read unset variables: source them with -u off.
  local nounset=0
  case $- in *u*) nounset=1; set +u ;; esac
  # shellcheck disable=SC1091
  source "$WORKSPACE_DIR/devel/setup.bash"
  [ "$nounset" = 0 ] || set -u
}
