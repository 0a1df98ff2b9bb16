"""animateBehaviourDemo: the demo's driver node: enables animateBehaviour, prints what moves, disables it.

rosrun cssr_system animateBehaviourDemo.py [_duration:=30] [_tail:=3] [_gesture:=false]
                                           [_recorder:=/animateBehaviourRecorder] [_outcome_file:=FILE]

It waits (at most ``~startup_timeout`` s, default 40) until the simulated Pepper publishes
/joint_states, the node's service answers, the recorder (``~recorder``; "" for none) listens to
/joint_states and, with ``~gesture``, the gesture player listens to its ``play`` topic. After 1 s at
rest it enables the node through its service, prints one line a second (which parts moved in that
second, the base heading from odometry), asks the gesture player to play half-way when ``~gesture``
is true, disables the node after ``~duration`` s, goes on printing for ``~tail`` s more so the return
to rest is recorded, then exits: launch/animateBehaviourDemo.launch marks it required, so the whole
launch ends with it.

Stopping early: SIGINT or SIGTERM to this node, or a shutdown request (``rosnode kill
/animateBehaviourDemo``, which is what `make demo` does on Ctrl-C), disables the node first, then
exits.

``~outcome_file`` (optional) receives one line when it exits: the demo's exit status and why, e.g.
``0 completed``, ``1 the animateBehaviour node (its service /animateBehaviour/setActivation) did not
start within 40 s``, ``130 stopped early (shutdown request)``.
"""
import functools
import signal
import threading
import time
from typing import Callable, List, Optional, Tuple

import dynamic_reconfigure.client
import rosgraph
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.demo import console
from cssr_system.animate_behaviour.contract import (DISABLED, ENABLED, REPLY_SUCCESS, SERVICE_PATH,
                                                    STATUS_TOPIC)
from cssr_system.animate_behaviour.demo.gesture import PLAY_TOPIC
from cssr_system.animate_behaviour.demo.live_lines import DISABLE, ENGAGED, GESTURE, LiveWindow, schedule, status_line
from cssr_system.animate_behaviour.live_settings import PRESETS
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.animate_behaviour.recording.recording import (RunSetting, run_setting, yaw_from_quaternion,
                                                               BASE_LABEL)
from cssr_system.animate_behaviour.topics import DEFAULT_JOINT_ANGLES_TOPIC
from cssr_system.pepper.joint_table import PARTS
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic

NODE_NAME = "animateBehaviourDemo"
say = functools.partial(console.say, NODE_NAME)
REST_BEFORE = 1.0  # s at rest before enabling, so the plot shows the start
SERVICE_CALL_TIMEOUT = 5.0  # s; the node answers within 100 ms, so this only catches a dead node
STOP_DISABLE_TIMEOUT = 2.0  # s for the disable when stopping early (the node may be stopping too)
EXIT_COMPLETED, EXIT_FAILED, EXIT_INTERRUPTED = 0, 1, 130


class DemoError(Exception):
    """Something did not start or answer: one line for the user, exit status 1."""


class Interrupted(Exception):
    """A stop was requested (signal or shutdown request)."""


def records_the_node(recorder: str, node: str = "/" + contract.NODE_NAME,
                     joint_angles: str = DEFAULT_JOINT_ANGLES_TOPIC) -> bool:
    """Whether the master lists `recorder` among the subscribers of /joint_states and of every goal topic `node`
    publishes (and of `joint_angles`, where it streams its calls): the node sends its first goals within
    milliseconds of the enable, and a goal topic joined later misses them."""
    try:
        publishers, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    except Exception:  # noqa: BLE001 - the master is checked again on the next try
        return False
    goals = [topic for topic, nodes in publishers
             if (topic.endswith("/goal") or topic == joint_angles) and node in nodes]
    listening = {topic for topic, nodes in subscribers if recorder in nodes}
    return bool(goals) and all(topic in listening for topic in goals + ["/joint_states"])


