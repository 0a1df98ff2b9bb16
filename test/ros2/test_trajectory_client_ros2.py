"""The ROS 2 controller client (cssr_system.ros2.trajectory_client) keeps the ids of its latest goals only: the set
by which the foreign watch tells our goals from others' does not grow with every goal sent.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import pytest

rclpy = pytest.importorskip("rclpy")

from control_msgs.action import FollowJointTrajectory  # noqa: E402 (after the skip)
from rclpy.context import Context  # noqa: E402
from rclpy.node import Node  # noqa: E402

from cssr_system.ros2.trajectory_client import REMEMBERED_GOALS, TrajectoryClient  # noqa: E402

from domains import claim_domain  # noqa: E402


def test_the_ids_of_a_clients_latest_goals_only_are_kept():
    context = Context()
    rclpy.init(context=context, domain_id=claim_domain())
    node = Node("trajectory_client_test", context=context)
    try:
        own_goals = {b"another client's"}
        client = TrajectoryClient(node, "/pepper/RightArm_controller/follow_joint_trajectory", own_goals)
        sent = [client.send(FollowJointTrajectory.Goal(), lambda *end: None) for _ in range(3 * REMEMBERED_GOALS)]
        assert own_goals == {b"another client's"} | {bytes(goal.uuid.uuid) for goal in sent[-REMEMBERED_GOALS:]}
    finally:
        node.destroy_node()
        rclpy.shutdown(context=context)
