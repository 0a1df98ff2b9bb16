"""The ROS 2 simulated Pepper (cssr_system.ros2.simulated_pepper_node) over real rclpy, in processes of its own.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python -m pytest test/ros2 -q
Skipped where rclpy or the interface packages cannot be imported (ROS 1). Each node under test runs on a
ROS_DOMAIN_ID of this test's own, discovered on this machine only, so parallel runs do not meet.
"""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("control_msgs.action")
pytest.importorskip("naoqi_bridge_msgs.msg")

from action_msgs.msg import GoalStatus, GoalStatusArray  # noqa: E402 (after the skips)
from builtin_interfaces.msg import Duration  # noqa: E402
from control_msgs.action import FollowJointTrajectory  # noqa: E402
from control_msgs.msg import JointTolerance, JointTrajectoryControllerState  # noqa: E402
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from std_msgs.msg import UInt32  # noqa: E402
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint  # noqa: E402

from domains import claim_domain  # noqa: E402

SRC = Path(__file__).resolve().parents[2] / "src"
MODULE = "cssr_system.ros2.simulated_pepper_node"
# Two nodes under test at most at a time, on domains of their own.
DOMAIN, SECOND_DOMAIN = claim_domain(), claim_domain()
START_TIMEOUT = 20.0  # s; a node starts in 1-2 s, but the machine may be busy
EXIT_TIMEOUT = 15.0
RESULT_TIMEOUT = 10.0
FIRST_ANSWER_TIMEOUT = 2.0  # s a client's first goal waits for its answer before it is sent again

NAMESPACE = "/pepper"  # the simulator platform's
ARM = ("RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw")
LEFT_ARM = ("LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll", "LWristYaw")
LEG = ("HipRoll", "HipPitch", "KneePitch")
HEAD = ("HeadYaw", "HeadPitch")
SERVERS = ("RightArm_controller", "LeftArm_controller", "Pelvis_controller", "Head_controller")


def node_environment(domain: int) -> dict:
    environment = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                       PYTHONUNBUFFERED="1")
    # The working tree's package, ahead of any installed copy.
    environment["PYTHONPATH"] = os.pathsep.join(filter(None, (str(SRC), os.environ.get("PYTHONPATH"))))
    return environment


