"""animateBehaviourRecorder on ROS 2: records a run of animateBehaviour and, when stopped, writes it and its plot.

  python3 -m cssr_system.ros2.recorder_node --ros-args [-p output_dir:=DIR] [-p node:=/animateBehaviour]
                                            [-p log_file:=FILE] [-p platform:=simulator]

From its start until SIGINT or SIGTERM it records /joint_states, the base heading (odometry of the simulated
Pepper's platform, ``<namespace>/odom``), each part's controller state (``<controller>/controller_state``), the
setAngles calls on the node's JointAngles topic and the node's mode (its status topic). When stopped, it
reads the node's log file for the enable and disable instants, the joints' bands and the changes of settings, and
writes ``animation.json`` and ``animation.png`` into ``output_dir``, printing both paths, as the ROS 1 recorder
does: both hand their samples to `cssr_system.recording.run_recorder`, which writes them. Exit
status 0 when written, 1 when not (nothing recorded, or a file could not be written).

Parameters:
  output_dir  the folder of both files (default ``$ROS_HOME/animateBehaviourDemo``)
  node        the node recorded (default ``/animateBehaviour``); its parameters (configFile, logFile, platform,
              behaviour, the topic files) are asked from it as soon as its parameter service answers
  log_file    the node's log file ("": the node's parameter ``logFile``, resolved as the node resolves it)
  platform    robot or simulator, which decides the odometry topic ("": the node's parameter ``platform``)

How it knows what the node commanded differs from ROS 1: on ROS 2 an action's goals, cancels and results travel as
service calls between a client and the server, not on topics, so no third node sees them. The ``commanded`` line of
the trajectory actuation is therefore each controller's ``reference`` (what joint_trajectory_controller, and the
simulated Pepper, publish at each update) from the node's first goal to the part, as its log's ``goal_sent`` tells,
and not while the part yields to another node (its log's ``part_yielded``, until its next goal); the marks of other
nodes' goals come from those yields (`run_recorder`). The setAngles calls of the joint_angles actuation are a topic,
so their ``commanded`` line and other nodes' marks are here as on ROS 1; but a ROS 2 message does not name its
publisher: a call counts as the node's only while the node is the topic's one publisher.
"""
import functools
import os
import sys
import threading
from typing import Any, Dict, List, Optional, Set

from control_msgs.msg import JointTrajectoryControllerState
from cssr_system_interfaces.msg import AnimateBehaviourStatus
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import PLATFORM_TOPICS_KEYS
from cssr_system.animate_behaviour.topics import joint_angles_topic
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic
from cssr_system.recording.commanded import SentCall
from cssr_system.recording.recording import SETTING_KEYS, RunSetting, run_setting
from cssr_system.recording.run_recorder import NODE_NAME, RunRecorder, default_output_dir, say
from cssr_system.ros2.program import on_signals, run_node
from cssr_system.ros2.rclpy_compat import endpoint_names
from cssr_system.ros2.status import LATCHED
from cssr_system.ros2.time_conversion import seconds_of

QUEUE_DEPTH = 100  # /joint_states, odometry and the controllers' states come at 50 Hz: a busy second must not drop
STATE_TOPIC = "/controller_state"  # joint_trajectory_controller's, beside its action
PARAMETERS_PERIOD = 0.5  # s between asks for the node's parameters until it answers
UNKNOWN_NODE = "another node"
# The node's parameters that decide its log file, configuration, platform and topics (recording.run_setting).
NODE_PARAMETERS = ("configFile", "logFile") + SETTING_KEYS + tuple(PLATFORM_TOPICS_KEYS.values())
VALUE_FIELDS = {ParameterType.PARAMETER_BOOL: "bool_value", ParameterType.PARAMETER_INTEGER: "integer_value",
                ParameterType.PARAMETER_DOUBLE: "double_value", ParameterType.PARAMETER_STRING: "string_value"}


def parameter_values(names: List[str], values: List[Any]) -> Dict[str, Any]:
    """The parameters of a GetParameters reply that are set, as Python values."""
    return {name: getattr(value, VALUE_FIELDS[value.type]) for name, value in zip(names, values)
            if value.type in VALUE_FIELDS}


def resolve_setting(node_values: Dict[str, Any], log_file: str, platform: str,
                    target: str) -> Optional[RunSetting]:
    """The run's setting of the node `target` (its full name) from its parameters, the recorder's `log_file` and
    `platform` winning; None (after a line saying why) when its configuration cannot be read."""
    values = dict(node_values)
    values.update({key: value for key, value in (("logFile", log_file), ("platform", platform)) if value})
    try:
        return run_setting(values, os.environ.get("ROS_HOME"), target)
    except ValueError as error:
        say("the configuration of the node cannot be read (%s): recording without its log" % error)
        return None


