"""Unit tests of what the recorder makes of setAngles calls (recording/commanded.py, actuation joint_angles): the
node's calls replayed as naoqi_driver executes them, other nodes' calls as marks."""
import numpy
import pytest

from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.recording.commanded import SentCall, call_marks, commanded_by_calls

NODE, OTHER = "/animateBehaviour", "/gesture"
TIMES = numpy.arange(0.0, 3.0, 0.02)


def measured_at_centre():
    names = tuple(name for part in PARTS.values() for name in part.joints)
    centres = [centre for part in PARTS.values() for centre in part.centre]
    return names, numpy.array([0.0]), numpy.array([centres])


def test_the_nodes_calls_are_replayed_from_the_measured_joints():
    start = PARTS["Leg"].centre[0]
    speed = 0.1
    calls = [SentCall(1.0, NODE, ("HipPitch",), (start + 0.05,), speed)]
    commanded = commanded_by_calls(NODE, calls, TIMES, measured_at_centre())
    assert commanded.joint_names == PARTS["Leg"].joints and commanded.source == NODE
    hip = commanded.positions[:, 0]
    assert numpy.isnan(hip[TIMES < 1.0]).all()  # before the node's first call
    arrival = 1.0 + 0.05 / (speed * JOINTS["HipPitch"].max_velocity)
    assert hip[numpy.searchsorted(TIMES, 2.5)] == pytest.approx(start + 0.05)
    middle = numpy.searchsorted(TIMES, (1.0 + arrival) / 2)
    assert start < hip[middle] < start + 0.05
    assert numpy.isnan(commanded.positions[:, 1]).all()  # a joint the node never named


def test_another_nodes_call_on_a_joint_hides_the_nodes_until_it_names_the_joint_again():
    calls = [SentCall(0.5, NODE, ("HipPitch",), (0.0,), 0.1), SentCall(1.0, OTHER, ("HipPitch",), (0.1,), 0.1),
             SentCall(2.0, NODE, ("HipPitch",), (0.0,), 0.1)]
    hip = commanded_by_calls(NODE, calls, TIMES, measured_at_centre()).positions[:, 0]
    assert not numpy.isnan(hip[(TIMES >= 0.5) & (TIMES < 1.0)]).any()
    assert numpy.isnan(hip[(TIMES >= 1.0) & (TIMES < 2.0)]).all()
    assert not numpy.isnan(hip[TIMES >= 2.0]).any()


def test_no_call_of_the_node_means_no_commanded_line_and_refused_calls_are_skipped():
    assert commanded_by_calls(NODE, [SentCall(1.0, OTHER, ("HipPitch",), (0.1,), 0.1)], TIMES) is None
    assert commanded_by_calls(NODE, [SentCall(1.0, NODE, ("HipPitch",), (0.1,), 0.0)], TIMES) is None


def test_other_nodes_bursts_of_calls_are_marks():
    calls = [SentCall(t, OTHER, ("RShoulderPitch",), (1.0,), 0.1) for t in (1.0, 1.1, 1.2, 5.0)]
    calls.append(SentCall(1.05, NODE, ("HipPitch",), (0.0,), 0.1))
    marks = call_marks(calls, NODE)
    assert [(mark.start, mark.end, mark.part) for mark in marks] == [(1.0, 1.2, "RArm"), (5.0, 5.0, "RArm")]
    assert marks[0].label == "/gesture: joint_angles"
