"""The test harness on ROS 2 (cssr_system.ros2.harness_runner): the ROS 1 harness's checks, from the same ROS-free
code (cssr_system.harness), judge the ROS 2 node (cssr_system.ros2.animate_behaviour_main) beside
the ROS 2 simulated Pepper, each in a process of its own: the random style with the leg's chunk pattern, the
breathing style, and the joint_angles actuation. A smoothness figure of motion/report.py, computed on the recorded
/joint_states, is bounded by the same figure of the node's own plan.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
Skipped where rclpy or the interface packages cannot be imported (ROS 1). The processes run on ROS_DOMAIN_IDs of
this test's own, discovered on this machine only, so parallel runs do not meet.
"""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy
import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")
# The simulated Pepper publishes odometry and the harness records it.
pytest.importorskip("nav_msgs.msg", reason="nav_msgs (PyPI: ros-nav-msgs) is not installed in the ROS 2 venv")

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.event_log import read_log  # noqa: E402
from cssr_system.harness import checks, oracle, report, settings  # noqa: E402
from cssr_system.harness.session import HarnessError  # noqa: E402
from cssr_system.motion import report as motion_report  # noqa: E402
from cssr_system.package_files import data_dir  # noqa: E402
from cssr_system.ros2.harness_runner import Ros2Harness  # noqa: E402

from domains import claim_domain  # noqa: E402

SRC = Path(__file__).resolve().parents[2] / "src"
CONFIGURATION = Path(__file__).resolve().parents[1] / "harnessTestConfiguration.ini"  # the rostests' one
# Two runs, one after the other, each on a domain of its own.
DOMAINS = (claim_domain(), claim_domain())
EXIT_TIMEOUT = 15.0
READY_TIMEOUT = 30.0  # s for the node to find the simulated Pepper's controllers and topics (ROS 2 discovery)
SIMULATOR_PARTS = {"RArm", "LArm", "Leg", "Wheels"}  # the simulator platform has no hand controllers
ROBOT_PARTS = SIMULATOR_PARTS | {"RHand", "LHand"}
# The recorded motion may be this much rougher than the plan's (rms jerk, rad/s^3): the node's random positions are
# not the plan's, and resampling the recorded samples onto motion.report's even grid adds a little.
JERK_FACTOR = 3.0
JERK_FLOOR = 2.0
# As the ROS 1 harness tests run it: /joint_states reports the controllers' desired state at its stamp. Otherwise
# it reports the last control update's (up to a control period earlier than the stamp), which figures of the
# motion computed at the stamps read as jerk.
SIMULATOR = ("velocity_report:=commanded",)
SEED = 1


def start(module: str, domain: int, output: Path, *parameters: str) -> subprocess.Popen:
    environment = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                       PYTHONUNBUFFERED="1")
    # The working tree's package, ahead of any installed copy.
    environment["PYTHONPATH"] = os.pathsep.join(filter(None, (str(SRC), os.environ.get("PYTHONPATH"))))
    command = [sys.executable, "-m", module, "--ros-args"]
    for parameter in parameters:
        command += ["-p", parameter]
    with open(output, "w") as stream:  # a file, not a pipe: nobody reads the output while the node runs
        return subprocess.Popen(command, env=environment, stdout=stream, stderr=subprocess.STDOUT,
                                start_new_session=True)


