"""Who else is a client of an action (ros2/rclpy_compat.py's other_action_client), the name a yielded part's log line
gives: the one other client found in the graph, else "another client of <action>"; and asked at every other node's
goal, all day, it leaves no memory behind (rclpy's own action-graph query never frees what it returns).

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import ctypes
import gc

import pytest

rclpy = pytest.importorskip("rclpy")

from control_msgs.action import FollowJointTrajectory  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.node import Node  # noqa: E402

from cssr_system.ros2.rclpy_compat import other_action_client  # noqa: E402
from processes import wait_until  # noqa: E402

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"
CALLS = 3000
ALLOWED_GROWTH = 300_000  # bytes of malloc in use after CALLS calls; rclpy's action-graph query left about 2 MB


def other_node(node, name):
    """A node of `node`'s context, and its client of ACTION."""
    made = Node(name, context=node.context)
    return made, ActionClient(made, FollowJointTrajectory, ACTION)


def malloc_in_use() -> int:
    """Bytes glibc's malloc has handed out and not had back, every arena (None without mallinfo2: glibc < 2.33)."""
    libc = ctypes.CDLL("libc.so.6")
    if not hasattr(libc, "mallinfo2"):
        return None

    class MallInfo2(ctypes.Structure):
        _fields_ = [(name, ctypes.c_size_t) for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                                         "fsmblks", "uordblks", "fordblks", "keepcost")]

    libc.mallinfo2.restype = MallInfo2
    gc.collect()
    return libc.mallinfo2().uordblks


def test_the_one_other_client_is_named_and_two_are_not(node):
    ActionClient(node, FollowJointTrajectory, ACTION)  # the node's own client never counts
    assert other_action_client(node, ACTION) == "another client of " + ACTION, "no other client yet"
    player, _ = other_node(node, "gesture_player")
    assert wait_until(lambda: other_action_client(node, ACTION) == "/gesture_player", 5.0), \
        other_action_client(node, ACTION)
    second, _ = other_node(node, "attention")
    assert wait_until(lambda: other_action_client(node, ACTION) == "another client of " + ACTION, 5.0), \
        "two other clients: neither is named"
    second.destroy_node()
    player.destroy_node()


def test_asking_all_day_leaves_no_memory(node):
    ActionClient(node, FollowJointTrajectory, ACTION)
    player, _ = other_node(node, "gesture_player")
    assert wait_until(lambda: other_action_client(node, ACTION) == "/gesture_player", 5.0)
    for _ in range(200):  # the first calls' one-time allocations
        other_action_client(node, ACTION)
    before = malloc_in_use()
    if before is None:
        pytest.skip("glibc has no mallinfo2")
    for _ in range(CALLS):
        assert other_action_client(node, ACTION) == "/gesture_player"
    growth = malloc_in_use() - before
    assert growth < ALLOWED_GROWTH, "%d bytes more in use after %d calls" % (growth, CALLS)
    player.destroy_node()
