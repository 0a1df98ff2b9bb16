# Shared settings of the set-up, build, test and demo scripts (sourced, not run).
# Puts the system Python first (a pyenv or virtualenv python3 has no rospy), names the private
# catkin workspace of this clone, and sources ROS Noetic where it is installed.

REPO_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)  # the real path: one workspace per clone, however reached
# The workspace lives outside the package: ROS tools search a package's folder for executables,
# and would find the workspace's build copies (and loop through its link back to the package).
# One workspace per clone, so two clones never share a build.
WORKSPACE_DIR="${CSSR_WORKSPACE:-${XDG_CACHE_HOME:-$HOME/.cache}/cssr_system/workspace-$(printf '%s' "$REPO_DIR" | md5sum | cut -c1-8)}"
RESULTS_DIR="$WORKSPACE_DIR/test_results"
NOETIC_SETUP=/opt/ros/noetic/setup.bash

export PYENV_VERSION=system
export PATH="/usr/bin:/bin:$PATH"
export PYTHONDONTWRITEBYTECODE=1
if [ -f "$NOETIC_SETUP" ] && [ -z "${ROS_DISTRO:-}" ]; then
  case $- in *u*) set +u; source "$NOETIC_SETUP"; set -u ;; *) source "$NOETIC_SETUP" ;; esac
fi

log_step() { printf '\n==> %s\n' "$*"; }

# Installs those of the given Debian packages that are not installed yet (as root, or through sudo).
install_missing() {
  local missing=() package sudo_cmd=()
  for package in "$@"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q 'install ok installed' || missing+=("$package")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  log_step "installing ${missing[*]}"
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

source_workspace() {
  # ROS's setup scripts read unset variables: source them with -u off.
  local nounset=0
  case $- in *u*) nounset=1; set +u ;; esac
  # shellcheck disable=SC1091
  source "$WORKSPACE_DIR/devel/setup.bash"
  [ "$nounset" = 0 ] || set -u
}

# Installs what is missing, builds the workspace, sources it and sets a ROS_HOME inside it: the
# common start of the test, demo and benchmark scripts.
prepare_workspace() {
  bash "$REPO_DIR/tools/setup.sh" || return 1
  bash "$REPO_DIR/tools/build.sh" || return 1
  source_workspace
  export ROS_HOME="$WORKSPACE_DIR/ros_home"
  export ROS_HOSTNAME=${ROS_HOSTNAME:-localhost}
  mkdir -p "$ROS_HOME"
}

# A ROS_DOMAIN_ID that no process of this machine has in its environment (so not another demo's, soak's or test's), of
# 1-101 (0 is ROS 2's default, which a simulator started by hand uses); at random, so two demos starting together
# are unlikely to pick the same.
free_ros2_domain() {
  python3 -c '
import os, random
used = set()
for pid in filter(str.isdigit, os.listdir("/proc")):
    try:
        with open("/proc/%s/environ" % pid, "rb") as environment:
            used.update(entry[14:] for entry in environment.read().split(b"\0") if entry.startswith(b"ROS_DOMAIN_ID="))
    except OSError:
        pass
print(random.choice([domain for domain in range(1, 102) if str(domain).encode() not in used] or [0]))'
}
