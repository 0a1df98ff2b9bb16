#!/usr/bin/env bash
# Builds the private catkin workspace of this clone (WORKSPACE_DIR, tools/common.sh) with this
# package (and, where the system has no control_msgs or no naoqi_bridge_msgs, the package's own
# minimal copies of them, in tools/). Run tools/setup.sh first.
set -euo pipefail
source "$(dirname "$0")/common.sh"

mkdir -p "$WORKSPACE_DIR/src"
# Links <target> at <link> unless it is there already. `ln -sfn` replaces a link through a temporary
# link beside it, and a ROS tool searching the workspace at that moment (a rostest while a test runs
# `make demo`) would find the package twice.
link_once() {
  [ "$(readlink "$2" 2>/dev/null)" = "$1" ] || ln -sfn "$1" "$2"
}
link_once "$REPO_DIR" "$WORKSPACE_DIR/src/cssr_system"
# Link tools/<name> into the workspace unless the system has the message package <name> (the link
# itself, once built, makes the import work: a link already there stays).
link_unless_installed() {
  if /usr/bin/python3 -c "import $1.msg" 2>/dev/null && [ ! -L "$WORKSPACE_DIR/src/$1" ]; then
    rm -f "$WORKSPACE_DIR/src/$1"
  else
    link_once "$REPO_DIR/tools/$1" "$WORKSPACE_DIR/src/$1"
  fi
}
link_unless_installed control_msgs
link_unless_installed naoqi_bridge_msgs
# catkin caches an empty PYTHONPATH on a first configure unless this folder already exists.
mkdir -p "$WORKSPACE_DIR/devel/lib/python3/dist-packages"

# One build at a time in a workspace: the test command's soaks and demos each make sure it is built, together, and two
# catkin_make runs in one build folder fail each other. A second one waits, then finds nothing to do.
exec 9> "$WORKSPACE_DIR/.build.lock"
flock 9
log_step "building $WORKSPACE_DIR"
# The end of the log on stderr: callers that keep stdout quiet still say why a build failed.
catkin_make -C "$WORKSPACE_DIR" -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
  > "$WORKSPACE_DIR/build.log" 2>&1 || { tail -n 40 "$WORKSPACE_DIR/build.log" >&2; echo "build failed" >&2; exit 1; }
echo "built; to use it: source $WORKSPACE_DIR/devel/setup.bash"
