#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds the workspace and the ROS 2 side, then runs the static
# checks and the unit tests (pytest), then the system tests and the integration tests (rostest) in three lanes
# (tools/run_test_job.sh) and, beside them, the ROS 2 tests (pytest in the ROS 2 environment: every one on Jazzy, the
# node of a colcon build among them, then the harness, successor and demo tests on Kilted), and ends with `N passed,
# N failed`.
# Exits non-zero when any test fails or does not run.
set -uo pipefail
source "$(dirname "$0")/common.sh"
cd "$REPO_DIR"

prepare_workspace || exit 1
rm -rf "$RESULTS_DIR"
mkdir -p "$RESULTS_DIR/rostest"
# The ROS 2 side (Jazzy, the default distribution) is made beside the static checks and the unit tests (mostly
# downloads and one core's builds); Kilted's beside Jazzy's tests in the ROS 2 lane below.
log_step "ROS 2 side: venv and packages (tools/ros2/setup.sh, in the background; output: $RESULTS_DIR/ros2-setup.out)"
bash tools/ros2/setup.sh > "$RESULTS_DIR/ros2-setup.out" 2>&1 &
ros2_setup=$!

log_step "static checks"
python3 tools/check_to_junit.py "$RESULTS_DIR/check-python38.xml" python38_compatibility -- \
  "$WORKSPACE_DIR/venv/bin/vermin" -t=3.8- --violations --no-tips --eval-annotations \
  src scripts test tools
python3 tools/check_to_junit.py "$RESULTS_DIR/check-catkin-lint.xml" catkin_lint_strict -- \
  catkin_lint --strict -W2 --pkg cssr_system
python3 tools/check_to_junit.py "$RESULTS_DIR/check-flake8.xml" flake8 -- \
  python3 -m flake8 src scripts test tools
# No function of the package above cyclomatic complexity 10 (flake8's mccabe check).
python3 tools/check_to_junit.py "$RESULTS_DIR/check-complexity.xml" complexity -- \
  python3 -m flake8 --select C901 --max-complexity 10 src

log_step "wire compatibility: control_msgs checksums (pytest)"
checksums=test/unit/test_control_msgs_checksums.py
python3 -m pytest "$checksums" -v -p no:cacheprovider --junitxml="$RESULTS_DIR/checksums.xml"

log_step "unit tests (pytest)"
python3 -m pytest test/unit -q -p no:cacheprovider --ignore="$checksums" --junitxml="$RESULTS_DIR/unit.xml"

bash tools/unit_tests_noetic_python.sh "$RESULTS_DIR/unit-python38.xml"

log_step "ROS 2 side: waiting for tools/ros2/setup.sh"
wait "$ros2_setup"
ros2_status=$?
if [ "$ros2_status" = 3 ]; then  # no Python the ROS 2 wheels support on this machine: the ROS 2 tests are skipped
  tail -n 1 "$RESULTS_DIR/ros2-setup.out"
elif [ "$ros2_status" != 0 ]; then
  tail -n 40 "$RESULTS_DIR/ros2-setup.out"; echo "the ROS 2 side could not be made"; exit 1
fi

# The node of doc/ros2.md's colcon build: tested in the ROS 2 lane once that build is done, apart from test/ros2's rest.
colcon_test=test/ros2/test_colcon_install_ros2.py
expected=(checksums.xml unit.xml unit-python38.xml system.xml check-python38.xml check-catkin-lint.xml check-flake8.xml
          check-complexity.xml ros2.xml ros2-kilted.xml demo-ros2-kilted.xml)
