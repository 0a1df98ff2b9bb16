"""The test harness on ROS 2 (README: "Test harness"): the rclpy side of the harness's session
(cssr_system.harness.session), which runs the same tests, checks and report as on ROS 1.

  python3 -m cssr_system.ros2.harness_runner [--config FILE] [--report FILE] [key:=value ...] [--ros-args ...]

The caller starts the robot (or cssr_system.ros2.simulated_pepper_node) and the node
(cssr_system.ros2.animate_behaviour_main). For each test the harness writes the node's configuration to its own
file, as on ROS 1, and hands it to the node as parameters (set_parameters_atomically): on ROS 2 the node's
configFile is read at start-up only, and each key's parameter overrides the file at every enable. Then it enables
the node over setActivation, records /joint_states, the odometry and the Wheels commands, disables it, reads the
node's log and judges the test (harness.checks). The key:=value arguments override keys of the harness
configuration, as the ROS 1 harness's private parameters do. Exit status: 0 when every test passed, 1 when one
failed, 2 when the harness could not run.
"""
import argparse
import os
import sys
import threading
from typing import List, Mapping, Optional, Sequence

import rclpy
from cssr_system_interfaces.srv import SetActivation
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rcl_interfaces.srv import GetParameters, SetParametersAtomically
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import (KEYS, Configuration, ConfigurationError,
                                                         shipped_configuration_path)
from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC
from cssr_system.animate_behaviour.event_log import default_log_path
from cssr_system.harness import checks, session, settings
from cssr_system.harness.session import (CONFIG_FILE_NAME, NODE_CONFIG_FILE_NAME,
                                         REPORT_FILE_NAME, HarnessError)
from cssr_system.package_files import data_dir, package_dir, package_path
from cssr_system.ros2.parameters import START_UP_KEYS, declared_value
from cssr_system.ros2.program import call
from cssr_system.ros2.time_conversion import seconds_of

NODE_NAME = session.HARNESS_NAME
SERVICE_TIMEOUT = 30.0  # s to wait for the node's services
CALL_TIMEOUT = 5.0  # s for a reply
JOINT_STATES_TIMEOUT = 10.0  # s to wait for the robot's first /joint_states
ODOMETRY_TIMEOUT = 2.0  # s to wait for odometry before using the Wheels commands
QUEUE = 50  # samples come at 50 Hz: keep a second of them if the executor falls behind


def _namespace(name: str) -> str:
    return name.rsplit("/", 1)[0] or "/"