class DemoDriver:
    def __init__(self, duration: float, tail: float, gesture: bool, recorder: str, startup_timeout: float,
                 setting: Optional[RunSetting], heading_topic: str, interaction: bool = False) -> None:
        self.duration, self.tail, self.gesture, self.interaction = duration, tail, gesture, interaction
        self.recorder, self.startup_timeout = recorder, startup_timeout
        self.setting, self.heading_topic = setting, heading_topic
        self.window = LiveWindow()
        self.stop = threading.Event()
        self.stop_reason = ""
        self._activation_lock = threading.Lock()
        self._enabled = False
        self.disabled_early = False  # disabled because a stop was requested
        self._gesture_publisher = rospy.Publisher(PLAY_TOPIC, Empty, queue_size=1) if gesture else None
        rospy.Subscriber("/joint_states", JointState, self._on_joint_states, queue_size=100)
        rospy.Subscriber(heading_topic, Odometry, self._on_odometry, queue_size=100)
        self._yielding: List[Tuple[str, str]] = []  # (label, caller) of the parts that yield, from the node's status
        rospy.Subscriber(STATUS_TOPIC, AnimateBehaviourStatus, self._on_status, queue_size=10)

    # -- callbacks and stop requests ------------------------------------------------------------
    def engage(self) -> None:
        """The engaged preset, as a behaviour tree would switch to it while the robot speaks to someone."""
        say("switching to the engaged preset: %s" % ", ".join("%s %s" % item for item in PRESETS["engaged"].items()))
        try:
            client = dynamic_reconfigure.client.Client("/" + contract.NODE_NAME, timeout=SERVICE_CALL_TIMEOUT)
            client.update_configuration(PRESETS["engaged"])
        except Exception as error:  # the demo goes on; the plot shows that nothing changed
            say("error: the engaged preset was not applied: %s" % error)

    def _on_joint_states(self, message: JointState) -> None:
        self.window.add_joint_states(time.time(), message.name, message.position)

    def _on_status(self, message: AnimateBehaviourStatus) -> None:
        self._yielding = [(PARTS[part.part].label if part.part in PARTS else BASE_LABEL, part.yielding_to)
                          for part in message.parts if part.state == "yielding"]

    def _on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.window.add_heading(time.time(), yaw_from_quaternion(orientation.x, orientation.y, orientation.z,
                                                                 orientation.w))

    def on_signal(self, signal_number: int, frame) -> None:
        self.stop_reason = self.stop_reason or signal.Signals(signal_number).name
        self.stop.set()  # the main thread disables and exits

    def on_ros_shutdown(self, reason: str) -> None:
        """rospy's pre-shutdown hook: service calls still work here, and no longer after it."""
        self.stop_reason = self.stop_reason or "shutdown request"
        self.stop.set()
        try:
            self.disable_if_enabled(STOP_DISABLE_TIMEOUT)
        except DemoError as error:
            say("error: %s" % error)

    # -- the node's service ---------------------------------------------------------------------
    def _activate(self, state: str, timeout: float) -> str:
        from cssr_system.srv import setActivation
        try:
            rospy.wait_for_service(SERVICE_PATH, timeout=timeout)
            return rospy.ServiceProxy(SERVICE_PATH, setActivation)(state).success
        except (rospy.ServiceException, rospy.ROSException) as error:
            raise DemoError("%s %s failed: %s" % (SERVICE_PATH, state, error)) from None

    def enable(self) -> None:
        with self._activation_lock:
            if self.stop.is_set():
                raise Interrupted()
            asked = time.time()
            reply = self._activate(ENABLED, SERVICE_CALL_TIMEOUT)
            if reply != REPLY_SUCCESS:
                reason = self._refusal_reason(asked)
                raise DemoError("animateBehaviour refused %r (reply %r): %s" % (ENABLED, reply, reason))
            self._enabled = True

    def disable_if_enabled(self, timeout: float = SERVICE_CALL_TIMEOUT) -> bool:
        """Disable the node when this driver enabled it; True when it was disabled now."""
        with self._activation_lock:
            if not self._enabled:
                return False
            self._enabled = False
            reply = self._activate(DISABLED, timeout)
            if reply != REPLY_SUCCESS:
                raise DemoError("animateBehaviour refused %r (reply %r)" % (DISABLED, reply))
            self.disabled_early = self.stop.is_set()
            return True

    def _refusal_reason(self, since: float) -> str:
        """The problems the node logged for a refused enable, else where to look."""
        if self.setting is None:
            return "see the node's log file"
        try:
            entries = read_log(self.setting.log_file)
        except (OSError, ValueError):
            entries = []
        for entry in reversed(entries):
            if entry.event == contract.CONFIGURATION_INVALID and entry.timestamp.timestamp() >= since - 1.0:
                return "; ".join(str(problem) for problem in entry.fields.get("problems", [])) or "invalid"
        return "see its log %s" % self.setting.log_file

    # -- the run ----------------------------------------------------------------------------------
    def pause(self, seconds: float) -> None:
        if self.stop.wait(max(0.0, seconds)):
            raise Interrupted()

    def wait_for_start(self) -> None:
        deadline = time.monotonic() + self.startup_timeout
        waits = [("the simulated Pepper (/joint_states)", self.window.has_joint_states),
                 ("the animateBehaviour node (its service %s)" % SERVICE_PATH, self._service_answers)
                 ]  # type: List[Tuple[str, Callable[[], bool]]]
        if self.recorder:
            waits.append(("the recorder %s" % self.recorder, lambda: records_the_node(self.recorder)))
        if self._gesture_publisher is not None:
            waits.append(("the gesture player (%s)" % PLAY_TOPIC,
                          lambda: self._gesture_publisher.get_num_connections() > 0))
        for what, ready in waits:
            while not ready():
                if time.monotonic() > deadline:
                    raise DemoError("%s did not start within %.0f s" % (what, self.startup_timeout))
                self.pause(0.1)

    @staticmethod
    def _service_answers() -> bool:
        try:
            rospy.wait_for_service(SERVICE_PATH, timeout=0.2)
            return True
        except rospy.ROSException:
            return False

    def run(self) -> None:
        self.wait_for_start()
        self.pause(REST_BEFORE)
        say("enabling animateBehaviour for %g s (Ctrl-C stops early)" % self.duration)
        self.enable()
        enabled_at = time.monotonic()
        state = ENABLED
        for moment, what in schedule(self.duration, self.tail, self.gesture, self.interaction):
            self.pause(enabled_at + moment - time.monotonic())
            if what == ENGAGED:
                self.engage()
            elif what == DISABLE:
                self.disable_if_enabled()
                state = DISABLED
                say("disabled after %g s; recording %g s more to show the stop" % (self.duration, self.tail))
            elif what == GESTURE:
                self._gesture_publisher.publish(Empty())
            else:
                names, positions, headings, heading = self.window.last(time.time(), 1.0)
                print(status_line(int(moment), state, names, positions, headings, heading, self._yielding),
                      flush=True)


