"""Several robots on one ROS 2 graph (README: "Several robots"): two simulated Peppers and two animateBehaviour nodes
in /robot1 and /robot2 (`-r __ns:=`), with the shipped files; robot2's node is renamed (`-r __node:=`) and robot1's
right arm controller is remapped, on its simulated Pepper and its node alike. Both nodes are asked for one log file.
Asserts that enabling one robot moves only it, that with both enabled neither yields to the other, that disabling
one leaves the other animating, that a renamed node's service is under its new name, that the two nodes never write
into one log file, and that the remapped arm still yields to another node's goal, which succeeds.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import threading
import time

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")

from action_msgs.msg import GoalStatus  # noqa: E402 (after the skips)
from builtin_interfaces.msg import Duration  # noqa: E402
from control_msgs.action import FollowJointTrajectory  # noqa: E402
from cssr_system_interfaces.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system_interfaces.srv import SetActivation  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from trajectory_msgs.msg import JointTrajectoryPoint  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.event_log import node_log_file_name, read_log  # noqa: E402
from cssr_system.pepper.joint_table import PARTS, centre_of  # noqa: E402
from cssr_system.recording.robot_watch import RobotWatch  # noqa: E402
from domains import claim_domain  # noqa: E402
from processes import on_executor, start_program, stop_program, wait_until  # noqa: E402

DOMAIN = claim_domain()
NODES = {"robot1": "/robot1/animateBehaviour", "robot2": "/robot2/animateRobot2"}
ARM_REMAP = "pepper_dcm/RightArm_controller/follow_joint_trajectory:=right_arm/follow_joint_trajectory"
REMAPPED_ARM = "/robot1/right_arm/follow_joint_trajectory"
START_TIMEOUT = 30.0  # s: four programs start and find each other
MOVED = 0.005  # rad: a joint that travelled more than this moved
WATCH = 3.0  # s of motion looked at per step
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class Robot(RobotWatch):
    """One robot's joints and node status as seen from outside, on the test client's node."""

    def __init__(self, node: Node, name: str) -> None:
        super().__init__()
        self.name, self.node_name = name, NODES[name]
        node.create_subscription(JointState, "/%s/joint_states" % name,
                                 lambda message: self.joint_states(message.name, message.position), 50)
        node.create_subscription(AnimateBehaviourStatus, contract.interface_of(self.node_name, contract.STATUS),
                                 self.status, LATCHED)
        self.set_activation = node.create_client(SetActivation, contract.interface_of(self.node_name,
                                                                                      contract.SET_ACTIVATION))

    def activate(self, state: str) -> str:
        assert self.set_activation.wait_for_service(timeout_sec=START_TIMEOUT), self.set_activation.srv_name
        future = self.set_activation.call_async(SetActivation.Request(state=state))
        assert wait_until(future.done, 5.0), "no reply from %s" % self.set_activation.srv_name
        return future.result().success


class Graph:
    """The two robots' programs and a test client."""

    def __init__(self, log_file: str) -> None:
        self.programs = []
        for name, node in NODES.items():
            remap = ["-r", ARM_REMAP] if name == "robot1" else []
            namespace = ["-r", "__ns:=/" + name]
            self.programs.append(start_program("cssr_system.ros2.simulated_pepper_node", DOMAIN, namespace + remap))
            self.programs.append(start_program(
                "cssr_system.ros2.animate_behaviour_main", DOMAIN,
                namespace + ["-r", "__node:=" + node.rsplit("/", 1)[1]] + remap + ["-p", "logFile:=" + log_file]))
        self.context = Context()
        rclpy.init(context=self.context, domain_id=DOMAIN)
        self.node = Node("several_robots_test", context=self.context)
        self.robots = {name: Robot(self.node, name) for name in NODES}
        self.gesture = ActionClient(self.node, FollowJointTrajectory, REMAPPED_ARM)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        threading.Thread(target=self.executor.spin, daemon=True).start()

    def ready(self) -> bool:
        return all(robot.set_activation.service_is_ready() and robot.samples for robot in self.robots.values())

    def close(self) -> None:
        """Disables both nodes, then stops every program, also when a disable fails."""
        try:
            for robot in self.robots.values():
                robot.activate("disabled")
        finally:
            for program in self.programs:
                stop_program(program)
            self.executor.shutdown()
            self.node.destroy_node()
            rclpy.shutdown(context=self.context)


