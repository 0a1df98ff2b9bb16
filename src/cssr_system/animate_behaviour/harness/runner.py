"""animateBehaviourTest: the test harness of the animateBehaviour node (README: "Test harness").

It checks the node from outside, as its users do: for each selected test (hands, body, rotation, all)
it writes the node's configuration, enables the node through its service, lets it run, disables it,
and judges the replies, the node's log file and what the robot did (/joint_states, the base heading
from odometry or from the Wheels commands). The checks and the report are in cssr_system.animate_behaviour.harness.

Private parameters:
  ~configFile      harness configuration (default <package>/config/animateBehaviourTestConfiguration.ini)
  ~reportFile      report, appended to (default <package>/data/animateBehaviourTestOutput.dat, or
                   $ROS_HOME/animateBehaviourTestOutput.dat when the data folder is not writable)
  ~nodeName        the node under test (default /animateBehaviour)
  ~nodeConfigFile  where the node's configuration is written; the harness points the node's
                   ~configFile there before each enable and restores it at the end (default
                   $ROS_HOME/animateBehaviourHarnessNode.ini; never the shipped configuration)
  ~nodeLogFile     the node's log file (default: the node's ~logFile, else the node's default path)
  ~odometryTopic   base heading (default <namespace of the Wheels topic>/odom)
  ~interactive     ask "Run tests again? (y/n)" after the rounds (default: only when a terminal is
                   attached and the harness was not started by roslaunch or rostest)
  ~<key>           overrides a key of the harness configuration (e.g. _platform:=simulator, _tests:=body)
Started by rostest (--gtest_output), the tests run as unittest cases with JUnit results; otherwise
the exit status is 0 when every test passed, 1 when one failed, 2 when the harness could not run.
"""
import datetime
import os
import sys
import threading
import time
import unittest

import rospkg
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import (ConfigurationError, configuration_items,
                                                         format_configuration_file,
                                                         shipped_configuration_path, topic_file_path)
from cssr_system.animate_behaviour.contract import NODE_PARAMETERS
from cssr_system.animate_behaviour.event_log import ROTATED_SUFFIX, default_log_path, read_log
from cssr_system.animate_behaviour.harness import settings, oracle, checks, report
from cssr_system.animate_behaviour.recording.recording import unwrap_heading, yaw_from_quaternion
from cssr_system.animate_behaviour.topics import WHEELS_KEY, TopicFileError, load_topic_map
from cssr_system.package_files import PACKAGE_NAME, data_dir, package_dir, package_path
from cssr_system.pepper.joint_table import RELATIVE, wheels_command_kind
from cssr_system.srv import setActivation

NODE_NAME = "animateBehaviourTest"
HARNESS_PARAMETERS = ("configFile", "reportFile", "nodeName", "nodeConfigFile", "nodeLogFile", "odometryTopic",
                      "interactive")
CONFIG_FILE_NAME = "animateBehaviourTestConfiguration.ini"
REPORT_FILE_NAME = "animateBehaviourTestOutput.dat"
NODE_CONFIG_FILE_NAME = "animateBehaviourHarnessNode.ini"
SERVICE_TIMEOUT = 30.0  # s to wait for the node's service
JOINT_STATES_TIMEOUT = 10.0  # s to wait for the robot's first /joint_states
ODOMETRY_TIMEOUT = 2.0  # s to wait for odometry before using the Wheels commands
POLL_PERIOD = 0.05


class HarnessError(Exception):
    """The harness cannot run (a message for the user, never a traceback)."""