# The ROS 2 lane: every ROS 2 test on Jazzy; then Kilted's harness and successor tests and, beside them, its demo test
# (on a ROS 2 domain of its own: Jazzy's demo test runs among the system tests). Kilted's set-up and doc/ros2.md's
# colcon build are made beside Jazzy's tests. Output: ros2.out, then ros2-kilted.out.
ros2_lane() {
  local status=0 colcon kilted_setup kilted_demo
  # Niced: the tests time their nodes. The colcon build's output is ros2-colcon.out; the test of the node from that
  # build comes after, and its own call of tools/ros2/colcon_build.sh finds little left to do.
  nice -n 10 bash tools/ros2/colcon_build.sh > "$RESULTS_DIR/ros2-colcon.out" 2>&1 &
  colcon=$!
  CSSR_ROS2_DISTRO=kilted nice -n 10 bash tools/ros2/setup.sh > "$RESULTS_DIR/ros2-kilted-setup.out" 2>&1 &
  kilted_setup=$!
  {
    bash tools/ros2/run.sh python3 -m pytest test/ros2 -q -p no:cacheprovider -W ignore::DeprecationWarning \
      --ignore="$colcon_test" --junitxml="$RESULTS_DIR/ros2.xml" || status=1
    wait "$colcon" || tail -n 40 "$RESULTS_DIR/ros2-colcon.out"
    tail -n 1 "$RESULTS_DIR/ros2-colcon.out"
    bash tools/ros2/run.sh python3 -m pytest "$colcon_test" -q -p no:cacheprovider -W ignore::DeprecationWarning \
      --junitxml="$RESULTS_DIR/ros2-colcon.xml" || status=1
  } > "$RESULTS_DIR/ros2.out" 2>&1
  {
    wait "$kilted_setup" || { tail -n 40 "$RESULTS_DIR/ros2-kilted-setup.out"; exit 1; }
    tail -n 1 "$RESULTS_DIR/ros2-kilted-setup.out"
    # The demo's plain run: the gesture and the conversation are Jazzy's alone (the test command keeps its time).
    CSSR_ROS2_DISTRO=kilted python3 -m pytest test/system/test_demo_ros2.py -q -p no:cacheprovider \
      -k runs_moves_within_the_bands --junitxml="$RESULTS_DIR/demo-ros2-kilted.xml" \
      > "$RESULTS_DIR/demo-ros2-kilted.out" 2>&1 &
    kilted_demo=$!
    CSSR_ROS2_DISTRO=kilted bash tools/ros2/run.sh python3 -m pytest test/ros2/test_harness_ros2.py \
      test/ros2/test_successor_ros2.py -q -p no:cacheprovider -W ignore::DeprecationWarning \
      --junitxml="$RESULTS_DIR/ros2-kilted.xml"
    tests=$?
    wait "$kilted_demo"
    demo=$?
    cat "$RESULTS_DIR/demo-ros2-kilted.out"
    [ "$tests" = 0 ] && [ "$demo" = 0 ]
  } > "$RESULTS_DIR/ros2-kilted.out" 2>&1 || status=1
  return "$status"
}
expected+=(ros2-colcon.xml)
# The ROS 2 tests run beside the rostests (both mostly wait for their nodes), each on a ROS 2 domain of its own.
if [ "$ros2_status" = 0 ]; then
  log_step "ROS 2 tests (beside the rostests; output: $RESULTS_DIR/ros2.out and ros2-kilted.out)"
  ros2_lane &
  ros2_tests=$!
else
  for name in ros2 ros2-colcon ros2-kilted demo-ros2-kilted; do
    python3 tools/check_to_junit.py --skipped "$(tail -n 1 "$RESULTS_DIR/ros2-setup.out")" "$RESULTS_DIR/$name.xml" \
      "${name//-/_}_tests"
  done
  ros2_tests=
fi
rostests=(test/*.test)
for file in "${rostests[@]}"; do
  expected+=("rostest-test_$(basename "$file" .test).xml")
done
# Three lanes, the longest jobs first (most of their time is waiting for nodes), so the rest fill in beside them: the
# system tests, one job (they build in the workspace one after the other; the rostests read nothing that a build
# rewrites), and each rostest with its own master, port and ROS_HOME files.
longest=(test/system test/animate_behaviour_robot.test test/controller_verdicts_12hz.test
         test/controller_verdicts_50hz.test)
# The 3-minute soak of each front-end (test/soak/, doc/soak.md) mostly waits for its nodes, as the ROS 2 lane does: both
# run beside the lanes, not in them; each prints its line once the lanes are done.
soaks=(test/soak/test_soak_ros1.py test/soak/test_soak_ros2.py)
expected+=(soak_ros1.xml soak_ros2.xml)
soak_jobs=()
for job in "${soaks[@]}"; do
  bash tools/run_test_job.sh "$RESULTS_DIR" "$job" > "$RESULTS_DIR/$(basename "$job" .py).line" 2>&1 &
  soak_jobs+=($!)
done
log_step "system tests (pytest) and integration tests (rostest), three at a time; the 3-minute soaks beside them" \
  "(output: $RESULTS_DIR/rostest/)"
{ printf '%s\n' "${longest[@]}"; printf '%s\n' "${rostests[@]}" | grep -vxF -f <(printf '%s\n' "${longest[@]}"); } |
  xargs -P 3 -I{} bash tools/run_test_job.sh "$RESULTS_DIR" {}
wait "${soak_jobs[@]}"
for job in "${soaks[@]}"; do cat "$RESULTS_DIR/$(basename "$job" .py).line"; done

if [ -n "$ros2_tests" ]; then
  if wait "$ros2_tests"; then
    echo "  test/ros2 (Jazzy, a colcon build's node among them; the harness, successor and demo tests on Kilted): ok"
  else
    echo "  test/ros2 (Jazzy, a colcon build's node among them; the harness, successor and demo tests on Kilted):" \
      "FAILED"
    tail -n 40 "$RESULTS_DIR/ros2.out" "$RESULTS_DIR/ros2-kilted.out"
  fi
fi

log_step "summary"
expect_args=()
for name in "${expected[@]}"; do expect_args+=(--expect "$name"); done
python3 tools/summarise_results.py "$RESULTS_DIR" "${expect_args[@]}"