class Ros2Harness(session.NodeLink):
    """The harness's rclpy node: the clients of the node's services, the subscriptions that feed the session's
    recorder. `node_log_file`: None asks the node's logFile parameter. `context`: None makes one of the harness's
    own (on `domain_id`, default ROS_DOMAIN_ID; `args`: ROS arguments, e.g. remappings), shut down by `close`."""

    def __init__(self, config: settings.HarnessConfiguration, node_config_file: str,
                 node_log_file: Optional[str] = None, node_name: str = "/" + contract.NODE_NAME,
                 report_file: Optional[str] = None, odometry_topic: Optional[str] = None,
                 context: Optional[Context] = None, domain_id: Optional[int] = None,
                 args: Optional[Sequence[str]] = None) -> None:
        try:
            settings.check_node_configuration_path(node_config_file, shipped_configuration_path())
        except ValueError as error:
            raise HarnessError(str(error)) from None
        self.config = config
        self.node_name = node_name
        self.node_log_file = node_log_file
        self.report_file = report_file
        self.wheels_topic, default_odometry = session.base_topics(config, data_dir())
        self.odometry_topic = default_odometry if odometry_topic is None else odometry_topic
        self._own_context = context is None
        self.context = Context() if context is None else context
        if self._own_context:
            rclpy.init(args=list(args or ()), context=self.context, domain_id=domain_id)
        self.node = Node(NODE_NAME, context=self.context)
        self.recorder = session.SampleRecorder()
        self._subscribe()
        # The node's services, setActivation and the parameter services, are under the node's own name.
        self._activation = self.node.create_client(SetActivation, contract.interface_of(node_name,
                                                                                        contract.SET_ACTIVATION))
        self._set_parameters = self.node.create_client(SetParametersAtomically,
                                                       node_name + "/set_parameters_atomically")
        self._get_parameters = self.node.create_client(GetParameters, node_name + "/get_parameters")
        # Spun only now that every entity exists: rclpy's are not safe to create while an executor iterates them.
        self._executor = SingleThreadedExecutor(context=self.context)
        self._executor.add_node(self.node)
        self._spinner = threading.Thread(target=self._executor.spin, name="harness executor", daemon=True)
        self._spinner.start()
        self.session = session.Session(config, self, self.recorder, os.path.abspath(node_config_file), "",
                                       self.wheels_topic, self.odometry_topic, self.node.get_logger().info,
                                       self.node.get_logger().error)
        self._connected = False
        self.iteration = 0

    def _subscribe(self) -> None:
        recorder = self.recorder
        # A zero stamp is an unset one: no stamped sample then.
        self.node.create_subscription(JointState, JOINT_STATES_TOPIC, lambda message: recorder.joint_state(
            message.name, message.position, seconds_of(message.header.stamp) or None), QUEUE)

        def odometry(message: Odometry) -> None:
            orientation = message.pose.pose.orientation
            recorder.odometry(orientation.x, orientation.y, orientation.z, orientation.w)
        if self.odometry_topic:
            self.node.create_subscription(Odometry, self.odometry_topic, odometry, QUEUE)
        if self.wheels_topic:
            self.node.create_subscription(Twist, self.wheels_topic,
                                          lambda message: recorder.base_command(message.angular.z), QUEUE)

    # -- set-up --------------------------------------------------------------------------------
    def connect(self, timeout: float = SERVICE_TIMEOUT) -> None:
        """Waits for the node's services and the robot's /joint_states; finds the node's log file."""
        for client in (self._activation, self._set_parameters):
            if not client.wait_for_service(timeout_sec=timeout):
                raise HarnessError("service {} not available after {:g} s: is animateBehaviour running?".format(
                    client.srv_name, timeout))
        if not self.recorder.joint_states_seen.wait(JOINT_STATES_TIMEOUT):
            raise HarnessError("no {} after {:g} s: is the robot (or the simulated Pepper) running?".format(
                JOINT_STATES_TOPIC, JOINT_STATES_TIMEOUT))
        if self.odometry_topic and not self.recorder.odometry_seen.wait(ODOMETRY_TIMEOUT):
            self.node.get_logger().warning("no odometry on {}; the base heading is taken from the commands on "
                                           "{}".format(self.odometry_topic, self.wheels_topic))
        if self.node_log_file is None:
            self.node_log_file = self._node_log_file()
        self.session.node_log_file = os.path.abspath(self.node_log_file)
        self._connected = True

    def _node_log_file(self) -> str:
        """The node's logFile parameter, or the node's default path when it is empty or cannot be read."""
        response = self._call(self._get_parameters, GetParameters.Request(names=["logFile"]))
        value = response.values[0].string_value if response is not None and response.values else ""
        return value or default_log_path(package_dir(), os.environ.get("ROS_HOME"))

    def _call(self, client, request, timeout: float = CALL_TIMEOUT):
        """The response, or None when there is none within `timeout`."""
        try:
            return call(client, request, timeout)
        except TimeoutError:
            return None

    # -- session.NodeLink ------------------------------------------------------------------------
    def request(self, state: str) -> str:
        response = self._call(self._activation, SetActivation.Request(state=state))
        if response is None:
            return "no reply from {} within {:g} s".format(self._activation.srv_name, CALL_TIMEOUT)
        return response.success

    def apply_configuration(self, config: Configuration, path: str) -> None:
        # Every key at once, typed as the node declares them: a change the node refuses leaves it unchanged. The
        # keys read at start-up are the node's own (the test starts it with the platform it runs).
        parameters = [Parameter(key, value=declared_value(config, key)).to_parameter_msg() for key in KEYS
                      if key not in START_UP_KEYS]
        response = self._call(self._set_parameters, SetParametersAtomically.Request(parameters=parameters))
        if response is None:
            raise HarnessError("no reply from {} within {:g} s".format(self._set_parameters.srv_name, CALL_TIMEOUT))
        if not response.result.successful:
            raise HarnessError("the node refused the test's configuration ({}): {}".format(
                path, response.result.reason))

    def node_overrides(self) -> Mapping[str, str]:
        return {}  # every key's parameter was just set to the written configuration: none differs

    def interrupted(self) -> bool:
        return not self.context.ok()

    # -- tests and rounds ----------------------------------------------------------------------
    def run_test(self, test: str, iteration: int = 1) -> checks.HarnessOutcome:
        return self.session.run_test(test, iteration)

    def run_rounds(self) -> List[checks.HarnessOutcome]:
        """`iterations` rounds of the configured tests, each appended to the report (when there is one)."""
        outcomes: List[checks.HarnessOutcome] = []
        planned = self.iteration + self.config.iterations
        for _ in range(self.config.iterations):
            self.iteration += 1
            outcomes.extend(self.session.run_round(self.iteration, planned, self.node_name, self.report_file))
        return outcomes

    def close(self) -> None:
        """Leaves the node disabled, and ends the harness's node (and its context, when it made it)."""
        if self._connected and self.context.ok():
            self.request(contract.DISABLED)
        self._executor.shutdown(timeout_sec=1.0)
        self._spinner.join(timeout=1.0)  # the executor's thread is done with the node before it goes
        self.node.destroy_node()
        if self._own_context:
            self.context.try_shutdown()