class Recorder:
    """/joint_states, the base heading and the Wheels commands, stamped on arrival (wall clock, like
    the node's log)."""

    def __init__(self, wheels_topic: str, odometry_topic: str) -> None:
        self._lock = threading.Lock()
        self._joints, self._headings, self._commands = [], [], []
        self._recording = False
        self.joint_states_seen = threading.Event()
        self.odometry_seen = threading.Event()
        self._heading = None  # unwrapped, so a turn across +-pi stays continuous
        rospy.Subscriber("/joint_states", JointState, self._on_joint_state, queue_size=50)
        if odometry_topic:
            rospy.Subscriber(odometry_topic, Odometry, self._on_odometry, queue_size=50)
        if wheels_topic:
            rospy.Subscriber(wheels_topic, Twist, self._on_twist, queue_size=50)

    def _on_joint_state(self, message: JointState) -> None:
        now = time.time()
        self.joint_states_seen.set()
        if self._recording:
            sample = checks.JointSample(now, dict(zip(message.name, message.position)))
            with self._lock:
                self._joints.append(sample)

    def _on_odometry(self, message: Odometry) -> None:
        now = time.time()
        self.odometry_seen.set()
        orientation = message.pose.pose.orientation
        yaw = yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)
        with self._lock:
            self._heading = unwrap_heading(self._heading, yaw)
            if self._recording:
                self._headings.append(checks.HeadingSample(now, self._heading))

    def _on_twist(self, message: Twist) -> None:
        if self._recording:
            with self._lock:
                self._commands.append(checks.BaseCommand(time.time(), message.angular.z))

    def start(self) -> None:
        with self._lock:
            self._joints, self._headings, self._commands = [], [], []
            self._recording = True

    def snapshot(self):
        with self._lock:
            return list(self._joints), list(self._headings), list(self._commands)

    def stop(self):
        with self._lock:
            self._recording = False
        return self.snapshot()


def started_by_rostest(argv) -> bool:
    return any(argument.startswith("--gtest_output") for argument in argv)


def started_by_roslaunch(argv) -> bool:
    return any(argument.startswith("__log:=") for argument in argv)  # roslaunch passes it, rosrun does not


