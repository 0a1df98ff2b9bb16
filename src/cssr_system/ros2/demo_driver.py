"""animateBehaviourDemo on ROS 2: the demo's driver: enables animateBehaviour, prints what moves, disables it.

  python3 -m cssr_system.ros2.demo_driver --ros-args [-p duration:=30.0] [-p tail:=3.0] [-p delay:=0.0]
      [-p platform:=robot] [-p interaction:=false] [-p gesture:=false] [-p conversation:=false]
      [-p node:=animateBehaviour]
      [-p recorder:=animateBehaviourRecorder] [-p log_file:=FILE] [-p outcome_file:=FILE] [-p startup_timeout:=40.0]

The run of the ROS 1 driver (`cssr_system.demo.demo_run`), over rclpy, with the node, the recorder and the gesture
player in its own namespace: it waits (at most ``startup_timeout`` s) until the simulated Pepper publishes
joint_states, the node's service setActivation is there, the recorder (``recorder``; "" for none) subscribes
joint_states and every JointAngles topic the node publishes, and with ``gesture`` (``conversation``) the gesture
player (the stand-in speech node) listens; after 1 s (and ``delay`` s more) at rest it enables the node, prints one
line a second (the parts moved in that second, the base heading from ``platform``'s odometry, with ``conversation``
the node's mode, the parts yielding to another node), with ``interaction`` sets the engaged preset half-way through
the node's parameters, with ``gesture`` has the gesture player play half-way, with ``conversation`` has the speech
node play its conversation 2 s after the enable, disables the
node after ``duration`` s, prints for ``tail`` s more so the return to rest is recorded, and exits.

SIGINT or SIGTERM disables the node first, then exits. ``log_file``: the node's log, where a refused enable's
reason is. ``outcome_file`` receives one line: the exit status and why. Exit status: 0 completed, 1 something did
not start or answer, 130 stopped early.
"""
import signal
import sys
import threading
import time
from typing import List, Optional, Sequence

from cssr_system_interfaces.msg import AnimateBehaviourStatus
from cssr_system_interfaces.srv import SetActivation
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor
from rcl_interfaces.srv import SetParameters
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.live_settings import PRESETS, SETTING_KEYS
from cssr_system.demo.demo_run import (EXIT_FAILED, NODE_NAME, SERVICE_CALL_TIMEOUT,
                                       DemoRun, Wait, drive, say, service_failure, write_outcome)
from cssr_system.demo.gesture import PLAY_TOPIC
from cssr_system.demo.speech import PLAY_TOPIC as CONVERSATION_TOPIC
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic
from cssr_system.recording.recording import BASE_LABEL, yaw_from_quaternion
from cssr_system.recording.run_recorder import NODE_NAME as RECORDER_NAME
from cssr_system.ros2.program import call, on_signals, run_node
from cssr_system.ros2.rclpy_compat import endpoint_names
from cssr_system.ros2.status import LATCHED

QUEUE_DEPTH = 100
EXECUTOR_STOP_TIMEOUT = 2.0  # s
JOINT_ANGLES_TYPE = "naoqi_bridge_msgs/msg/JointAnglesWithSpeed"  # what the joint_angles actuation streams


