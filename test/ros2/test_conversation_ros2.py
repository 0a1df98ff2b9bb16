"""The modes following the conversation on ROS 2 (README: "Modes"): a stand-in speech node's Bool topic puts the robot
into listening, its action's active goal (the successor's `/tts`, here of the node's own action type: only its status
is read) into speaking, each within a goal period, spliced without a stop or a velocity jump; speaking wins; a
speaking topic whose node dies falls back to idle after the time-out; a part still yields while speaking. Against the
node beside the ROS 2 simulated Pepper on the simulator platform.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2/test_conversation_ros2.py -q
"""
import subprocess
import sys
import threading
import time

import numpy
import pytest

rclpy = pytest.importorskip("rclpy")

from cssr_system_interfaces.action import Animate  # noqa: E402 (after the skip)
from cssr_system_interfaces.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system_interfaces.srv import SetActivation  # noqa: E402
from rclpy.action import ActionServer  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import MultiThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from std_msgs.msg import Bool  # noqa: E402
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402

from domains import claim_domain  # noqa: E402
from processes import environment, start_program, stop_program, wait_until  # noqa: E402

DOMAIN = claim_domain()
START_TIMEOUT = 20.0  # s
SWITCH_TIME = 1.0  # s: a goal period of the shipped random style (gestureDuration 1 s)
TIMEOUT = 1.5  # s: the node's conversationTimeout here
JUMP_ACCELERATION = 30.0  # rad/s^2 between samples: a velocity jump (test/conversation_rostest.py)
MOVING = ("RArm", "LArm", "Leg")
SPEAKER = """
import rclpy, std_msgs.msg
rclpy.init()
node = rclpy.create_node("speaker")
publisher = node.create_publisher(std_msgs.msg.Bool, "/speaking", 10)
node.create_timer(2.0, lambda: publisher.publish(std_msgs.msg.Bool(data=True)))
publisher.publish(std_msgs.msg.Bool(data=True))
rclpy.spin(node)
"""


class Speech:
    """The stand-in speech node: the listening topic, the tts action (speaks until told to stop); and what the test
    watches: the node's status and /joint_states."""

    def __init__(self) -> None:
        self.context = Context()
        rclpy.init(context=self.context, domain_id=DOMAIN)
        self.node = Node("speech", context=self.context)
        self.executor = MultiThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.lock = threading.Lock()
        self.statuses, self.samples = [], []
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.node.create_subscription(AnimateBehaviourStatus, "/animateBehaviour/status", self._on_status, latched)
        self.node.create_subscription(JointState, "/joint_states", self._on_joint_states, 100)
        self.listening = self.node.create_publisher(Bool, "/listening", 10)
        self.gesture = self.node.create_publisher(JointTrajectory, "/pepper/RightArm_controller/joint_trajectory", 1)
        self.set_activation = self.node.create_client(SetActivation, "/animateBehaviour/setActivation")
        self.done_speaking = threading.Event()
        self.speaking_since = None  # when the tts goal began to execute (the action's status says so then)
        self.tts = ActionServer(self.node, Animate, "/tts", self._speak)
        threading.Thread(target=self.executor.spin, daemon=True).start()

    def _speak(self, handle):
        self.speaking_since = time.monotonic()
        self.done_speaking.wait(20.0)
        self.done_speaking.clear()
        handle.succeed()
        return Animate.Result()

    def _on_status(self, message) -> None:
        with self.lock:
            self.statuses.append((time.monotonic(), message))

    def _on_joint_states(self, message) -> None:
        stamp = message.header.stamp.sec + message.header.stamp.nanosec * 1e-9
        with self.lock:
            self.samples.append((time.monotonic(), stamp, dict(zip(message.name, message.velocity))))

    def activate(self, state: str) -> str:
        future = self.set_activation.call_async(SetActivation.Request(state=state))
        assert wait_until(future.done, 5.0)
        return future.result().success

    def mode_at(self, mode: str, since: float, within: float):
        """The first status after `since` naming `mode`, if it came within `within` s."""
        def seen():
            with self.lock:
                return [(at, status) for at, status in self.statuses if at >= since and status.mode == mode]
        assert wait_until(seen, within + 0.5), "the mode never became %s" % mode
        at, status = seen()[0]
        assert at - since <= within, "%s after %.2f s" % (mode, at - since)
        return status

    def latest(self):
        with self.lock:
            return self.statuses[-1][1]

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