class Harness:
    """Runs the selected tests against the node and writes the report."""

    def __init__(self) -> None:
        self.package_dir = package_dir()
        self.data_dir = data_dir()
        self.config_file = os.path.abspath(rospy.get_param(
            "~configFile", package_path("config", CONFIG_FILE_NAME)))
        overrides = {name: value for name, value in self._private_parameters(rospy.get_name()).items()
                     if name not in HARNESS_PARAMETERS}
        try:
            self.config = settings.load_harness_configuration(self.config_file, overrides, self.data_dir)
        except ConfigurationError as error:
            raise HarnessError("invalid test configuration: {}".format(error)) from None
        self.node_name = rospy.resolve_name(rospy.get_param("~nodeName", "/" + contract.NODE_NAME))
        # The node offers its service under its namespace (contract.SERVICE_NAME is relative).
        self.service_name = rospy.names.ns_join(rospy.names.namespace(self.node_name), contract.SERVICE_NAME)
        self.node_config_param = self.node_name + "/configFile"
        self.original_node_config = rospy.get_param(self.node_config_param, None)
        self.node_config_file = os.path.abspath(rospy.get_param(
            "~nodeConfigFile", os.path.join(rospkg.get_ros_home(), NODE_CONFIG_FILE_NAME)))
        try:
            settings.check_node_configuration_path(
                self.node_config_file, shipped_configuration_path())
        except ValueError as error:
            raise HarnessError(str(error)) from None
        self.node_log_file = os.path.abspath(rospy.get_param("~nodeLogFile", rospy.get_param(
            self.node_name + "/logFile", default_log_path(self.package_dir, os.environ.get("ROS_HOME")))))
        self.report_file = os.path.abspath(rospy.get_param("~reportFile", default_log_path(
            self.package_dir, os.environ.get("ROS_HOME"), file_name=REPORT_FILE_NAME)))
        try:
            topics = load_topic_map(topic_file_path(self.config.node, self.data_dir)).topics
        except TopicFileError as error:
            raise HarnessError(str(error)) from None
        self.wheels_topic = topics.get(WHEELS_KEY, "")
        default_odometry = self.wheels_topic.rsplit("/", 1)[0] + "/odom" if "/" in self.wheels_topic else ""
        self.odometry_topic = rospy.get_param("~odometryTopic", default_odometry)
        self.recorder = Recorder(self.wheels_topic, self.odometry_topic)
        self.iteration = 0
        self.planned_iterations = 0  # grows by `iterations` at each run ("Run tests again?")
        self._call = None

    @staticmethod
    def _private_parameters(node: str):
        prefix = node.rstrip("/") + "/"
        return {name[len(prefix):]: rospy.get_param(name) for name in rospy.get_param_names()
                if name.startswith(prefix) and "/" not in name[len(prefix):]}

    # -- set-up --------------------------------------------------------------------------------
    def connect(self) -> None:
        rospy.loginfo("%s: waiting for %s", NODE_NAME, self.service_name)
        try:
            rospy.wait_for_service(self.service_name, timeout=SERVICE_TIMEOUT)
        except rospy.ROSException:
            raise HarnessError("service {} not available after {:g} s: is animateBehaviour running?".format(
                self.service_name, SERVICE_TIMEOUT)) from None
        self._call = rospy.ServiceProxy(self.service_name, setActivation)
        if not self.recorder.joint_states_seen.wait(JOINT_STATES_TIMEOUT):
            raise HarnessError("no /joint_states after {:g} s: is the robot (or simulatedPepper.py) "
                               "running?".format(JOINT_STATES_TIMEOUT))
        if self.odometry_topic and not self.recorder.odometry_seen.wait(ODOMETRY_TIMEOUT):
            rospy.logwarn("%s: no odometry on %s; the base heading is taken from the commands on %s",
                          NODE_NAME, self.odometry_topic, self.wheels_topic)

    def request(self, state: str) -> str:
        try:
            return self._call(state).success
        except (rospy.ServiceException, rospy.ROSException) as error:
            return "no reply ({})".format(error)

    def write_node_configuration(self, test: str):
        config = settings.node_configuration(self.config, test)
        temporary = self.node_config_file + ".tmp"
        try:
            os.makedirs(os.path.dirname(self.node_config_file), exist_ok=True)
            with open(temporary, "w", encoding="utf-8") as stream:
                stream.write("# Written by animateBehaviourTest for the test '{}'; rewritten at every "
                             "test.\n".format(test))
                stream.write(format_configuration_file(config))
            os.replace(temporary, self.node_config_file)  # the node never reads half a file
        except OSError as error:
            raise HarnessError("cannot write the node's configuration {}: {}".format(
                self.node_config_file, error)) from None
        rospy.set_param(self.node_config_param, self.node_config_file)
        return config

    def node_overrides(self):
        return {name: str(value) for name, value in self._private_parameters(self.node_name).items()
                if name not in NODE_PARAMETERS}

    # -- waiting -------------------------------------------------------------------------------
    def sleep_until(self, deadline: float) -> None:
        while time.time() < deadline:
            if rospy.is_shutdown():
                raise HarnessError("interrupted")
            time.sleep(min(POLL_PERIOD, max(0.0, deadline - time.time())))

    def wait_for_rest(self, since: float, timeout: float, reference_heading=None, return_tolerance=0.0) -> None:
        """Until the robot has been still for the quiet window (and, given a reference, the base is
        back at that heading, within `return_tolerance`), or `timeout` s after `since`."""
        tolerance, heading_tolerance = self.config.position_tolerance, self.config.heading_tolerance
        while time.time() < since + timeout:
            joints, headings, _ = self.recorder.snapshot()
            joints = [sample for sample in joints if sample.time >= since]
            headings = [sample for sample in headings if sample.time >= since]
            still = checks.settled_since(joints, headings, tolerance, heading_tolerance)
            returned = reference_heading is None or not headings or \
                abs(headings[-1].heading - reference_heading) <= return_tolerance
            if still is not None and time.time() - still >= settings.QUIET_WINDOW and returned:
                return
            self.sleep_until(time.time() + POLL_PERIOD)

    def read_node_log(self, since: float):
        """Entries of the node's log written since `since` (also in the rotated file), and a problem."""
        moment = datetime.datetime.fromtimestamp(since - 1.0).astimezone()
        entries = []
        try:
            rotated = self.node_log_file + ROTATED_SUFFIX
            if os.path.exists(rotated) and os.path.getmtime(rotated) >= since - 1.0:
                entries.extend(read_log(rotated, moment))
            entries.extend(read_log(self.node_log_file, moment))
        except (OSError, ValueError) as error:
            return entries, "cannot read the node's log {}: {}".format(self.node_log_file, error)
        return entries, ""

    # -- one test ------------------------------------------------------------------------------
    def run_test(self, test: str, iteration: int) -> checks.HarnessOutcome:
        config = self.write_node_configuration(test)
        rotates = oracle.expected_motion(test, config.platform, config).base
        # Start from a disabled node and a robot at rest.
        self.request(contract.DISABLED)
        rest_from = time.time()
        self.recorder.start()
        self.wait_for_rest(rest_from, settings.BASE_STOP_LIMIT + settings.QUIET_WINDOW + 2.0)

        self.recorder.start()
        self.sleep_until(time.time() + 0.2)  # a heading and joint sample from before the enable
        enable_sent = time.time()
        enable_reply = self.request(contract.ENABLED)
        rospy.loginfo("%s: %s: enabled (reply %r), running %g s", NODE_NAME, settings.TESTS[test].title,
                      enable_reply, self.config.test_duration)
        self.sleep_until(enable_sent + self.config.test_duration)
        disable_sent = time.time()
        disable_reply = self.request(contract.DISABLED)
        _, headings, _ = self.recorder.snapshot()
        reference = checks.heading_at(headings, enable_sent) if rotates and config.home_on_disable else None
        limit = settings.BASE_STOP_LIMIT if rotates else settings.JOINT_STOP_LIMIT
        # Wait past the limit so that a late motion (e.g. a late return turn) is seen, not missed.
        self.wait_for_rest(disable_sent, limit + settings.QUIET_WINDOW + 2.0, reference,
                           checks.return_tolerance(self.config, config, self.wheels_topic))
        ended = time.time()
        joints, headings, commands = self.recorder.stop()
        heading_source = "odometry on {}".format(self.odometry_topic)
        if not headings and self.wheels_topic:
            relative = wheels_command_kind(self.wheels_topic) == RELATIVE
            headings = checks.headings_from_commands(commands, relative, joints[0].time if joints else enable_sent,
                                                     ended)
            heading_source = "commands on {} (no odometry on {})".format(self.wheels_topic, self.odometry_topic)
        entries, log_problem = self.read_node_log(enable_sent)
        observation = checks.Observation(
            enable_sent=enable_sent, enable_reply=enable_reply, disable_sent=disable_sent,
            disable_reply=disable_reply, ended=ended, entries=entries, joints=joints, headings=headings,
            heading_source=heading_source, base_commands=commands, base_topic=self.wheels_topic,
            written_items=configuration_items(config), node_overrides=self.node_overrides(),
            log_problem=log_problem)
        return checks.evaluate_test(test, iteration, self.config, observation)

    # -- rounds --------------------------------------------------------------------------------
    def append_report(self, text: str) -> None:
        try:
            os.makedirs(os.path.dirname(self.report_file), exist_ok=True)
            with open(self.report_file, "a", encoding="utf-8") as stream:
                stream.write(text)
        except OSError as error:
            raise HarnessError("cannot write the report {}: {}".format(self.report_file, error)) from None

    def run_round(self):
        """One round of the selected tests: outcomes, and the report appended."""
        self.iteration += 1
        started = datetime.datetime.now()
        self.append_report(report.format_run_header(started, self.config, self.iteration, self.node_name,
                                                    self.node_config_file, self.node_log_file,
                                                    max(self.planned_iterations, self.iteration)))
        outcomes = []
        for test in self.config.tests:
            outcome = self.run_test(test, self.iteration)
            outcomes.append(outcome)
            self.append_report(report.format_test(outcome))
            if outcome.passed:
                rospy.loginfo("%s: %s (iteration %d): PASSED", NODE_NAME, settings.TESTS[test].title, self.iteration)
            else:
                rospy.logerr("%s: %s", NODE_NAME, checks.failure_message(outcome).replace("\n", "\n  "))
        self.append_report(report.format_run_footer(outcomes))
        rospy.loginfo("%s: round %d %s; report: %s", NODE_NAME, self.iteration,
                      "PASSED" if all(outcome.passed for outcome in outcomes) else "FAILED", self.report_file)
        return outcomes

    def run_rounds(self):
        self.planned_iterations += self.config.iterations
        outcomes = []
        for _ in range(self.config.iterations):
            outcomes.extend(self.run_round())
        return outcomes

    def finish(self) -> None:
        """Leave the node disabled, with its own configuration file again."""
        if rospy.is_shutdown():
            return
        if self._call is not None:
            self.request(contract.DISABLED)
        try:
            if self.original_node_config is None:
                rospy.delete_param(self.node_config_param)
            else:
                rospy.set_param(self.node_config_param, self.original_node_config)
        except (KeyError, OSError, rospy.ROSException):
            pass