class DemoDriver(DemoRun):
    """The run (`demo_run`) on ROS 2."""

    def __init__(self, node: Node, target: str, duration: float, tail: float, recorder: str, startup_timeout: float,
                 log_file: Optional[str], heading_topic: str, interaction: bool, delay: float = 0.0,
                 gesture: bool = False, conversation: bool = False) -> None:
        super().__init__(duration, tail, startup_timeout, log_file, gesture=gesture, interaction=interaction,
                         delay=delay, name=node.get_fully_qualified_name(), conversation=conversation)
        self._gesture = node.create_publisher(Empty, PLAY_TOPIC, 1) if gesture else None
        self._conversation = node.create_publisher(Empty, CONVERSATION_TOPIC, 1) if conversation else None
        self.node, self.target, self.recorder = node, target, recorder  # full names of the node and the recorder
        self.service = contract.interface_of(target, contract.SET_ACTIVATION)
        self._activation = node.create_client(SetActivation, self.service)
        self._parameters = node.create_client(SetParameters, target + "/set_parameters")
        node.create_subscription(JointState, contract.JOINT_STATES_TOPIC, self._on_joint_states, QUEUE_DEPTH)
        node.create_subscription(Odometry, heading_topic, self._on_odometry, QUEUE_DEPTH)
        node.create_subscription(AnimateBehaviourStatus, contract.interface_of(target, contract.STATUS),
                                 self._on_status, LATCHED)

    def _on_joint_states(self, message: JointState) -> None:
        self.window.add_joint_states(time.time(), message.name, message.position)

    def _on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.window.add_heading(time.time(), yaw_from_quaternion(orientation.x, orientation.y, orientation.z,
                                                                 orientation.w))

    def _on_status(self, message: AnimateBehaviourStatus) -> None:
        self.yielding = [(PARTS[part.part].label if part.part in PARTS else BASE_LABEL, part.yielding_to)
                         for part in message.parts if part.state == "yielding"]
        self.mode = message.mode

    # -- the node's services ----------------------------------------------------------------------
    def activate(self, state: str, timeout: float) -> str:
        try:
            return call(self._activation, SetActivation.Request(state=state), timeout).success
        except TimeoutError as error:
            raise service_failure(self.service, state, error) from None

    def engage(self) -> None:
        """The engaged preset through the node's parameters, as a behaviour tree would switch to it."""
        preset = PRESETS["engaged"]
        self.say("switching to the engaged preset: %s" % ", ".join("%s %s" % item for item in preset.items()))
        request = SetParameters.Request(parameters=[Parameter(SETTING_KEYS[name], value=value).to_parameter_msg()
                                                    for name, value in preset.items()])
        try:
            refused = [result.reason for result in call(self._parameters, request, SERVICE_CALL_TIMEOUT).results
                       if not result.successful]
        except TimeoutError as error:
            refused = [str(error)]
        if refused:  # the demo goes on; the plot shows that nothing changed
            self.say("error: the engaged preset was not applied: %s" % "; ".join(refused))

    # -- start-up -------------------------------------------------------------------------------
    def startup_waits(self) -> Sequence[Wait]:
        waits = [("the animateBehaviour node (its service %s)" % self.service, self._activation.service_is_ready)]
        if self.recorder:
            waits.append(("the recorder %s" % self.recorder, self.records_the_node))
        if self._gesture is not None:
            waits.append(("the gesture player (%s)" % PLAY_TOPIC, lambda: self._gesture.get_subscription_count() > 0))
        if self._conversation is not None:
            waits.append(("the stand-in speech node (%s)" % CONVERSATION_TOPIC,
                          lambda: self._conversation.get_subscription_count() > 0))
        return waits

    def play_gesture(self) -> None:
        self._gesture.publish(Empty())

    def play_conversation(self) -> None:
        self._conversation.publish(Empty())

    def records_the_node(self) -> bool:
        """Whether the recorder subscribes joint_states and every JointAngles topic the node publishes: the node's
        first calls follow the enable within milliseconds, and a subscription made later misses them."""
        namespace, name = self.target.rsplit("/", 1)
        try:
            published = self.node.get_publisher_names_and_types_by_node(name, namespace or "/")
        except Exception:  # noqa: BLE001 - the node's service is seen before the node itself: asked again
            return False
        streams = [name for name, types in published if JOINT_ANGLES_TYPE in types]
        return all(self.recorder in endpoint_names(self.node.get_subscriptions_info_by_topic(topic))
                   for topic in [self.node.resolve_topic_name(contract.JOINT_STATES_TOPIC)] + streams)


def number(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError("%s must be a number (got %r)" % (name, value))
    return float(value)


def make_driver(node: Node) -> DemoDriver:
    """The driver of the node's parameters; ValueError naming a bad one."""
    # Dynamic typing: `duration:=6` is an integer, and the check below says what is wrong, not rclpy.
    dynamic = ParameterDescriptor(dynamic_typing=True)
    value = {name: node.declare_parameter(name, default, dynamic).value for name, default in (
        ("duration", 30.0), ("tail", 3.0), ("delay", 0.0), ("platform", "robot"), ("interaction", False),
        ("gesture", False), ("conversation", False),
        ("node", contract.NODE_NAME), ("recorder", RECORDER_NAME), ("log_file", ""), ("startup_timeout", 40.0))}
    duration, tail, delay = (number(value[name], name) for name in ("duration", "tail", "delay"))
    if not duration > 0.0 or tail < 0.0 or delay < 0.0:
        raise ValueError("duration must be positive, tail and delay not negative (got %r, %r and %r)"
                         % (duration, tail, delay))
    heading_topic = odometry_topic(PLATFORMS.get(str(value["platform"]), PLATFORMS["robot"]))
    # Relative names: the driver, the node and the recorder share a namespace (README: "Several robots").
    target, recorder = (node.resolve_topic_name(str(value[name]), only_expand=True) for name in ("node", "recorder"))
    return DemoDriver(node, target, duration, tail, recorder, number(value["startup_timeout"], "startup_timeout"),
                      str(value["log_file"]) or None, heading_topic, value["interaction"] is True, delay,
                      value["gesture"] is True, value["conversation"] is True)


def run(node: Node, outcome_file: str, early_stops: List[str]) -> int:
    """The run on `node`; `early_stops`: the signals that came before the driver existed."""
    try:
        driver = make_driver(node)
    except ValueError as error:
        say("error: %s" % error)
        write_outcome(outcome_file, EXIT_FAILED, "invalid parameter: %s" % error)
        return EXIT_FAILED
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, driver.on_signal)
    if early_stops:
        driver.request_stop(early_stops[0])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    try:
        status, _ = drive(driver, outcome_file, "the demo")
    finally:
        executor.shutdown(timeout_sec=EXECUTOR_STOP_TIMEOUT)
        spinner.join(timeout=EXECUTOR_STOP_TIMEOUT)
    return status


def main(args: Optional[List[str]] = None) -> int:
    early_stops: List[str] = []  # kept for the driver, which stops before it enables anything
    on_signals(early_stops.append)
    return run_node(NODE_NAME, args, lambda node: run(node, node.declare_parameter("outcome_file", "").value,
                                                      early_stops), EXIT_FAILED)


if __name__ == "__main__":
    sys.exit(main())