def write_outcome(path: str, status: int, text: str) -> None:
    if not path:
        return
    try:
        with open(path, "w", encoding="utf-8") as outcome:
            outcome.write("%d %s\n" % (status, text))
    except OSError as error:
        say("error: cannot write the outcome file %s: %s" % (path, error))


def main() -> int:
    rospy.init_node(NODE_NAME, disable_signals=True)
    duration = float(rospy.get_param("~duration", 30.0))
    tail = float(rospy.get_param("~tail", 3.0))
    outcome_file = str(rospy.get_param("~outcome_file", ""))
    if not duration > 0.0 or tail < 0.0:
        say("error: ~duration must be positive and ~tail not negative (got %r and %r)" % (duration, tail))
        write_outcome(outcome_file, EXIT_FAILED, "invalid ~duration or ~tail")
        return EXIT_FAILED
    node = "/" + contract.NODE_NAME
    try:
        setting = run_setting(rospy.get_param(node, {}), None)  # type: Optional[RunSetting]
        platform = setting.platform
    except ValueError:
        setting, platform = None, str(rospy.get_param(node + "/platform", "robot"))  # the node says why
    heading_topic = odometry_topic(PLATFORMS[platform if platform in PLATFORMS else "robot"])
    driver = DemoDriver(duration, tail, bool(rospy.get_param("~gesture", False)),
                        str(rospy.get_param("~recorder", "/animateBehaviourRecorder")),
                        float(rospy.get_param("~startup_timeout", 40.0)), setting, heading_topic,
                        bool(rospy.get_param("~interaction", False)))
    signal.signal(signal.SIGINT, driver.on_signal)
    signal.signal(signal.SIGTERM, driver.on_signal)
    rospy.core.add_preshutdown_hook(driver.on_ros_shutdown)
    status, text = EXIT_COMPLETED, "completed"
    try:
        driver.run()
        say("finished; stopping the launch (the recorder writes the plot)")
    except Interrupted:
        status, text = EXIT_INTERRUPTED, "stopped early (%s)" % driver.stop_reason
    except DemoError as error:
        say("error: %s" % error)
        status, text = EXIT_FAILED, str(error)
    try:
        driver.disable_if_enabled(STOP_DISABLE_TIMEOUT)  # never leave it enabled, also after an error
    except DemoError as error:
        say("error: %s" % error)
    if status == EXIT_INTERRUPTED:
        say("%s%s; stopping the launch" % (text, ": animateBehaviour disabled" if driver.disabled_early else ""))
    write_outcome(outcome_file, status, text)
    rospy.signal_shutdown("demo " + text)
    return EXIT_FAILED if status == EXIT_FAILED else 0
