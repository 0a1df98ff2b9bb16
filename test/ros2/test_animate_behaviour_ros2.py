"""animateBehaviour on ROS 2 (cssr_system.ros2.animate_behaviour_main) beside the ROS 2 simulated Pepper, both in
processes of their own, driven by real rclpy clients: the replies, the goals and their bands on both backends
(FollowJointTrajectory and /joint_angles), the stop, yielding to another node's goal or setAngles calls, a live
parameter change, a bad configuration, the animate action, and a log with one final state for every goal sent.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import subprocess
import threading
import time
from pathlib import Path

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")

from builtin_interfaces.msg import Duration  # noqa: E402 (after the skips)
from action_msgs.msg import GoalStatus, GoalStatusArray  # noqa: E402
from control_msgs.action import FollowJointTrajectory  # noqa: E402
from cssr_system_interfaces.action import Animate  # noqa: E402
from cssr_system_interfaces.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system_interfaces.srv import SetActivation  # noqa: E402
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed  # noqa: E402
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue  # noqa: E402
from rcl_interfaces.srv import SetParameters  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, qos_profile_action_status_default  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from std_srvs.srv import SetBool  # noqa: E402
from trajectory_msgs.msg import JointTrajectoryPoint  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.configuration import ConfigurationError, load_configuration  # noqa: E402
from cssr_system.animate_behaviour.event_log import read_log  # noqa: E402
from cssr_system.core.joint_states import REST_DELAY  # noqa: E402
from cssr_system.package_files import data_dir  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402
from cssr_system.ros2.animate_action import RESULT_TIMEOUT  # noqa: E402

from domains import claim_domain  # noqa: E402
from processes import on_executor, start_program, stop_program as stop, wait_until  # noqa: E402

# The trajectory run's domain, the joint-angle run's and the one-off runs': the first two last as long as this module.
DOMAIN, JOINT_ANGLES_DOMAIN, ONE_OFF_DOMAIN = claim_domain(), claim_domain(), claim_domain()
START_TIMEOUT = 20.0  # s; a node starts in 1-2 s, but the machine may be busy
STOP_BOUND = 0.5  # s from the disable request to each part's stop (the ROS 1 tests' bound)
FIRST_GOAL_BOUND = 1.0  # s from the enable request to each part's first goal (the ROS 1 tests' bound)
SIMULATOR_PARTS = {"RArm", "LArm", "Leg"}  # the simulator platform has no hand controllers
ARM = PARTS["RArm"].joints
TEST_CLIENT = "/ros2_test_client"  # the test's node, as the graph names it
# Joints off their centres (0.03 to 0.2 rad, both sides), as another node may leave them, as the ROS 1 ease-in rostests
# start them; every joint enters its band within EASE_IN_BOUND of the enable (README: "Motion styles").
OFF_CENTRE = ("KneePitch=0.0022, HipPitch=-0.2107, HipRoll=0.19234, RShoulderRoll=-0.29664, RElbowRoll=0.50664, "
              "RWristYaw=0.14321, RHand=0.46608")
EASE_IN_BOUND = 3.0  # s


def start(module: str, *parameters: str, domain: int = DOMAIN) -> subprocess.Popen:
    return start_program(module, domain, [word for parameter in parameters for word in ("-p", parameter)])


class Client:
    """A test node of its own context, spun on a thread: the services, the status, /joint_states, the animate
    parameters, a FollowJointTrajectory client and a /joint_angles publisher of 'another node'."""

    def __init__(self, domain: int) -> None:
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node("ros2_test_client", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.status = None
        self.joint_states = []
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.node.create_subscription(AnimateBehaviourStatus, "/animateBehaviour/status", self._on_status, latched)
        self.node.create_subscription(JointState, "/joint_states", self.joint_states.append, 10)
        self.set_activation = self.node.create_client(SetActivation, "/animateBehaviour/setActivation")
        self.set_enabled = self.node.create_client(SetBool, "/animateBehaviour/set_enabled")
        self.set_parameters = self.node.create_client(SetParameters, "/animateBehaviour/set_parameters")
        self.joint_angles = self.node.create_publisher(JointAnglesWithSpeed, "/joint_angles", 10)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def _on_status(self, message) -> None:
        self.status = message

    def call(self, client, request, timeout: float = 5.0):
        assert client.wait_for_service(timeout_sec=START_TIMEOUT), "service %s" % client.srv_name
        future = client.call_async(request)
        assert wait_until(future.done, timeout), "no reply from %s" % client.srv_name
        return future.result()

    def activate(self, state: str) -> str:
        return self.call(self.set_activation, SetActivation.Request(state=state)).success

    def part_state(self, part: str) -> str:
        status = self.status
        return next((row.state for row in status.parts if row.part == part), "") if status is not None else ""

    def node_listens_to_joint_states(self) -> bool:
        """The graph lists the node among /joint_states' subscribers."""
        return any(info.node_name == contract.NODE_NAME
                   for info in self.node.get_subscriptions_info_by_topic("/joint_states"))

    def set_parameter(self, name: str, value):
        if isinstance(value, str):
            typed = ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=value)
        else:
            typed = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=value)
        parameter = Parameter(name=name, value=typed)
        return self.call(self.set_parameters, SetParameters.Request(parameters=[parameter])).results[0]

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


