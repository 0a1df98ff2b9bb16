"""animateBehaviourDemo: the demo's driver node: enables animateBehaviour, prints what moves, disables it.

rosrun cssr_system animateBehaviourDemo.py [_duration:=30] [_tail:=3] [_gesture:=false] [_conversation:=false]
                                           [_recorder:=/animateBehaviourRecorder] [_outcome_file:=FILE]

It waits (at most ``~startup_timeout`` s, default 40) until the simulated Pepper publishes
/joint_states, the node's service answers, the recorder (``~recorder``; "" for none) listens to
/joint_states and, with ``~gesture`` (``~conversation``), the gesture player (the stand-in speech node)
listens to its ``play`` topic. After 1 s at rest it enables the node through its service, prints one
line a second (which parts moved in that second, the base heading from odometry, with
``~conversation`` the node's mode), asks the gesture player to play half-way when ``~gesture`` is
true and the speech node to play its conversation 2 s after the enable when ``~conversation`` is
true, disables the node after ``~duration`` s, goes on printing for ``~tail`` s more so the return
to rest is recorded, then exits: launch/animateBehaviourDemo.launch marks it required, so the whole
launch ends with it.

Stopping early: SIGINT or SIGTERM to this node, or a shutdown request (``rosnode kill
/animateBehaviourDemo``, which is what `make demo` does on Ctrl-C), disables the node first, then
exits.

``~outcome_file`` (optional) receives one line when it exits: the demo's exit status and why, e.g.
``0 completed``, ``1 the animateBehaviour node (its service /animateBehaviour/setActivation) did not
start within 40 s``, ``130 stopped early (shutdown request)``.

The run itself is `demo_run`'s, which the ROS 2 driver (``cssr_system.ros2.demo_driver``) shares.
"""
import signal
import time
from typing import Optional, Sequence

import dynamic_reconfigure.client
import rosgraph
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.live_settings import PRESETS
from cssr_system.animate_behaviour.topics import DEFAULT_JOINT_ANGLES_TOPIC
from cssr_system.demo.demo_run import (EXIT_FAILED, NODE_NAME, SERVICE_CALL_TIMEOUT,
                                       STOP_DISABLE_TIMEOUT, DemoError, DemoRun, Wait, drive,
                                       say, service_failure, write_outcome)
from cssr_system.demo.gesture import PLAY_TOPIC
from cssr_system.demo.speech import PLAY_TOPIC as CONVERSATION_TOPIC
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic
from cssr_system.recording.recording import (BASE_LABEL, RunSetting, run_setting,
                                             yaw_from_quaternion)
from cssr_system.recording.run_recorder import NODE_NAME as RECORDER_NAME


def records_the_node(recorder: str, node: str) -> bool:
    """Whether the master lists `recorder` among the subscribers of joint_states and of every goal topic `node`
    publishes (and of joint_angles, where it streams its calls), all resolved names: the node sends its first goals
    within milliseconds of the enable, and a goal topic joined later misses them."""
    joint_angles = rospy.resolve_name(DEFAULT_JOINT_ANGLES_TOPIC)
    try:
        publishers, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    except Exception:  # noqa: BLE001 - the master is checked again on the next try
        return False
    goals = [topic for topic, nodes in publishers
             if (topic.endswith("/goal") or topic == joint_angles) and node in nodes]
    listening = {topic for topic, nodes in subscribers if recorder in nodes}
    needed = goals + [rospy.resolve_name(contract.JOINT_STATES_TOPIC)]
    return bool(goals) and all(topic in listening for topic in needed)


