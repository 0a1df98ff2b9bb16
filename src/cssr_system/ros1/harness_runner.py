"""animateBehaviourTest: the test harness of the animateBehaviour node (README: "Test harness").

It checks the node from outside, as its users do: for each selected test (hands, body, rotation, all)
it writes the node's configuration, enables the node through its service, lets it run, disables it,
and judges the replies, the node's log file and what the robot did (/joint_states, the base heading
from odometry or from the Wheels commands). The checks and the report are in cssr_system.harness.

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
import os
import sys
import unittest

import rospkg
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError, shipped_configuration_path
from cssr_system.animate_behaviour.contract import NODE_PARAMETERS
from cssr_system.animate_behaviour.event_log import default_log_path, node_log_file_name
from cssr_system.harness import checks, session, settings
from cssr_system.harness.session import (CONFIG_FILE_NAME, NODE_CONFIG_FILE_NAME, REPORT_FILE_NAME,
                                         HarnessError)
from cssr_system.package_files import PACKAGE_NAME, data_dir, package_dir, package_path
from cssr_system.srv import setActivation

NODE_NAME = session.HARNESS_NAME
HARNESS_PARAMETERS = ("configFile", "reportFile", "nodeName", "nodeConfigFile", "nodeLogFile", "odometryTopic",
                      "interactive")
SERVICE_TIMEOUT = 30.0  # s to wait for the node's service
JOINT_STATES_TIMEOUT = 10.0  # s to wait for the robot's first /joint_states
ODOMETRY_TIMEOUT = 2.0  # s to wait for odometry before using the Wheels commands


class Recorder(session.SampleRecorder):
    """The samples of `session.SampleRecorder`, from rospy's subscriptions."""

    def __init__(self, wheels_topic: str, odometry_topic: str) -> None:
        super().__init__()
        rospy.Subscriber(contract.JOINT_STATES_TOPIC, JointState, self._on_joint_state, queue_size=50)
        if odometry_topic:
            rospy.Subscriber(odometry_topic, Odometry, self._on_odometry, queue_size=50)
        if wheels_topic:
            rospy.Subscriber(wheels_topic, Twist, self._on_twist, queue_size=50)

    def _on_joint_state(self, message: JointState) -> None:
        self.joint_state(message.name, message.position)

    def _on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.odometry(orientation.x, orientation.y, orientation.z, orientation.w)

    def _on_twist(self, message: Twist) -> None:
        self.base_command(message.angular.z)


def started_by_rostest(argv) -> bool:
    return any(argument.startswith("--gtest_output") for argument in argv)


def started_by_roslaunch(argv) -> bool:
    return any(argument.startswith("__log:=") for argument in argv)  # roslaunch passes it, rosrun does not


class Harness(session.NodeLink):
    """Runs the selected tests against the node and writes the report: the rospy side of `session.Session`."""

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
        # Relative: the node under test is in the harness's namespace; its service is under its name.
        self.node_name = rospy.resolve_name(rospy.get_param("~nodeName", contract.NODE_NAME))
        self.service_name = contract.interface_of(self.node_name, contract.SET_ACTIVATION)
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
            self.node_name + "/logFile", default_log_path(self.package_dir, os.environ.get("ROS_HOME"),
                                                          node_log_file_name(self.node_name)))))
        self.report_file = os.path.abspath(rospy.get_param("~reportFile", default_log_path(
            self.package_dir, os.environ.get("ROS_HOME"), file_name=REPORT_FILE_NAME)))
        self.wheels_topic, default_odometry = session.base_topics(self.config, self.data_dir)
        self.odometry_topic = rospy.get_param("~odometryTopic", default_odometry)
        self.recorder = Recorder(self.wheels_topic, self.odometry_topic)
        self.session = session.Session(self.config, self, self.recorder, self.node_config_file, self.node_log_file,
                                       self.wheels_topic, self.odometry_topic,
                                       lambda text: rospy.loginfo("%s: %s", NODE_NAME, text),
                                       lambda text: rospy.logerr("%s: %s", NODE_NAME, text))
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

    # -- session.NodeLink ------------------------------------------------------------------------
    def request(self, state: str) -> str:
        try:
            return self._call(state).success
        except (rospy.ServiceException, rospy.ROSException) as error:
            return "no reply ({})".format(error)

    def apply_configuration(self, config, path: str) -> None:
        # The node reads its ~configFile at every enable: point it at the harness's file.
        rospy.set_param(self.node_config_param, path)

    def node_overrides(self):
        return {name: str(value) for name, value in self._private_parameters(self.node_name).items()
                if name not in NODE_PARAMETERS}

    def interrupted(self) -> bool:
        return rospy.is_shutdown()

    # -- tests and rounds ----------------------------------------------------------------------
    def run_test(self, test: str, iteration: int) -> checks.HarnessOutcome:
        return self.session.run_test(test, iteration)

    def run_round(self):
        """One round of the selected tests: outcomes, and the report appended."""
        self.iteration += 1
        return self.session.run_round(self.iteration, max(self.planned_iterations, self.iteration), self.node_name,
                                      self.report_file)

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
    return session.verdict(passed, harness.report_file)