def stop(process: subprocess.Popen):
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        return process.wait(EXIT_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        return process.wait()


class Robot:
    """The simulated Pepper and the node on one domain; a harness per harness configuration."""

    def __init__(self, folder: Path, domain: int, simulator: tuple, node: tuple, parts: set) -> None:
        self.folder, self.domain = folder, domain
        self.log_file = folder / "animateBehaviour.log"
        self.outputs = (folder / "simulated_pepper.out", folder / "animate_behaviour.out")
        self.processes = [start("cssr_system.ros2.simulated_pepper_node", domain, self.outputs[0], *simulator),
                          start("cssr_system.ros2.animate_behaviour_main", domain, self.outputs[1],
                                "logFile:=%s" % self.log_file, *node)]
        self.wait_until_connected(parts)

    def wait_until_connected(self, parts: set) -> None:
        """Until the node has found the simulated Pepper behind every part and the base topic, before any harness
        runs: discovery may take seconds, and the harness's own subscription to the base topic must not be what
        the node finds there."""
        deadline = time.monotonic() + READY_TIMEOUT
        while self.connected_parts() < parts:
            if time.monotonic() > deadline:
                self.close()
                pytest.fail("the node found only {} of {} in {:g} s\n{}".format(
                    sorted(self.connected_parts()), sorted(parts), READY_TIMEOUT, self.output()))
            time.sleep(0.05)

    def connected_parts(self) -> set:
        if not self.log_file.exists():
            return set()
        return {entry.fields["part"] for entry in read_log(str(self.log_file))
                if entry.event == contract.CONTROLLER_CONNECTED}

    def run(self, test: str, harness_class=Ros2Harness, **overrides):
        """(the harness's outcome of `test`, its harness configuration, the harness) with `overrides` of the
        rostests' harness configuration; one round, appended to report.dat in the run's folder."""
        config = settings.load_harness_configuration(str(CONFIGURATION), dict(overrides, tests=test), data_dir())
        harness = harness_class(config, str(self.folder / "node.ini"), str(self.log_file),
                                report_file=str(self.folder / "report.dat"), domain_id=self.domain)
        try:
            harness.connect()
            [outcome] = harness.run_rounds()
            return outcome, config, harness
        except HarnessError as error:  # e.g. a node that stopped answering: what it said is the evidence
            pytest.fail("{}\n{}".format(error, self.output()))
        finally:
            harness.close()

    def output(self) -> str:
        return "\n".join("== {}\n{}".format(path.name, path.read_text()[-3000:]) for path in self.outputs)

    def close(self) -> list:
        return [stop(process) for process in reversed(self.processes)]


@pytest.fixture(scope="module")
def simulator(tmp_path_factory):
    robot = Robot(tmp_path_factory.mktemp("simulator"), DOMAINS[0], ("platform:=simulator",) + SIMULATOR,
                  ("platform:=simulator",), SIMULATOR_PARTS)
    yield robot
    assert robot.close() == [0, 0], robot.output()


def assert_passed(outcome: checks.HarnessOutcome, robot: Robot) -> None:
    assert outcome.passed, "\n".join((checks.failure_message(outcome), report.format_test(outcome), robot.output()))


def resampled(joints, names, start: float, end: float, rate: float):
    """(times, positions (times x names)) of the observed joints on an even grid of `rate` Hz from `start` to
    `end`: the evenly spaced samples that motion.report's figures take. Cubic between samples (through the two
    either side), so that an uneven or a missing sample does not show up as a jerk, as it would with straight
    lines; straight lines with fewer than four samples."""
    ordered = []
    for sample in joints:
        if not ordered or sample.time > ordered[-1].time:  # the weights below divide by time differences
            ordered.append(sample)
    times = numpy.arange(start, end, 1.0 / rate)
    stamps = numpy.array([sample.time for sample in ordered])
    values = numpy.array([[sample.positions.get(name, numpy.nan) for name in names] for sample in ordered],
                         dtype=float).reshape(len(ordered), len(names))
    if len(ordered) < 4:
        columns = [numpy.interp(times, stamps, values[:, column]) for column in range(len(names))]
        return times, numpy.array(columns, dtype=float).T.reshape(len(times), len(names))
    first = numpy.clip(numpy.searchsorted(stamps, times) - 2, 0, len(ordered) - 4)
    around = first[:, None] + numpy.arange(4)  # the four samples around each time
    knots = stamps[around]
    weights = numpy.ones(around.shape)  # Lagrange's
    for one in range(4):
        for other in range(4):
            if one != other:
                weights[:, one] *= (times - knots[:, other]) / (knots[:, one] - knots[:, other])
    return times, numpy.einsum("tk,tkj->tj", weights, values[around])


def rms_jerks(times, names, positions) -> dict:
    return {row.joint: row.rms_jerk for row in motion_report.figures(times, names, positions)}


def planned_rms_jerks(node_config, seconds: float) -> dict:
    """The rms jerk of each joint the node's plan moves (motion.report), as executed by what the node drives: the
    controllers (the plan itself) or naoqi_driver's setAngles (the joint_angles actuation)."""
    plans = motion_report.planned_run(node_config, seconds, SEED)
    times = numpy.arange(0.0, seconds, 1.0 / motion_report.SAMPLE_RATE)
    names = tuple(name for joints, _ in plans for name in joints)
    if node_config.actuation == "joint_angles":
        return rms_jerks(times, names, motion_report.executed_by_joint_angles(times, plans))
    return rms_jerks(*motion_report.commanded_run(node_config, seconds, SEED))


def assert_smooth(harness: Ros2Harness, config, test: str) -> None:
    """The recorded joints' largest rms jerk while enabled is within JERK_FACTOR x the plan's + JERK_FLOOR."""
    observation = harness.session.last_observation
    node_config = settings.node_configuration(config, test)
    expected = oracle.expected_motion(test, config.platform, node_config)
    names = [joint for joint, bound in expected.bounds.items() if bound.moving]
    times, positions = resampled(harness.recorder.stamped_joints(), names, observation.enable_sent,
                                 observation.disable_sent, motion_report.SAMPLE_RATE)
    recorded = rms_jerks(times, names, positions)
    planned = planned_rms_jerks(node_config, config.test_duration)
    worst = max(recorded, key=recorded.get)
    bound = JERK_FACTOR * max(planned[name] for name in names if name in planned) + JERK_FLOOR
    print("rms jerk (rad/s^3) recorded: {}; planned: {}".format(
        {name: round(value, 1) for name, value in recorded.items()},
        {name: round(value, 1) for name, value in planned.items() if name in recorded}))
    assert recorded[worst] <= bound, "{} rms jerk {:.1f} rad/s^3 > {:.1f}".format(worst, recorded[worst], bound)


def test_random_style_passes_every_check_with_the_leg_pattern_and_moves_smoothly(simulator):
    outcome, config, harness = simulator.run("all", platform="simulator", motionStyle="random")
    assert "Leg follows its chunk pattern" in [check.name for check in outcome.checks]
    assert_passed(outcome, simulator)
    assert_smooth(harness, config, "all")


def test_breathing_style_passes_every_check_and_moves_smoothly(simulator):
    # Longer than the other runs' 3 s: the first goal eases in from rest onto the breathing curve in up to ~3 s here,
    # and the bounds are checked from its first point to the disable.
    outcome, config, harness = simulator.run("body", platform="simulator", motionStyle="breathing", testDuration=5)
    assert_passed(outcome, simulator)
    assert_smooth(harness, config, "body")


class WideningHarness(Ros2Harness):
    """Gives the node selectedRange 1.0 where the configuration it wrote says 0.5: a node that moves twice as far
    as the harness's bounds allow (the ROS 1 test/harness_broken_node.test)."""

    def apply_configuration(self, config, path: str) -> None:
        super().apply_configuration(config._replace(selected_range=1.0), path)


def test_a_node_that_moves_too_far_fails_and_the_harness_says_where(simulator):
    outcome, _, _ = simulator.run("body", WideningHarness, platform="simulator", motionStyle="random")
    failed = {check.name: check.detail for check in outcome.failures}
    assert "selectedRange: node used 1.0, the harness wrote 0.5" in failed["Node applied the test configuration"]
    assert "Random positions sent within bounds" in failed
    assert "outside [" in failed["Observed positions within bounds"], failed


def test_joint_angles_actuation_passes_every_check(tmp_path):
    robot = Robot(tmp_path, DOMAINS[1], ("platform:=robot", "driver:=naoqi_driver") + SIMULATOR,
                  ("platform:=robot", "actuation:=joint_angles"), ROBOT_PARTS)
    try:
        outcome, config, harness = robot.run("all", platform="robot", actuation="joint_angles")
    finally:
        statuses = robot.close()
    assert_passed(outcome, robot)
    assert_smooth(harness, config, "all")
    assert statuses == [0, 0], robot.output()
