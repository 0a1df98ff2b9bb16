"""Unit tests of what a test sees of one robot from outside (recording/robot_watch.py)."""
import time
from types import SimpleNamespace

from cssr_system.pepper.joint_table import PARTS
from cssr_system.recording.robot_watch import RobotWatch

JOINTS = [joint for part in PARTS.values() for joint in part.joints]


def test_travel_is_the_largest_move_of_a_joint_since_a_moment():
    watch = RobotWatch()
    watch.joint_states(JOINTS, [0.0] * len(JOINTS))
    since = time.monotonic()
    assert watch.travel(since) == 0.0, "no sample since"
    moved = [0.0] * len(JOINTS)
    moved[JOINTS.index("RShoulderPitch")] = 0.2
    moved[JOINTS.index("HipPitch")] = -0.05
    watch.joint_states(JOINTS, [0.0] * len(JOINTS))
    watch.joint_states(JOINTS, moved)
    assert abs(watch.travel(since) - 0.2) < 1e-12


def test_yielding_since_names_each_yielding_part_and_the_node_it_yields_to():
    watch = RobotWatch()
    row = SimpleNamespace
    watch.status(SimpleNamespace(parts=[row(part="RArm", state="yielding", yielding_to="/old")]))
    watch.status(SimpleNamespace(parts=[row(part="RArm", state="yielding", yielding_to="/gesture"),
                                        row(part="LArm", state="animating", yielding_to="")]))
    assert watch.yielding_since(1) == [("RArm", "/gesture")]