class Run:
    """The simulated Pepper and the node, and a test client; the node's log is read from its file."""

    def __init__(self, tmp: Path, simulator: tuple, node: tuple, domain: int) -> None:
        self.log_file = tmp / "animateBehaviour.log"
        self.simulator = start("cssr_system.ros2.simulated_pepper_node", *simulator, domain=domain)
        self.node = start("cssr_system.ros2.animate_behaviour_main", "logFile:=%s" % self.log_file,
                          "randomSeed:=7", *node, domain=domain)
        self.client = Client(domain)
        assert self.client.set_activation.wait_for_service(timeout_sec=START_TIMEOUT), self.output()
        # Ready when the simulated Pepper publishes and the node has found its controllers (or naoqi_driver).
        assert wait_until(lambda: self.client.joint_states, START_TIMEOUT), self.output(self.simulator)
        assert wait_until(lambda: {entry.fields["part"] for entry in self.entries(contract.CONTROLLER_CONNECTED)}
                          >= SIMULATOR_PARTS, START_TIMEOUT), self.output()

    def entries(self, event: str, since: float = 0.0):
        if not self.log_file.exists():
            return []
        return [entry for entry in read_log(str(self.log_file))
                if entry.event == event and entry.timestamp.timestamp() >= since]

    def output(self, process: subprocess.Popen = None) -> str:
        process = process or self.node
        return "still running" if process.poll() is None else process.communicate()[1]

    def close(self) -> int:
        """Disables the node, then stops both programs, also when the disable fails (no process outlives a test)."""
        try:
            self.client.activate("disabled")
        finally:
            self.client.close()
            status = stop(self.node)
            stop(self.simulator)
        return status


@pytest.fixture(scope="module")
def trajectory_run(tmp_path_factory):
    run = Run(tmp_path_factory.mktemp("trajectory"), ("platform:=simulator",),
              ("platform:=simulator", "behaviour:=all", "yieldQuietTime:=0.5"), DOMAIN)
    yield run
    assert run.close() == 0, "SIGINT: the node stops the robot and exits 0"
    assert run.entries(contract.NODE_STOPPED), "node_stopped in the log"


@pytest.fixture(scope="module")
def joint_angles_run(tmp_path_factory):
    run = Run(tmp_path_factory.mktemp("joint_angles"), ("platform:=robot", "driver:=naoqi_driver",
                                                        "initial_positions:=" + OFF_CENTRE),
              ("platform:=robot", "behaviour:=all", "actuation:=joint_angles", "motionStyle:=breathing",
               "yieldQuietTime:=0.5"), JOINT_ANGLES_DOMAIN)
    yield run
    assert run.close() == 0


