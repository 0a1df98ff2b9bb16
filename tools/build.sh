#!/usr/bin/env bash
# Builds the private catkin workspace of this clone (WORKSPACE_DIR, tools/common.sh) with this
# package (and, where the system has no
# control_msgs, the package's own minimal control_msgs). Run tools/setup.sh first.
set -euo pipefail
source "$(dirname "$0")/common.sh"

mkdir -p "$WORKSPACE_DIR/src"
ln -sfn "$REPO_DIR" "$WORKSPACE_DIR/src/cssr_system"
if /usr/bin/python3 -c 'import control_msgs.msg' 2>/dev/null && [ ! -L "$WORKSPACE_DIR/src/control_msgs" ]; then
  rm -f "$WORKSPACE_DIR/src/control_msgs"
else
  ln -sfn "$REPO_DIR/tools/control_msgs" "$WORKSPACE_DIR/src/control_msgs"
fi
# catkin caches an empty PYTHONPATH on a first configure unless this folder already exists.
mkdir -p "$WORKSPACE_DIR/devel/lib/python3/dist-packages"

log_step "building $WORKSPACE_DIR"
catkin_make -C "$WORKSPACE_DIR" -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
  > "$WORKSPACE_DIR/build.log" 2>&1 || { tail -n 40 "$WORKSPACE_DIR/build.log"; exit 1; }
echo "built; to use it: source $WORKSPACE_DIR/devel/setup.bash"