class MessageRecorder(RunRecorder):
    """The ROS 2 messages, handed to the recorder (`run_recorder`) as plain values; every callback runs in the
    one thread of the node's executor."""

    def __init__(self, node: Node, target: str, log_file: str, platform: str) -> None:
        super().__init__(target, None, "")
        self._node = node
        self._log_file, self._platform = log_file, platform
        self._subscriptions = [node.create_subscription(JointState, contract.JOINT_STATES_TOPIC,
                                                        self.on_joint_states, QUEUE_DEPTH),
                               node.create_subscription(AnimateBehaviourStatus,
                                                        contract.interface_of(target, contract.STATUS),
                                                        lambda message: self.add_mode(message.mode), LATCHED)]
        self._heading_subscribed = False
        self._state_topics: Set[str] = set()
        if platform:
            self._subscribe_heading(platform)
            # The controllers' states of the platform's default topics at once, not after the node answers: a
            # subscription made late, on a busy machine, missed the node's first seconds of goals.
            default = resolve_setting({}, log_file, platform, target)
            self._subscribe_states(default.topics if default is not None else {})
        self._client = node.create_client(GetParameters, target.rstrip("/") + "/get_parameters")
        self._asking = False
        self._timer = node.create_timer(PARAMETERS_PERIOD, self._ask_parameters)

    def _subscribe_heading(self, platform: str) -> None:
        self.heading_topic = odometry_topic(PLATFORMS.get(platform, PLATFORMS["robot"]))
        self._subscriptions.append(self._node.create_subscription(Odometry, self.heading_topic, self.on_odometry,
                                                                  QUEUE_DEPTH))
        self._heading_subscribed = True

    # -- the node's parameters ------------------------------------------------------------------
    def _ask_parameters(self) -> None:
        if self._asking or not self._client.service_is_ready():
            return
        self._asking = True
        future = self._client.call_async(GetParameters.Request(names=list(NODE_PARAMETERS)))
        future.add_done_callback(self._on_parameters)

    def _on_parameters(self, future) -> None:
        self._asking = False
        reply = future.result()
        values = parameter_values(list(NODE_PARAMETERS), list(reply.values) if reply is not None else [])
        if "platform" not in values:  # asked before the node declared its configuration keys: ask again
            return
        self._timer.cancel()
        self.setting = resolve_setting(values, self._log_file, self._platform, self.node)
        if not self._heading_subscribed:
            self._subscribe_heading(self.setting.platform if self.setting is not None else str(values["platform"]))
        topics = self.setting.topics if self.setting is not None else {}
        calls = joint_angles_topic(topics)
        self._subscriptions.append(self._node.create_subscription(JointAnglesWithSpeed, calls, self.on_joint_angles,
                                                                  QUEUE_DEPTH))
        self._subscribe_states(topics)
        self._node.get_logger().info("recording /joint_states, {}, the states of {} controllers and the calls on {}; "
                                     "the node's log {}".format(self.heading_topic, len(self._state_topics), calls,
                                                                self.setting.log_file if self.setting is not None
                                                                else "unknown"))

    def _subscribe_states(self, topics: Dict[str, str]) -> None:
        """Each part's controller state in `topics` (the topic file's names), once."""
        for key in PARTS:
            topic = controller_state_topic(topics[key]) if key in topics else None
            if topic is not None and topic not in self._state_topics:
                self._state_topics.add(topic)
                self._subscriptions.append(self._node.create_subscription(
                    JointTrajectoryControllerState, topic, functools.partial(self.on_controller_state, key),
                    QUEUE_DEPTH))

    def finish(self) -> None:
        """Where the node never answered: its log and configuration as the node would resolve them by default."""
        if self.setting is None:
            self.setting = resolve_setting({}, self._log_file, self._platform, self.node)

    # -- messages -------------------------------------------------------------------------------
    def on_joint_states(self, message: JointState) -> None:
        self.add_joint_states(seconds_of(message.header.stamp), message.name, message.position)

    def on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.add_orientation(seconds_of(message.header.stamp), orientation.x, orientation.y, orientation.z,
                             orientation.w)

    def on_controller_state(self, part: str, message: JointTrajectoryControllerState) -> None:
        self.add_reference(seconds_of(message.header.stamp), part, message.joint_names, message.reference.positions)

    def on_joint_angles(self, message: JointAnglesWithSpeed) -> None:
        topic = joint_angles_topic(self.setting.topics if self.setting is not None else {})
        self.add_call(SentCall(self.now(), self._publisher_of(topic), tuple(message.joint_names),
                               tuple(message.joint_angles), message.speed, message.relative))

    def _publisher_of(self, topic: str) -> str:
        """The topic's one publisher; with several, none of them can be told (ROS 2 does not name a message's)."""
        names = sorted(endpoint_names(self._node.get_publishers_info_by_topic(topic)))
        return names[0] if len(names) == 1 else UNKNOWN_NODE


def controller_state_topic(action: str) -> str:
    """The state topic of the controller that serves `action` (``<controller>/follow_joint_trajectory``)."""
    return action.rsplit("/", 1)[0] + STATE_TOPIC


def record(node: Node, stop: threading.Event) -> int:
    """Record on `node` until `stop` is set, then write the recording and its plot: 0 when written."""
    output_dir = os.path.abspath(node.declare_parameter("output_dir", "").value
                                 or default_output_dir(node.get_namespace()))
    # Relative: the node recorded is in the recorder's namespace (README: "Several robots").
    target = node.resolve_topic_name(node.declare_parameter("node", contract.NODE_NAME).value, only_expand=True)
    recorder = MessageRecorder(node, target, node.declare_parameter("log_file", "").value,
                               node.declare_parameter("platform", "").value)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    node.get_logger().info("recording {}; output in {}".format(target, output_dir))
    while not stop.wait(0.2):
        pass
    executor.shutdown(timeout_sec=2.0)  # no callback runs while the recording is made
    spinner.join(timeout=2.0)
    recorder.finish()
    return recorder.save(output_dir)


def main(args: Optional[List[str]] = None) -> int:
    stop = threading.Event()
    on_signals(lambda _name: stop.set())  # the recording is written after the signal, rclpy still up
    return run_node(NODE_NAME, args, lambda node: record(node, stop))


if __name__ == "__main__":
    sys.exit(main())