def assert_goals_in_bands(run: Run, since: float, parts) -> None:
    goals = [entry for entry in run.entries(contract.GOAL_SENT, since) if entry.fields["purpose"] == "animate"]
    assert {entry.fields["part"] for entry in goals} >= set(parts), goals
    for entry in goals:
        lower, upper = entry.fields["lower"], entry.fields["upper"]
        for row in entry.fields["positions"]:
            assert all(low - 1e-9 <= value <= high + 1e-9 for value, low, high in zip(row, lower, upper)), entry


def test_replies_are_those_of_ros_1(trajectory_run):
    client = trajectory_run.client
    assert client.activate("nonsense") == contract.REPLY_FAILURE
    assert client.activate(" Disabled ") == contract.REPLY_SUCCESS
    reply = client.call(client.set_enabled, SetBool.Request(data=False))
    assert (reply.success, reply.message) == (True, "disabled")


def test_goals_stay_in_their_bands_and_a_disable_stops_every_part_at_once(trajectory_run):
    run, client = trajectory_run, trajectory_run.client
    sent = time.time()
    assert client.activate("enabled") == contract.REPLY_SUCCESS
    assert wait_until(lambda: {entry.fields["part"] for entry in run.entries(contract.GOAL_SENT, sent)}
                      >= SIMULATOR_PARTS, 5.0)
    for part in SIMULATOR_PARTS:
        first = min(entry.timestamp.timestamp() for entry in run.entries(contract.GOAL_SENT, sent)
                    if entry.fields["part"] == part)
        assert first - sent < FIRST_GOAL_BOUND, part
    assert wait_until(lambda: all(client.part_state(part) == "animating" for part in SIMULATOR_PARTS), 3.0)
    moved_from = len(client.joint_states)
    time.sleep(2.0)
    assert_goals_in_bands(run, sent, SIMULATOR_PARTS)
    samples = client.joint_states[moved_from:]
    arm = [dict(zip(message.name, message.position))["RShoulderPitch"] for message in samples]
    assert max(arm) - min(arm) > 0.01, "the arm moves"
    assert wait_until(lambda: not client.node_listens_to_joint_states(), REST_DELAY + 3.0), \
        "while every part runs goals of ours, the node does not listen to /joint_states"
    stopped = time.time()
    assert client.activate("disabled") == contract.REPLY_SUCCESS
    assert wait_until(lambda: {entry.fields["part"] for entry in run.entries(contract.GOAL_SENT, stopped)
                               if entry.fields["purpose"] == "home"} >= SIMULATOR_PARTS, 2.0)
    for entry in run.entries(contract.GOAL_SENT, stopped):
        assert entry.timestamp.timestamp() - stopped < STOP_BOUND, entry
        assert entry.fields["positions"][-1] == pytest.approx(list(PARTS[entry.fields["part"]].centre))
    assert wait_until(lambda: all(client.part_state(part) == "idle" for part in SIMULATOR_PARTS), 4.0)
    count = len(run.entries(contract.GOAL_SENT))
    time.sleep(1.0)
    assert len(run.entries(contract.GOAL_SENT)) == count, "nothing after the return home"