@pytest.fixture(scope="module")
def speech(tmp_path_factory):
    log_file = tmp_path_factory.mktemp("conversation") / "animateBehaviour.log"
    simulator = start_program("cssr_system.ros2.simulated_pepper_node", DOMAIN,
                              ["-p", "platform:=simulator", "-p", "velocity_report:=commanded"])
    node = start_program("cssr_system.ros2.animate_behaviour_main", DOMAIN,
                         ["-p", "platform:=simulator", "-p", "behaviour:=body", "-p", "logFile:=%s" % log_file,
                          "-p", "listeningTopic:=listening", "-p", "speakingTopic:=speaking",
                          "-p", "speakingAction:=tts", "-p", "conversationTimeout:=%g" % TIMEOUT])
    speech = Speech()
    assert speech.set_activation.wait_for_service(timeout_sec=START_TIMEOUT)
    yield speech
    speech.close()
    assert stop_program(node) == 0
    stop_program(simulator)


def assert_smooth_and_animating(speech: Speech, start: float) -> None:
    with speech.lock:
        window = [(stamp, velocities) for at, stamp, velocities in speech.samples if at >= start]
        states = {row.state for at, status in speech.statuses if at >= start for row in status.parts
                  if row.part in MOVING}
    steps = numpy.maximum(numpy.diff([stamp for stamp, _ in window]), 1e-3)
    for name in [joint for part in MOVING for joint in PARTS[part].joints]:
        velocities = numpy.array([sample[name] for _, sample in window])
        assert (numpy.abs(numpy.diff(velocities)) / steps).max() <= JUMP_ACCELERATION, name
    assert states == {"animating"}, "no part stopped"


def test_a_topic_and_an_actions_status_set_the_mode_within_a_goal_period(speech):
    assert speech.activate("enabled") == contract.REPLY_SUCCESS
    time.sleep(2.0)
    start = time.monotonic()
    speech.listening.publish(Bool(data=True))
    assert speech.mode_at("listening", start, SWITCH_TIME).mode_by == "listeningTopic /listening"
    client_goal = subprocess.Popen(  # the speech node's own client: a goal on /tts
        [sys.executable, "-c", "import rclpy, rclpy.action, cssr_system_interfaces.action as a; rclpy.init(); "
         "n = rclpy.create_node('say'); c = rclpy.action.ActionClient(n, a.Animate, '/tts'); "
         "c.wait_for_server(); f = c.send_goal_async(a.Animate.Goal()); rclpy.spin_until_future_complete(n, f)"],
        env=environment(DOMAIN))
    assert client_goal.wait(20.0) == 0 and speech.speaking_since is not None
    # From the goal's start on the speech node (rclpy publishes the status just before it runs the goal): the client
    # program's own start-up (seconds on a busy machine) is not the node's.
    since = speech.speaking_since - 0.05
    assert speech.mode_at("speaking", since, SWITCH_TIME + 0.05).mode_by == "speakingAction /tts"
    for _ in range(3):  # listening goes on: speaking wins
        speech.listening.publish(Bool(data=True))
        time.sleep(0.5)
    assert speech.latest().mode == "speaking"
    ended = time.monotonic()
    speech.done_speaking.set()
    speech.mode_at("listening", ended, SWITCH_TIME)
    quiet = time.monotonic()
    speech.listening.publish(Bool(data=False))
    speech.mode_at("idle", quiet, SWITCH_TIME)
    time.sleep(1.0)
    assert_smooth_and_animating(speech, start)


def test_a_speaking_topic_whose_node_dies_falls_back_to_idle_and_parts_still_yield(speech):
    # From idle (a speech goal left running by a failed test above ends within 20 s).
    assert wait_until(lambda: speech.latest().mode == "idle", 25.0)
    assert speech.activate("enabled") == contract.REPLY_SUCCESS
    speaker = subprocess.Popen([sys.executable, "-c", SPEAKER], env=environment(DOMAIN))
    try:
        speech.mode_at("speaking", time.monotonic(), 10.0)
        point = JointTrajectoryPoint(positions=list(PARTS["RArm"].centre))
        point.time_from_start.sec = 2
        speech.gesture.publish(JointTrajectory(joint_names=list(PARTS["RArm"].joints), points=[point]))
        assert wait_until(lambda: {row.part: row.state for row in speech.latest().parts}["RArm"] == "yielding", 2.0)
    finally:
        speaker.terminate()
        speaker.wait(10.0)
    died = time.monotonic()
    assert speech.mode_at("idle", died, TIMEOUT + 1.0).mode_by == "speakingTopic /speaking silent"
    assert speech.activate("disabled") == contract.REPLY_SUCCESS