class DemoDriver(DemoRun):
    """The run (`demo_run`) on ROS 1."""

    def __init__(self, node: str, duration: float, tail: float, gesture: bool, recorder: str, startup_timeout: float,
                 setting: Optional[RunSetting], heading_topic: str, interaction: bool = False,
                 delay: float = 0.0, conversation: bool = False) -> None:
        super().__init__(duration, tail, startup_timeout, setting.log_file if setting is not None else None,
                         gesture, interaction, delay, rospy.get_name(), conversation)
        self.node = node  # the resolved name of the node driven: its service and status are under it
        self.service = contract.interface_of(node, contract.SET_ACTIVATION)
        self.recorder = recorder
        self.setting, self.heading_topic = setting, heading_topic
        self._gesture_publisher = rospy.Publisher(PLAY_TOPIC, Empty, queue_size=1) if gesture else None
        self._conversation_publisher = (rospy.Publisher(CONVERSATION_TOPIC, Empty, queue_size=1) if conversation
                                        else None)
        rospy.Subscriber(contract.JOINT_STATES_TOPIC, JointState, self._on_joint_states, queue_size=100)
        rospy.Subscriber(heading_topic, Odometry, self._on_odometry, queue_size=100)
        rospy.Subscriber(contract.interface_of(node, contract.STATUS), AnimateBehaviourStatus, self._on_status,
                         queue_size=10)

    # -- callbacks and stop requests ------------------------------------------------------------
    def engage(self) -> None:
        """The engaged preset, as a behaviour tree would switch to it while the robot speaks to someone."""
        self.say("switching to the engaged preset: %s"
                 % ", ".join("%s %s" % item for item in PRESETS["engaged"].items()))
        try:
            client = dynamic_reconfigure.client.Client(self.node, timeout=SERVICE_CALL_TIMEOUT)
            client.update_configuration(PRESETS["engaged"])
        except Exception as error:  # the demo goes on; the plot shows that nothing changed
            self.say("error: the engaged preset was not applied: %s" % error)

    def play_gesture(self) -> None:
        self._gesture_publisher.publish(Empty())

    def play_conversation(self) -> None:
        self._conversation_publisher.publish(Empty())

    def _on_joint_states(self, message: JointState) -> None:
        self.window.add_joint_states(time.time(), message.name, message.position)

    def _on_status(self, message: AnimateBehaviourStatus) -> None:
        self.yielding = [(PARTS[part.part].label if part.part in PARTS else BASE_LABEL, part.yielding_to)
                         for part in message.parts if part.state == "yielding"]
        self.mode = message.mode

    def _on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.window.add_heading(time.time(), yaw_from_quaternion(orientation.x, orientation.y, orientation.z,
                                                                 orientation.w))

    def on_ros_shutdown(self, reason: str) -> None:
        """rospy's pre-shutdown hook: service calls still work here, and no longer after it."""
        self.request_stop("shutdown request")
        try:
            self.disable_if_enabled(STOP_DISABLE_TIMEOUT)
        except DemoError as error:
            self.say("error: %s" % error)

    # -- the node's service ---------------------------------------------------------------------
    def activate(self, state: str, timeout: float) -> str:
        from cssr_system.srv import setActivation
        try:
            rospy.wait_for_service(self.service, timeout=timeout)
            return rospy.ServiceProxy(self.service, setActivation)(state).success
        except (rospy.ServiceException, rospy.ROSException) as error:
            raise service_failure(self.service, state, error) from None

    def startup_waits(self) -> Sequence[Wait]:
        waits = [("the animateBehaviour node (its service %s)" % self.service, self._service_answers)]
        if self.recorder:
            waits.append(("the recorder %s" % self.recorder, lambda: records_the_node(self.recorder, self.node)))
        if self._gesture_publisher is not None:
            waits.append(("the gesture player (%s)" % PLAY_TOPIC,
                          lambda: self._gesture_publisher.get_num_connections() > 0))
        if self._conversation_publisher is not None:
            waits.append(("the stand-in speech node (%s)" % CONVERSATION_TOPIC,
                          lambda: self._conversation_publisher.get_num_connections() > 0))
        return waits

    def _service_answers(self) -> bool:
        try:
            rospy.wait_for_service(self.service, timeout=0.2)
            return True
        except rospy.ROSException:
            return False


def main() -> int:
    rospy.init_node(NODE_NAME, disable_signals=True)
    duration = float(rospy.get_param("~duration", 30.0))
    tail = float(rospy.get_param("~tail", 3.0))
    delay = float(rospy.get_param("~delay", 0.0))
    outcome_file = str(rospy.get_param("~outcome_file", ""))
    if not duration > 0.0 or tail < 0.0 or delay < 0.0:
        say("error: ~duration must be positive, ~tail and ~delay not negative (got %r, %r and %r)"
            % (duration, tail, delay))
        write_outcome(outcome_file, EXIT_FAILED, "invalid ~duration, ~tail or ~delay")
        return EXIT_FAILED
    # Relative names: the driver, the node and the recorder share a namespace (README: "Several robots").
    node = rospy.resolve_name(str(rospy.get_param("~node", contract.NODE_NAME)))
    try:
        setting = run_setting(rospy.get_param(node, {}), None, node)  # type: Optional[RunSetting]
        platform = setting.platform
    except ValueError:
        setting, platform = None, str(rospy.get_param(node + "/platform", "robot"))  # the node says why
    heading_topic = odometry_topic(PLATFORMS[platform if platform in PLATFORMS else "robot"])
    driver = DemoDriver(node, duration, tail, bool(rospy.get_param("~gesture", False)),
                        rospy.resolve_name(str(rospy.get_param("~recorder", RECORDER_NAME))),
                        float(rospy.get_param("~startup_timeout", 40.0)), setting, heading_topic,
                        bool(rospy.get_param("~interaction", False)), delay,
                        bool(rospy.get_param("~conversation", False)))
    signal.signal(signal.SIGINT, driver.on_signal)
    signal.signal(signal.SIGTERM, driver.on_signal)
    rospy.core.add_preshutdown_hook(driver.on_ros_shutdown)
    status, text = drive(driver, outcome_file, "the launch")
    rospy.signal_shutdown("demo " + text)
    return EXIT_FAILED if status == EXIT_FAILED else 0