def test_another_clients_goal_is_yielded_to_and_resumed_from(trajectory_run):
    run, client = trajectory_run, trajectory_run.client
    assert client.activate("enabled") == contract.REPLY_SUCCESS
    assert wait_until(lambda: client.part_state("RArm") == "animating", 3.0)
    action = "/pepper/RightArm_controller/follow_joint_trajectory"
    gesture = ActionClient(client.node, FollowJointTrajectory, action)
    assert gesture.wait_for_server(timeout_sec=5.0)
    # The node's goal must have reached the controller first: the controller runs whichever goal it accepts last, so
    # a gesture that overtakes the node's first goal (the node says `animating` as it sends it) is aborted at once,
    # and the node yields only for its quiet time.
    statuses = []
    watch = client.node.create_subscription(GoalStatusArray, action + "/_action/status", statuses.append,
                                            qos_profile_action_status_default)
    assert wait_until(lambda: statuses and any(status.status == GoalStatus.STATUS_EXECUTING
                                               for status in statuses[-1].status_list), 3.0), "the node's goal runs"
    client.executor.create_task(client.node.destroy_subscription, watch)  # not from this thread while it spins
    since = time.time()
    sent = on_executor(client.node, lambda: gesture.send_goal_async(arm_gesture(1)))
    assert wait_until(lambda: client.part_state("RArm") == "yielding", 2.0), "RArm yields"
    assert client.part_state("LArm") == "animating", "the other parts go on"
    assert wait_until(lambda: run.entries(contract.PART_YIELDED, since), 1.0)
    assert wait_until(lambda: client.part_state("RArm") == "animating", 4.0), "RArm resumes"
    assert wait_until(lambda: run.entries(contract.PART_RESUMED, since), 1.0)
    assert sent.done() and sent.result().accepted
    ended = on_executor(client.node, sent.result().get_result_async)
    assert wait_until(ended.done, 1.0) and ended.result().status == GoalStatus.STATUS_SUCCEEDED, "the gesture ran"
    (resumed,) = run.entries(contract.PART_RESUMED, since)
    assert resumed.fields["part"] == "RArm" and resumed.fields["seconds"] >= 1.0
    (yielded,) = run.entries(contract.PART_YIELDED, since)
    assert yielded.fields["caller"] == TEST_CLIENT, "the graph's one other client of that action is named"
    replaced = [entry.fields for entry in run.entries(contract.GOAL_FINISHED, since)
                if entry.fields["part"] == "RArm" and entry.fields["state"] != "SUCCEEDED"]
    assert replaced and all(fields["state"] == "PREEMPTED" and fields["replaced_by"] == TEST_CLIENT
                            for fields in replaced), replaced
    client.node.destroy_client(gesture)
    assert client.activate("disabled") == contract.REPLY_SUCCESS


def arm_gesture(seconds: int) -> FollowJointTrajectory.Goal:
    """Another node's goal: the right arm to its centre in `seconds`, with half a second to settle (the controller
    judges the measured velocity at the end, which a motion that ends at rest still has for a period or two)."""
    goal = FollowJointTrajectory.Goal()
    goal.goal_time_tolerance = Duration(nanosec=500000000)
    goal.trajectory.joint_names = list(ARM)
    goal.trajectory.points = [JointTrajectoryPoint(positions=list(PARTS["RArm"].centre), velocities=[0.0] * 5,
                                                   time_from_start=Duration(sec=seconds))]
    return goal


def test_a_gesture_sent_as_soon_as_disabled_replies_is_not_overtaken_by_the_return_home(trajectory_run):
    """The reply to `disabled` comes once the return goals have left: another node's next goal reaches the controller
    after them, so it replaces them, not they it."""
    run, client = trajectory_run, trajectory_run.client
    action = "/pepper/RightArm_controller/follow_joint_trajectory"
    gesture = ActionClient(client.node, FollowJointTrajectory, action)
    assert gesture.wait_for_server(timeout_sec=5.0)
    for _ in range(3):
        since = time.time()
        assert client.activate("enabled") == contract.REPLY_SUCCESS
        assert wait_until(lambda: client.part_state("RArm") == "animating", 3.0)
        time.sleep(0.5)
        assert client.activate("disabled") == contract.REPLY_SUCCESS
        sent = on_executor(client.node, lambda: gesture.send_goal_async(arm_gesture(1)))
        assert wait_until(sent.done, 3.0) and sent.result().accepted
        ended = on_executor(client.node, sent.result().get_result_async)
        assert wait_until(ended.done, 5.0) and ended.result().status == GoalStatus.STATUS_SUCCEEDED, \
            "the gesture ran to its end"
        homes = [entry.fields for entry in run.entries(contract.GOAL_FINISHED, since)
                 if entry.fields["part"] == "RArm" and entry.fields["purpose"] == "home"]
        assert homes and homes[-1]["state"] == "PREEMPTED", homes
        assert wait_until(lambda: client.part_state("RArm") == "idle", 2.0)
    client.node.destroy_client(gesture)


