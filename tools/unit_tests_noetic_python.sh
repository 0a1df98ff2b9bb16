#!/usr/bin/env bash
# Runs the unit tests (test/unit) under Python 3.8 with the versions of Ubuntu 20.04 + ROS Noetic, the robot
# laptop's platform: numpy 1.17.4, matplotlib 3.1.2, pytest 4.6.9, hypothesis 5.5.4, PyYAML 5.3.1. Part of
# `make test` and `catkin_make run_tests`; a workspace holding the package must be built and sourced.
#
# The interpreter is `python3.8` on the PATH, or one that pyenv installed. The versions are installed once into
# a virtual environment in the workspace (`venv-noetic`) and reused while its pins are the same. The ROS
# modules come from this workspace (generated messages) and, for the pure-Python ones, from the system's
# dist-packages through a folder of links; the system's compiled modules are for another Python and stay out.
#
# usage: tools/unit_tests_noetic_python.sh RESULT_XML
# Writes a JUnit file; with no Python 3.8 found, one skipped test case that says why, and exits 0.
set -uo pipefail
source "$(dirname "$0")/common.sh"
result_xml=$1

# Ubuntu 20.04's versions, the packages they depend on included, so nothing newer slips in. netifaces is for a running
# node (rospy's connections: `make benchmark PYTHON38=1`), not for the unit tests.
PINS="numpy==1.17.4 matplotlib==3.1.2 kiwisolver==1.1.0 cycler==0.10.0 pyparsing==2.4.6 python-dateutil==2.7.3
six==1.14.0 pytest==4.6.9 attrs==19.3.0 more-itertools==4.2.0 pluggy==0.13.0 py==1.8.1 packaging==20.3 wcwidth==0.1.8
atomicwrites==1.1.5 hypothesis==5.5.4 sortedcontainers==2.1.0 PyYAML==5.3.1 rospkg==1.5.0 catkin_pkg==0.5.2
docutils==0.16 distro==1.4.0 netifaces==0.10.4 Pillow==7.0.0"
# The system's pure-Python ROS modules that the unit tests import, directly or through rospy and actionlib.
ROS_MODULES="rospy rosgraph roslib genpy genmsg actionlib roslaunch rosmaster rosparam rosservice rostest rosunit
rostopic rosnode rosmsg rosclean catkin roscpp"

skip() {
  python3 - "$result_xml" "$1" <<'EOF'
import sys
import xml.etree.ElementTree as ElementTree
path, reason = sys.argv[1], sys.argv[2]
suite = ElementTree.Element("testsuite", name="noetic_python", tests="1", skipped="1")
case = ElementTree.SubElement(suite, "testcase", classname="noetic_python", name="unit_tests_python38")
ElementTree.SubElement(case, "skipped", message=reason)
ElementTree.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
EOF
  echo "unit tests under Python 3.8: skipped: $1"
  exit 0
}

interpreter=$(command -v python3.8 2>/dev/null || true)
if [ -z "$interpreter" ] || ! "$interpreter" -c 'import sys; assert sys.version_info[:2] == (3, 8)' 2>/dev/null; then
  interpreter=$(ls -d "${PYENV_ROOT:-$HOME/.pyenv}"/versions/3.8*/bin/python3.8 2>/dev/null | sort -V | tail -n 1)
fi
[ -n "$interpreter" ] && [ -x "$interpreter" ] ||
  skip "no Python 3.8 interpreter (python3.8 on the PATH, or one installed by pyenv) on this machine"

venv="$WORKSPACE_DIR/venv-noetic"
if [ "$(cat "$venv/pins.txt" 2>/dev/null)" != "$PINS" ]; then
  log_step "installing Noetic's Python versions into $venv ($("$interpreter" --version))"
  rm -rf "$venv"
  "$interpreter" -m venv "$venv" || skip "cannot create a virtual environment with $interpreter"
  # shellcheck disable=SC2086
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check --only-binary=numpy,matplotlib,kiwisolver \
      $PINS || ! "$venv/bin/pip" check > /dev/null; then
    echo "unit tests under Python 3.8: FAILED: cannot install $PINS" >&2
    exit 1
  fi
  printf '%s' "$PINS" > "$venv/pins.txt"
fi

links="$venv/ros-modules"
mkdir -p "$links"
for module in $ROS_MODULES; do
  [ -e "/usr/lib/python3/dist-packages/$module" ] && ln -sfn "/usr/lib/python3/dist-packages/$module" "$links/$module"
done
for message_package in /usr/lib/python3/dist-packages/*_msgs /usr/lib/python3/dist-packages/*_srvs; do
  [ -d "$message_package" ] && ln -sfn "$message_package" "$links/$(basename "$message_package")"
done

log_step "unit tests under Python 3.8 with Noetic's versions ($("$venv/bin/python" --version 2>&1))"
# The sourced workspace's modules (its generated messages; on Noetic also /opt/ros/noetic's) and the links: not
# the whole system dist-packages, whose compiled modules are for the system's Python. PATH keeps pip's
# rosversion out.
cd "$REPO_DIR" && PYTHONPATH="${PYTHONPATH:+$PYTHONPATH:}$links" PATH="/usr/bin:/bin" \
  "$venv/bin/python" -m pytest test/unit -q -p no:cacheprovider --junitxml="$result_xml" \
  -o junit_suite_name=unit_python38