def parse_overrides(arguments: Sequence[str]) -> dict:
    """key:=value arguments as the harness configuration's overrides; ValueError for another form."""
    overrides = {}
    for argument in arguments:
        key, separator, value = argument.partition(":=")
        if not separator or not key:
            raise ValueError("expected key:=value, got {!r}".format(argument))
        overrides[key] = value
    return overrides


def main(argv: Optional[Sequence[str]] = None) -> int:
    ros_home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    parser = argparse.ArgumentParser(prog=NODE_NAME, description="The animateBehaviour test harness on ROS 2.")
    parser.add_argument("--config", default=package_path("config", CONFIG_FILE_NAME), help="harness configuration")
    parser.add_argument("--report", default=default_log_path(package_dir(), ros_home, file_name=REPORT_FILE_NAME),
                        help="report, appended to")
    parser.add_argument("--node", default="/" + contract.NODE_NAME, help="the node under test")
    parser.add_argument("--node-config", default=os.path.join(ros_home, NODE_CONFIG_FILE_NAME),
                        help="where the node's configuration of each test is written")
    parser.add_argument("--node-log", default=None, help="the node's log file (default: its logFile parameter)")
    parser.add_argument("overrides", nargs="*", metavar="key:=value", help="a key of the harness configuration")
    argv = list(sys.argv[1:] if argv is None else argv)
    # ROS's own arguments come last; rclpy would read a key:=value before them as a (deprecated) remapping.
    ros = argv.index("--ros-args") if "--ros-args" in argv else len(argv)
    arguments = parser.parse_args(argv[:ros])
    harness = None
    try:
        config = settings.load_harness_configuration(arguments.config, parse_overrides(arguments.overrides),
                                                     data_dir())
        harness = Ros2Harness(config, arguments.node_config, arguments.node_log, arguments.node, arguments.report,
                              args=[parser.prog] + argv[ros:])
        harness.connect()
        passed = all(outcome.passed for outcome in harness.run_rounds())
    except (ConfigurationError, ValueError, HarnessError) as error:
        print("{}: {}".format(NODE_NAME, error), file=sys.stderr, flush=True)
        return 2
    finally:
        if harness is not None:
            harness.close()
    return session.verdict(passed, arguments.report)


if __name__ == "__main__":
    sys.exit(main())