def test_a_parameter_change_applies_live_and_a_bad_one_is_refused(trajectory_run):
    run, client = trajectory_run, trajectory_run.client
    assert client.activate("enabled") == contract.REPLY_SUCCESS
    since = time.time()
    assert client.set_parameter("intensity", 0.5).successful
    assert wait_until(lambda: client.status.intensity == pytest.approx(0.5) and client.status.enabled, 2.0)
    assert client.status.settings_by == "parameters"
    assert wait_until(lambda: run.entries(contract.SETTING_CHANGED, since), 1.0)
    refused = client.set_parameter("intensity", 1.5)
    assert not refused.successful and "intensity" in refused.reason and "[0, 1]" in refused.reason
    assert client.status.intensity == pytest.approx(0.5), "nothing applied"
    assert client.set_parameter("intensity", 1.0).successful
    assert not client.set_parameter("platform", "robot").successful, "the controllers are named at start-up"
    assert client.activate("disabled") == contract.REPLY_SUCCESS


def test_a_bad_configuration_gives_the_ros_1_line_and_exit_status(tmp_path):
    bad = tmp_path / "bad.ini"
    bad.write_text("platform simulator\nnumPoints 2.5\n")
    with pytest.raises(ConfigurationError) as expected:
        load_configuration(str(bad), {}, data_dir=data_dir())
    process = start("cssr_system.ros2.animate_behaviour_main", "configFile:=%s" % bad,
                    "logFile:=%s" % (tmp_path / "log"))
    _, stderr = process.communicate(timeout=START_TIMEOUT)
    assert process.returncode == 1
    assert stderr.strip().splitlines() == ["animateBehaviour: invalid configuration: %s" % expected.value]


def entered_band(samples, joint: str, lower: float, upper: float) -> float:
    """When `joint` entered [lower, upper] for good, of `samples` (stamp, positions by joint)."""
    outside = [stamp for stamp, positions in samples if not lower - 1e-3 <= positions[joint] <= upper + 1e-3]
    return max(outside, default=samples[0][0])


def test_breathing_through_joint_angles_eases_every_joint_into_its_band_from_off_centre(joint_angles_run):
    run, client = joint_angles_run, joint_angles_run.client
    enabled = time.time()
    assert client.activate("enabled") == contract.REPLY_SUCCESS
    time.sleep(EASE_IN_BOUND + 1.0)
    samples = [(message.header.stamp.sec + 1e-9 * message.header.stamp.nanosec,
                dict(zip(message.name, message.position))) for message in list(client.joint_states)]
    samples = [(stamp, positions) for stamp, positions in samples if stamp >= enabled]
    first_goals = {}
    for entry in run.entries(contract.GOAL_SENT, enabled):
        first_goals.setdefault(entry.fields["part"], entry.fields)
    checked = 0
    for name in [pair.split("=")[0] for pair in OFF_CENTRE.split(", ")]:
        goal = next((fields for fields in first_goals.values() if name in fields["joints"]), None)
        if goal is None or not goal["moving"][goal["joints"].index(name)]:
            continue  # a part or joint the behaviour does not move
        index = goal["joints"].index(name)
        assert entered_band(samples, name, goal["lower"][index], goal["upper"][index]) - enabled <= EASE_IN_BOUND, name
        checked += 1
    assert checked >= 5, first_goals
    assert client.activate("disabled") == contract.REPLY_SUCCESS
    time.sleep(1.0)


