"""Who else is a client of an action (ros2/rclpy_compat.py's other_action_client), the name a yielded part's log line
gives: the one other client found in the graph, else "another client of <action>"; and asked at every other node's
goal, all day, it leaves no memory behind (rclpy's own action-graph query never frees what it returns).

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import gc
import importlib.util
import os
from typing import Optional

import pytest

rclpy = pytest.importorskip("rclpy")

from control_msgs.action import FollowJointTrajectory  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.node import Node  # noqa: E402

from cssr_system.ros2.rclpy_compat import other_action_client  # noqa: E402
from processes import wait_until  # noqa: E402

PROBE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "soak_probe", "sitecustomize.py")
ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"
CALLS = 3000
ALLOWED_GROWTH = 300_000  # bytes of malloc in use after CALLS calls; rclpy's action-graph query left 1.5 MB


def other_node(node, name):
    """A node of `node`'s context, and its client of ACTION."""
    made = Node(name, context=node.context)
    return made, ActionClient(made, FollowJointTrajectory, ACTION)


def soak_probe():
    """The soak's probe of what a process's allocators hold (tools/soak_probe; it does nothing else without the
    soak's variables)."""
    spec = importlib.util.spec_from_file_location("soak_probe", PROBE)
    probe = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(probe)
    return probe


def malloc_in_use(probe) -> Optional[int]:
    """Bytes malloc has handed out and not had back, as the soak reads them (None without glibc's mallinfo)."""
    mallinfo = probe.malloc_info()
    if mallinfo is None:
        return None
    gc.collect()
    return probe.malloc_bytes(mallinfo)[0]


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
    probe = soak_probe()
    before = malloc_in_use(probe)
    if before is None:
        pytest.skip("no glibc mallinfo")
    for _ in range(CALLS):
        assert other_action_client(node, ACTION) == "/gesture_player"
    growth = malloc_in_use(probe) - before
    assert growth < ALLOWED_GROWTH, "%d bytes more in use after %d calls" % (growth, CALLS)
    player.destroy_node()
