"""The ROS 2 controller client (cssr_system.ros2.trajectory_client): goals sent from the supervisor's thread while
the executor spins each get their end; a goal replaced before it has gone is sent whole; and the client keeps the ids
of its latest goals only, so the set by which the foreign watch tells our goals from others' does not grow with every
goal sent.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import threading

import pytest

rclpy = pytest.importorskip("rclpy")

from control_msgs.action import FollowJointTrajectory  # noqa: E402 (after the skip)
from rclpy.action import ActionServer  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from trajectory_msgs.msg import JointTrajectoryPoint  # noqa: E402

from cssr_system.core.goals import SUCCEEDED  # noqa: E402
from cssr_system.ros2.animate_behaviour_node import ExecutorThread  # noqa: E402
from cssr_system.ros2.trajectory_client import REMEMBERED_GOALS, TrajectoryClient  # noqa: E402

from processes import fail_on_error, wait_until  # noqa: E402

ACTION = "/pepper/RightArm_controller/follow_joint_trajectory"
GOALS = 300
# Goals sent and not yet ended, at most. An action's goal service keeps its latest 10 requests (ROS 2's default
# service QoS): on a loaded machine, a stream of requests faster than the server takes them loses some. The node has
# at most two goals of a controller in flight, the running one and the one that replaces it.
IN_FLIGHT = 4


class Controller:
    """An action server that accepts every goal and succeeds at once, noting how many points each goal had."""

    def __init__(self, node) -> None:
        self.points = []
        self._server = ActionServer(node, FollowJointTrajectory, ACTION, self._execute)

    def _execute(self, handle):
        self.points.append(len(handle.request.trajectory.points))
        handle.succeed()
        return FollowJointTrajectory.Result()


def unspun(node):
    """(the node's executor, the thread that will spin it)"""
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    return executor, ExecutorThread(node, fail_on_error)


def test_goals_sent_from_another_thread_while_the_executor_spins_each_get_their_end(node):
    controller = Controller(node)
    executor, spinning = unspun(node)
    spinning.spin(executor)
    client = TrajectoryClient(node, ACTION, set(), spinning.run)
    assert wait_until(client.ready, 5.0)
    ends, lock = [], threading.Lock()

    def done(state, error_code, error_string):
        with lock:
            ends.append(state)
    for sent in range(GOALS):  # a few a second per controller on the robot: here as fast as they end
        assert wait_until(lambda: sent - len(ends) < IN_FLIGHT, 10.0), "goal %d: %d ended" % (sent, len(ends))
        client.send(FollowJointTrajectory.Goal(), done)
    assert wait_until(lambda: len(ends) == GOALS, 30.0), "%d of %d goals ended" % (len(ends), GOALS)
    assert set(ends) == {SUCCEEDED}
    assert len(controller.points) == GOALS
    assert not spinning.ended()


def test_a_goal_replaced_before_it_has_gone_is_sent_whole(node):
    controller = Controller(node)
    executor, spinning = unspun(node)
    client = TrajectoryClient(node, ACTION, set(), spinning.run)
    assert wait_until(client.ready, 5.0)
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.points = [JointTrajectoryPoint(positions=[0.1]), JointTrajectoryPoint(positions=[0.2])]
    ends = []
    sent = client.send(goal, lambda *end: ends.append(end))
    sent.release()  # replaced while the send still waits for the executor
    spinning.spin(executor)
    assert wait_until(lambda: ends, 10.0)
    assert controller.points == [2]
    assert goal.trajectory.points == []  # let go once it had gone


def test_the_ids_of_a_clients_latest_goals_only_are_kept(node):
    own_goals = {b"another client's"}
    client = TrajectoryClient(node, ACTION, own_goals, lambda work: None)
    sent = [client.send(FollowJointTrajectory.Goal(), lambda *end: None) for _ in range(3 * REMEMBERED_GOALS)]
    assert own_goals == {b"another client's"} | {bytes(goal.uuid.uuid) for goal in sent[-REMEMBERED_GOALS:]}