def test_joint_angles_stream_in_bands_and_yield_to_another_nodes_calls(joint_angles_run):
    run, client = joint_angles_run, joint_angles_run.client
    sent = time.time()
    assert client.activate("enabled") == contract.REPLY_SUCCESS
    assert wait_until(lambda: run.entries(contract.ANGLES_SENT, sent), 3.0), "setAngles calls streamed"
    assert wait_until(lambda: client.part_state("RArm") == "animating", 3.0)
    time.sleep(1.0)
    assert_goals_in_bands(run, sent, set(PARTS) - {"RHand", "LHand"})
    since = time.time()
    for _ in range(5):  # another node's short stream of calls on the right arm
        client.joint_angles.publish(JointAnglesWithSpeed(joint_names=list(ARM), joint_angles=[1.0, -0.2, 1.2, 0.5, 0.0],
                                                         speed=0.2))
        time.sleep(0.05)
    assert wait_until(lambda: client.part_state("RArm") == "yielding", 2.0), "RArm yields"
    assert client.part_state("LArm") == "animating"
    assert wait_until(lambda: client.part_state("RArm") == "animating", 8.0), "RArm resumes"
    assert [entry.fields["kind"] for entry in run.entries(contract.PART_YIELDED, since)] == ["joint_angles"]
    stopped = time.time()
    assert client.activate("disabled") == contract.REPLY_SUCCESS
    assert wait_until(lambda: {entry.fields["part"] for entry in run.entries(contract.GOAL_SENT, stopped)
                               if entry.fields["purpose"] == "home"} >= {"RArm", "LArm", "Leg"}, 2.0)
    for entry in run.entries(contract.GOAL_SENT, stopped):
        assert entry.timestamp.timestamp() - stopped < STOP_BOUND, entry


def test_sigint_while_animating_returns_every_part_home_before_the_node_exits(tmp_path):
    run = Run(tmp_path, ("platform:=simulator",), ("platform:=simulator", "behaviour:=body"), ONE_OFF_DOMAIN)
    try:
        assert run.client.activate("enabled") == contract.REPLY_SUCCESS
        assert wait_until(lambda: all(run.client.part_state(part) == "animating" for part in SIMULATOR_PARTS), 3.0)
        time.sleep(1.0)
        assert stop(run.node) == 0
        assert_one_final_state_per_goal(run)
        time.sleep(2.5)  # the return home takes at most 2 s
        final = dict(zip(run.client.joint_states[-1].name, run.client.joint_states[-1].position))
        for part in SIMULATOR_PARTS:
            for joint, centre in zip(PARTS[part].joints, PARTS[part].centre):
                assert final[joint] == pytest.approx(centre, abs=0.01), joint
    finally:
        run.client.close()
        stop(run.simulator)


def assert_one_final_state_per_goal(run: Run) -> None:
    """Every goal_sent has exactly one goal_finished; the goals still running at the exit say so."""
    sent = sorted((entry.fields["part"], entry.fields["goal"]) for entry in run.entries(contract.GOAL_SENT))
    finished = sorted((entry.fields["part"], entry.fields["goal"]) for entry in run.entries(contract.GOAL_FINISHED))
    assert sent and finished == sent
    at_exit = [entry.fields for entry in run.entries(contract.GOAL_FINISHED) if entry.fields["state"] ==
               "RUNNING_AT_EXIT"]
    assert {fields["purpose"] for fields in at_exit} >= {"home"}, "the returns home outlast the node"


def animate_goal(**fields) -> Animate.Goal:
    goal = Animate.Goal()
    for name, value in fields.items():
        setattr(goal, name, value)
    return goal


class AnimateClient:
    """An animate action client of the test node: each goal's handle, feedback and result."""

    def __init__(self, client: Client) -> None:
        self.node = client.node
        self.action = ActionClient(client.node, Animate, "/animateBehaviour/animate")
        assert self.action.wait_for_server(timeout_sec=START_TIMEOUT)
        self.feedback = []

    def send(self, goal: Animate.Goal):
        future = on_executor(self.node,
                             lambda: self.action.send_goal_async(goal, feedback_callback=self.feedback.append))
        assert wait_until(future.done, 5.0), "no answer to the goal"
        return future.result()

    def result(self, handle, timeout: float = 10.0):
        future = on_executor(self.node, handle.get_result_async)
        assert wait_until(future.done, timeout), "no result"
        return future.result()

    def close(self) -> None:
        self.node.destroy_client(self.action)