# ---------------------------------------------------------------------------------------------------
# rostest: one unittest case per test, judged on the outcomes of all rounds.

class AnimateBehaviourHarness(unittest.TestCase):
    harness = None
    outcomes = []

    @classmethod
    def setUpClass(cls):
        try:
            cls.harness = Harness()
            cls.harness.connect()
            cls.outcomes = cls.harness.run_rounds()
        except HarnessError as error:
            raise AssertionError("{}: {}".format(NODE_NAME, error)) from None
        finally:
            if cls.harness is not None:
                cls.harness.finish()

    def judge(self, test: str) -> None:
        if test not in self.harness.config.tests:
            self.skipTest("{} is not selected in {}".format(test, self.harness.config.source))
        failed = [outcome for outcome in self.outcomes if outcome.test == test and not outcome.passed]
        if failed:
            self.fail("\n".join(checks.failure_message(outcome) for outcome in failed)
                      + "\nreport: {}".format(self.harness.report_file))

    def test_1_hands(self):
        self.judge("hands")

    def test_2_body(self):
        self.judge("body")

    def test_3_rotation(self):
        self.judge("rotation")

    def test_4_all(self):
        self.judge("all")


def ask_again() -> bool:
    try:
        answer = input("Tests completed. Run tests again? (y/n): ")
    except EOFError:
        return False
    return answer.strip().lower() in ("y", "yes")


def main() -> int:
    rospy.init_node(NODE_NAME)
    if started_by_rostest(sys.argv):
        import rostest
        rostest.rosrun(PACKAGE_NAME, NODE_NAME, AnimateBehaviourHarness, sys.argv)
        return 0
    harness = None
    try:
        harness = Harness()
        interactive = rospy.get_param("~interactive", sys.stdin.isatty() and not started_by_roslaunch(sys.argv))
        harness.connect()
        passed = True
        while True:
            passed = all(outcome.passed for outcome in harness.run_rounds()) and passed
            if not interactive or rospy.is_shutdown() or not ask_again():
                break
    except HarnessError as error:
        print("{}: {}".format(NODE_NAME, error), file=sys.stderr, flush=True)
        return 2
    finally:
        if harness is not None:
            harness.finish()
    print("{}: {}; report: {}".format(NODE_NAME, "all tests PASSED" if passed else "some tests FAILED",
                                      harness.report_file), flush=True)
    return 0 if passed else 1