def start_node(domain: int, *parameters: str) -> subprocess.Popen:
    command = [sys.executable, "-m", MODULE, "--ros-args"]
    for parameter in parameters:
        command += ["-p", parameter]
    return subprocess.Popen(command, env=node_environment(domain), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def stop_node(process: subprocess.Popen, signum: int = signal.SIGINT):
    """Signal the node and wait for it: (exit status, stdout, stderr); killed if it does not end."""
    if process.poll() is None:
        process.send_signal(signum)
    try:
        out, err = process.communicate(timeout=EXIT_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        out, err = process.communicate()
        return None, out, err
    return process.returncode, out, err


def wait_until_serving(process: subprocess.Popen, peer, controllers, namespace: str = NAMESPACE):
    """Every controller's action server is up; a node that ended instead fails the test with its last words."""
    deadline = time.monotonic() + START_TIMEOUT
    for controller in controllers:
        client = ActionClient(peer.node, FollowJointTrajectory,
                              "{}/{}/follow_joint_trajectory".format(namespace, controller))
        while not client.server_is_ready():
            if process.poll() is not None:
                pytest.fail("the node ended with status {}: {}".format(
                    process.returncode, process.stderr.read().strip()[-2000:]))
            assert time.monotonic() < deadline, "timed out waiting for " + controller
            peer.executor.spin_once(timeout_sec=0.05)
        peer.clients[controller] = client


def duration(seconds: float) -> Duration:
    return Duration(sec=int(seconds), nanosec=int(round((seconds % 1.0) * 1e9)))


def trajectory_goal(joints, target, seconds, path_tolerance=()):
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.points = [JointTrajectoryPoint(positions=list(target), velocities=[0.0] * len(target),
                                                   time_from_start=duration(seconds))]
    goal.path_tolerance = list(path_tolerance)
    return goal


class Peer:
    """A client node on one domain, spun by the test itself (one thread: no race with the client's futures)."""

    def __init__(self, domain: int):
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node("simulated_pepper_test", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.joint_states = []  # (arrival time, message)
        self.node.create_subscription(JointState, "/joint_states", self._store_joint_state, 50)
        self.clients = {}
        self.answered = set()  # the controllers that have answered a goal of this peer

    def _store_joint_state(self, message):
        self.joint_states.append((time.monotonic(), message))
        del self.joint_states[:-100]

    def close(self):
        self.executor.shutdown(timeout_sec=1.0)
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)

    def spin_until(self, condition, timeout: float, what: str):
        deadline = time.monotonic() + timeout
        while not condition():
            assert time.monotonic() < deadline, "timed out after {} s waiting for {}".format(timeout, what)
            self.executor.spin_once(timeout_sec=0.02)
        return condition()

    def spin_for(self, seconds: float):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)

    def client(self, controller: str) -> ActionClient:
        if controller not in self.clients:
            client = ActionClient(self.node, FollowJointTrajectory,
                                  "{}/{}/follow_joint_trajectory".format(NAMESPACE, controller))
            self.spin_until(client.server_is_ready, START_TIMEOUT, controller + "'s action server")
            self.clients[controller] = client
        return self.clients[controller]

    def send(self, controller: str, goal):
        future = self.client(controller).send_goal_async(goal)
        if controller not in self.answered:
            # Just after discovery, a server may answer before it has found this client's reader of answers, and the
            # answer is lost: a first goal left unanswered is sent again (if it was taken, the second replaces it).
            answer_by = time.monotonic() + FIRST_ANSWER_TIMEOUT
            self.spin_until(lambda: future.done() or time.monotonic() > answer_by, RESULT_TIMEOUT, "an answer")
            if not future.done():
                future = self.clients[controller].send_goal_async(goal)
        self.spin_until(future.done, RESULT_TIMEOUT, "the goal's acceptance")
        self.answered.add(controller)
        return future.result()

    def result(self, goal_handle):
        future = goal_handle.get_result_async()
        self.spin_until(future.done, RESULT_TIMEOUT, "the goal's result")
        return future.result()

    def positions(self, joints, after: float = None):
        """The joints' positions in the first /joint_states message that arrives after `after` (default: now)."""
        after = time.monotonic() if after is None else after
        self.spin_until(lambda: self.joint_states and self.joint_states[-1][0] > after, 5.0, "/joint_states")
        message = next(message for arrival, message in self.joint_states if arrival > after)
        by_name = dict(zip(message.name, message.position))
        return [by_name[joint] for joint in joints]

    def reaches(self, joints, target, timeout: float = 3.0, tolerance: float = 1e-3) -> bool:
        def there():
            self.executor.spin_once(timeout_sec=0.02)
            return all(abs(a - b) <= tolerance for a, b in zip(self.positions(joints), target))
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if there():
                return True
        return False


@pytest.fixture(scope="module")
def discovery_on_this_machine():
    previous = os.environ.get("ROS_AUTOMATIC_DISCOVERY_RANGE")
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    yield
    if previous is None:
        del os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"]
    else:
        os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = previous


@pytest.fixture(scope="module")
def pepper(discovery_on_this_machine):
    """The simulator platform, ideal driver; goals end at rest within 0.5 s of the trajectory's end."""
    process = start_node(DOMAIN, "platform:=simulator", "goal_time:=0.5")
    peer = Peer(DOMAIN)
    try:
        wait_until_serving(process, peer, SERVERS)
        yield process, peer
    finally:
        peer.close()
        stop_node(process)


def test_every_controller_of_the_platform_serves_its_action(pepper):
    _, peer = pepper
    for controller in SERVERS:
        assert peer.client(controller).server_is_ready()


def test_a_goal_succeeds_and_the_joints_reach_its_last_point(pepper):
    _, peer = pepper
    target = (1.0, -0.4, 0.6, 1.2, 0.3)
    handle = peer.send("RightArm_controller", trajectory_goal(ARM, target, 0.6))
    assert handle.accepted
    response = peer.result(handle)
    assert response.status == GoalStatus.STATUS_SUCCEEDED
    assert response.result.error_code == FollowJointTrajectory.Result.SUCCESSFUL
    assert peer.positions(ARM) == pytest.approx(target, abs=1e-6)


def test_a_new_goal_replaces_the_running_one_which_ends_aborted(pepper):
    _, peer = pepper
    first = peer.send("LeftArm_controller", trajectory_goal(LEFT_ARM, (1.0, 0.5, -1.0, -0.5, 0.2), 3.0))
    peer.spin_for(0.3)
    second_target = (0.5, 0.3, -0.5, -0.3, 0.0)
    second = peer.send("LeftArm_controller", trajectory_goal(LEFT_ARM, second_target, 0.6))
    assert first.accepted and second.accepted
    replaced = peer.result(first)
    # As ros2_controllers' joint_trajectory_controller since Jazzy: aborted, INVALID_GOAL, "preempted".
    assert replaced.status == GoalStatus.STATUS_ABORTED
    assert replaced.result.error_code == FollowJointTrajectory.Result.INVALID_GOAL
    assert "preempted" in replaced.result.error_string
    response = peer.result(second)
    assert response.status == GoalStatus.STATUS_SUCCEEDED
    assert peer.positions(LEFT_ARM) == pytest.approx(second_target, abs=1e-6)


def test_a_goal_naming_an_unknown_joint_is_rejected(pepper):
    _, peer = pepper
    handle = peer.send("Head_controller", trajectory_goal(("HeadYaw", "Nose"), (0.1, 0.1), 0.5))
    assert not handle.accepted


def test_a_cancel_stops_the_joints_and_the_goal_ends_canceled(pepper):
    _, peer = pepper
    target = (0.3, -0.8, 0.3)
    handle = peer.send("Pelvis_controller", trajectory_goal(LEG, target, 3.0))
    peer.spin_for(0.5)
    future = handle.cancel_goal_async()
    peer.spin_until(future.done, RESULT_TIMEOUT, "the cancel response")
    assert len(future.result().goals_canceling) == 1
    response = peer.result(handle)
    assert response.status == GoalStatus.STATUS_CANCELED
    peer.spin_for(0.1)  # the hardware reports a control period behind
    held = peer.positions(LEG)
    peer.spin_for(0.3)
    assert peer.positions(LEG) == pytest.approx(held, abs=1e-9)
    assert abs(held[1] - target[1]) > 0.1  # stopped on the way


def test_a_goal_the_model_judges_off_its_path_aborts_with_the_models_error(pepper):
    _, peer = pepper
    tight = [JointTolerance(name="HeadYaw", position=1e-6)]  # the hardware reports a period behind
    handle = peer.send("Head_controller", trajectory_goal(HEAD, (0.8, 0.2), 1.0, tight))
    response = peer.result(handle)
    assert response.status == GoalStatus.STATUS_ABORTED
    assert response.result.error_code == FollowJointTrajectory.Result.PATH_TOLERANCE_VIOLATED
    assert response.result.error_string.startswith("HeadYaw path error")


def test_the_joint_trajectory_topic_moves_the_controllers_joints(pepper):
    _, peer = pepper
    publisher = peer.node.create_publisher(JointTrajectory, NAMESPACE + "/Head_controller/joint_trajectory", 10)
    peer.spin_until(lambda: publisher.get_subscription_count() > 0, START_TIMEOUT, "the joint_trajectory subscriber")
    target = (-0.5, -0.1)
    publisher.publish(JointTrajectory(joint_names=list(HEAD), points=[
        JointTrajectoryPoint(positions=list(target), time_from_start=duration(0.3))]))
    assert peer.reaches(HEAD, target)


# The fields of ros-controls/control_msgs' JointTrajectoryControllerState (jazzy branch, 5.x; the same in 6.x): the
# same names and types give the same type on the wire, so a recorder of the real controller reads ours.
CONTROLLER_STATE_FIELDS = dict(
    header="std_msgs/Header", joint_names="sequence<string>",
    **{name: "trajectory_msgs/JointTrajectoryPoint" for name in ("reference", "feedback", "error", "output")},
    multi_dof_joint_names="sequence<string>",
    **{"multi_dof_" + name: "trajectory_msgs/MultiDOFJointTrajectoryPoint"
       for name in ("reference", "feedback", "error", "output")},
    speed_scaling_factor="double")


def test_each_controller_publishes_its_reference_as_joint_trajectory_controller_does(pepper):
    assert JointTrajectoryControllerState.get_fields_and_field_types() == CONTROLLER_STATE_FIELDS
    _, peer = pepper
    states = []
    peer.node.create_subscription(JointTrajectoryControllerState, NAMESPACE + "/Pelvis_controller/controller_state",
                                  states.append, 50)
    peer.spin_until(lambda: states, START_TIMEOUT, "the controller's state")
    start = states[-1].reference.positions[LEG.index("HipPitch")]
    target = (0.0, start - 0.2, 0.0)
    peer.result(peer.send("Pelvis_controller", trajectory_goal(LEG, target, 0.5)))
    peer.spin_for(0.2)
    state = states[-1]
    assert tuple(state.joint_names) == LEG and state.speed_scaling_factor == 1.0
    assert tuple(state.reference.positions) == pytest.approx(target, abs=1e-9)
    passed = [message.reference.positions[1] for message in states if target[1] < message.reference.positions[1]
              < start - 0.01]
    assert len(passed) >= 10, "the reference moves with the trajectory, at every update (50 Hz)"
    for message in states:
        assert list(message.error.positions) == pytest.approx(
            [reference - feedback for reference, feedback in zip(message.reference.positions,
                                                                 message.feedback.positions)], abs=1e-12)
    stamps = [message.header.stamp.sec + message.header.stamp.nanosec * 1e-9 for message in states]
    assert stamps == sorted(stamps)


def test_limit_violations_are_latched(pepper):
    _, peer = pepper
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    counts = []
    peer.node.create_subscription(UInt32, "/simulatedPepper/limit_violations", lambda m: counts.append(m.data),
                                  latched)
    peer.spin_until(lambda: counts, START_TIMEOUT, "the latched limit_violations")
    handle = peer.send("Head_controller", trajectory_goal(HEAD, (3.0, 0.0), 0.3))  # HeadYaw's limit: 2.08567
    peer.result(handle)
    peer.spin_until(lambda: counts[-1] == 1, 5.0, "one limit violation")


def test_sigint_aborts_the_running_goal_and_exits_cleanly(pepper):
    process, peer = pepper
    handle = peer.send("RightArm_controller", trajectory_goal(ARM, (0.0, -0.2, 0.0, 0.5, 0.0), 10.0))
    future = handle.get_result_async()
    peer.spin_for(0.3)
    status, out, err = stop_node(process, signal.SIGINT)
    assert status == 0, err
    assert "Traceback" not in out + err
    peer.spin_until(future.done, RESULT_TIMEOUT, "the running goal's result")
    assert future.result().status == GoalStatus.STATUS_ABORTED


def test_with_naoqi_driver_joint_angles_move_the_joints_and_sigterm_ends_it(discovery_on_this_machine):
    domain = SECOND_DOMAIN
    process = start_node(domain, "platform:=robot", "driver:=naoqi_driver")
    peer = Peer(domain)
    try:
        wait_until_serving(process, peer, ("Head_controller",), namespace="/pepper_dcm")
        publisher = peer.node.create_publisher(JointAnglesWithSpeed, "/joint_angles", 10)
        peer.spin_until(lambda: publisher.get_subscription_count() > 0, START_TIMEOUT, "the /joint_angles subscriber")
        publisher.publish(JointAnglesWithSpeed(joint_names=["HeadYaw", "LShoulderPitch"], joint_angles=[0.5, 1.0],
                                               speed=0.5))
        assert peer.reaches(("HeadYaw", "LShoulderPitch"), (0.5, 1.0), tolerance=1e-5)
    finally:
        peer.close()
        status, out, err = stop_node(process, signal.SIGTERM)
    assert status == 0, err
    assert "Traceback" not in out + err


def test_a_finished_goal_leaves_the_controllers_status_after_the_result_timeout(discovery_on_this_machine):
    # Each status message lists every goal the server keeps: kept for 900 s, a busy controller's list would grow to
    # hundreds of goals, which each client decodes at every change.
    process = start_node(SECOND_DOMAIN, "platform:=simulator", "goal_time:=0.5", "result_timeout:=1.0")
    peer = Peer(SECOND_DOMAIN)
    listed = []  # the goals each status message lists
    status_qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)  # rcl_action's status profile
    status_topic = NAMESPACE + "/Head_controller/follow_joint_trajectory/_action/status"
    peer.node.create_subscription(GoalStatusArray, status_topic,
                                  lambda message: listed.append(len(message.status_list)), status_qos)
    try:
        wait_until_serving(process, peer, ("Head_controller",))
        first = peer.send("Head_controller", trajectory_goal(HEAD, (0.1, 0.1), 0.2))
        assert peer.result(first).status == GoalStatus.STATUS_SUCCEEDED
        peer.spin_for(2.0)
        second = peer.send("Head_controller", trajectory_goal(HEAD, (0.0, 0.0), 0.2))
        assert peer.result(second).status == GoalStatus.STATUS_SUCCEEDED
        peer.spin_until(lambda: listed and listed[-1] == 1, 5.0, "a status listing the second goal alone")
        assert max(listed) == 1
    finally:
        peer.close()
        stop_node(process)


@pytest.mark.parametrize("parameter, expected", [
    ("platform:=mars", "platform must be one of robot, simulator (got 'mars')"),
    ("feedback_rate:=fast", "feedback_rate must be a finite number >= 0 (got 'fast')"),
    ("result_timeout:=0.0", "result_timeout must be a finite number > 0 (got 0.0)"),
])
def test_a_bad_parameter_value_exits_1_with_one_line(parameter, expected):
    process = start_node(SECOND_DOMAIN, parameter)
    try:
        out, err = process.communicate(timeout=START_TIMEOUT)
    finally:
        if process.poll() is None:
            process.kill()
    lines = [line for line in (out + err).splitlines() if line.strip()]
    assert process.returncode == 1
    assert len(lines) == 1, lines
    assert expected in lines[0]