@pytest.fixture(scope="module")
def graph(tmp_path_factory):
    log_file = str(tmp_path_factory.mktemp("several") / "animateBehaviourLogFile.log")
    graph = Graph(log_file)
    graph.log_file = log_file
    try:
        assert wait_until(graph.ready, START_TIMEOUT), [p.poll() for p in graph.programs]
        time.sleep(2.0)  # discovery: each node finds its controllers
        yield graph
    finally:
        graph.close()


def test_each_robot_animates_stops_and_yields_on_its_own(graph):
    robot1, robot2 = graph.robots["robot1"], graph.robots["robot2"]
    assert robot1.activate("enabled") == contract.REPLY_SUCCESS
    start = time.monotonic()
    time.sleep(WATCH)
    assert robot1.travel(start) > MOVED, "robot1 moves once enabled"
    assert robot2.travel(start) < MOVED, "robot2 stays still: only robot1 was enabled"
    counts = len(robot1.statuses), len(robot2.statuses)
    assert robot2.activate("enabled") == contract.REPLY_SUCCESS
    start = time.monotonic()
    time.sleep(WATCH)
    assert robot2.travel(start) > MOVED, "robot2 moves once enabled"
    assert robot1.yielding_since(counts[0]) + robot2.yielding_since(counts[1]) == [], "neither yields to the other"
    assert robot1.activate("disabled") == contract.REPLY_SUCCESS
    time.sleep(2.5)  # the return home (at most 2 s) ends
    start = time.monotonic()
    time.sleep(WATCH)
    assert robot1.travel(start) < MOVED, "robot1 rests once disabled"
    assert robot2.travel(start) > MOVED, "robot2 still animates"
    assert robot2.activate("disabled") == contract.REPLY_SUCCESS


def test_a_renamed_node_offers_its_service_under_its_new_name(graph):
    services = {name for name, _ in graph.node.get_service_names_and_types()}
    assert {"/robot2/animateRobot2/setActivation", "/robot2/animateRobot2/set_enabled"} <= services
    assert "/robot2/animateBehaviour/setActivation" not in services
    assert "/animateBehaviour/setActivation" not in services


def test_each_robot_serves_the_successors_action_and_stop_service_in_its_own_namespace(graph):
    services = {name for name, _ in graph.node.get_service_names_and_types()}
    for robot in NODES:
        assert "/%s/animate_behavior/stop" % robot in services
        assert "/%s/animate_behavior/_action/send_goal" % robot in services
    assert not {"/animate_behavior/stop", "/animate_behavior/_action/send_goal"} & services


def test_the_two_nodes_never_write_into_one_log_file(graph):
    (first,) = started_in(graph.log_file)  # one node holds the file asked for; the other writes beside it
    (second,) = set(NODES.values()) - {first}
    beside = graph.log_file.rsplit("/", 1)[0] + "/" + node_log_file_name(second)
    assert started_in(beside) == {second}


def test_a_remapped_arm_yields_to_another_nodes_goal_which_succeeds(graph):
    robot1 = graph.robots["robot1"]
    assert robot1.activate("enabled") == contract.REPLY_SUCCESS
    try:
        assert graph.gesture.wait_for_server(timeout_sec=10.0)
        time.sleep(1.0)  # our goals run on the arm
        count = len(robot1.statuses)
        sent = on_executor(graph.node, lambda: graph.gesture.send_goal_async(gesture_goal()))
        assert wait_until(sent.done, 5.0) and sent.result().accepted
        result = on_executor(graph.node, sent.result().get_result_async)
        assert wait_until(result.done, 15.0)
        assert result.result().status == GoalStatus.STATUS_SUCCEEDED
        assert "RArm" in [part for part, _ in robot1.yielding_since(count)]
    finally:
        robot1.activate("disabled")


def started_in(path: str) -> set:
    return {entry.fields["node"] for entry in read_log(path) if entry.event == contract.NODE_STARTED}


def gesture_goal() -> FollowJointTrajectory.Goal:
    """A 3 s gesture of the right arm, ending at rest, as another node would send it."""
    joints = PARTS["RArm"].joints
    centre = [centre_of(joint) for joint in joints]
    raised = [value + (0.2 if index == 0 else 0.0) for index, value in enumerate(centre)]
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=raised, time_from_start=Duration(sec=1, nanosec=500000000)),
        JointTrajectoryPoint(positions=centre, velocities=[0.0] * len(joints), time_from_start=Duration(sec=3))]
    goal.goal_time_tolerance = Duration(sec=1)  # the measured joints settle after the end, as on the robot
    return goal