def test_an_animate_goal_with_a_duration_succeeds_with_every_part_home_and_the_base_kept_on(trajectory_run):
    run, client = trajectory_run, trajectory_run.client
    animate = AnimateClient(client)
    since = time.time()
    handle = animate.send(animate_goal(intensity=0.6, duration=4.0))
    assert handle.accepted
    assert wait_until(lambda: client.status.enabled, 2.0)
    assert "base" in client.status.moving_parts, "a goal that names no part moves every part, the base too"
    response = animate.result(handle)
    assert (response.status, response.result.reason) == (GoalStatus.STATUS_SUCCEEDED, "duration elapsed")
    assert response.result.animated == pytest.approx(4.0, abs=0.3), "on time (core/session.py)"
    assert all(client.part_state(part) == "idle" for part in SIMULATOR_PARTS), "every part home"
    assert len(animate.feedback) >= 3, "feedback once a second"
    assert {row.part for row in animate.feedback[-1].feedback.parts} >= SIMULATOR_PARTS
    assert [entry.fields for entry in run.entries(contract.SETTING_CHANGED, since)
            if entry.fields["key"] == "turnBase"] == [], "the base was never mentioned: it stays on"
    animate.close()


def test_a_new_goal_replaces_the_last_and_a_cancel_stops_the_robot(trajectory_run):
    client = trajectory_run.client
    animate = AnimateClient(client)
    first = animate.send(animate_goal(intensity=1.0))
    assert wait_until(lambda: client.part_state("RArm") == "animating", 3.0)
    second = animate.send(animate_goal(intensity=0.5, parts=["arms", "leg"]))
    replaced = animate.result(first)
    assert (replaced.status, replaced.result.reason) == (GoalStatus.STATUS_ABORTED, "replaced")
    assert wait_until(lambda: client.status.intensity == pytest.approx(0.5), 2.0), "the last command wins"
    assert sorted(client.status.moving_parts) == ["arms", "leg"]
    time.sleep(1.5)
    assert client.part_state("RArm") == "animating", "the robot did not stop at the switch"
    on_executor(client.node, second.cancel_goal_async)
    cancelled = animate.result(second)
    assert (cancelled.status, cancelled.result.reason) == (GoalStatus.STATUS_CANCELED, "cancelled")
    assert wait_until(lambda: not client.status.enabled, 1.0)
    third = animate.send(animate_goal(intensity=0.5))
    assert wait_until(lambda: client.status.enabled, 2.0)
    assert client.activate("disabled") == contract.REPLY_SUCCESS
    disabled = animate.result(third)
    assert (disabled.status, disabled.result.reason) == (GoalStatus.STATUS_ABORTED, "disabled")
    animate.close()


def test_an_animate_goal_with_a_bad_value_is_rejected_and_changes_nothing(trajectory_run):
    run, client = trajectory_run, trajectory_run.client
    animate = AnimateClient(client)
    for goal in (animate_goal(intensity=1.5), animate_goal(intensity=0.5, parts=["head"]),
                 animate_goal(intensity=0.5, duration=-1.0)):
        assert not animate.send(goal).accepted, goal
    assert not client.status.enabled and run.node.poll() is None
    animate.close()


def test_an_ended_animate_goal_leaves_the_actions_status_after_its_result_timeout(trajectory_run):
    # Each status message lists every goal the server keeps: kept rclpy's default 900 s, a quarter of an hour of them.
    # rcl_action (Jazzy) expires a goal RESULT_TIMEOUT after its acceptance, at its expiry timer's next call, which
    # may come one period later: twice RESULT_TIMEOUT at most.
    client = trajectory_run.client
    listed = []  # the goals each status message lists
    client.node.create_subscription(GoalStatusArray, "/animateBehaviour/animate/_action/status",
                                    lambda message: listed.append(len(message.status_list)),
                                    qos_profile_action_status_default)
    animate = AnimateClient(client)
    ended = animate.send(animate_goal(intensity=0.5, duration=1.0))
    assert animate.result(ended).status == GoalStatus.STATUS_SUCCEEDED
    time.sleep(2 * RESULT_TIMEOUT)
    since = len(listed)
    last = animate.send(animate_goal(intensity=0.5))
    assert wait_until(lambda: len(listed) > since, 2.0), "a status since the last goal"
    assert max(listed[since:]) == 1, "a goal that ended %g s ago is still listed" % (2 * RESULT_TIMEOUT)
    on_executor(client.node, last.cancel_goal_async)
    assert animate.result(last).status == GoalStatus.STATUS_CANCELED
    animate.close()
