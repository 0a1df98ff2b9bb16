"""Unit tests of the demo's pure parts: the gesture the gesture player sends, the conversation the speech node plays,
the live lines and the run's schedule."""
import threading
import time

import numpy
import pytest

from cssr_system.demo import speech
from cssr_system.demo.gesture import GESTURE_DURATION, GESTURE_PART, gesture_points
from cssr_system.demo.live_lines import (CONVERSATION, CONVERSATION_START, DISABLE, GESTURE, LINE,
                                         MOVING_COLUMN_WIDTH, LiveWindow, schedule, status_line)
from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline, sample_trajectory


@pytest.mark.parametrize("part_key", ["RArm", "LArm"])
def test_the_gesture_stays_in_the_limits_and_ends_at_rest(part_key):
    part = PARTS[part_key]
    points = gesture_points(part_key, GESTURE_DURATION)
    times = [point.time for point in points]
    assert times == sorted(times) and times[-1] == GESTURE_DURATION and times[0] > 0.0
    assert points[-1].positions == part.centre
    spline = JointTrajectorySpline(part.centre, None, None, points)
    positions = sample_trajectory(spline, numpy.linspace(0.0, GESTURE_DURATION, 400))[0]
    lower = numpy.array([JOINTS[name].lower for name in part.joints])
    upper = numpy.array([JOINTS[name].upper for name in part.joints])
    assert numpy.all(positions >= lower) and numpy.all(positions <= upper)
    pitch = part.joints.index(part_key[0] + "ShoulderPitch")
    assert numpy.ptp(positions[:, pitch]) > 1.0  # a gesture anyone sees, far outside the node's bands


def test_the_left_arm_mirrors_the_right():
    right, left = gesture_points("RArm"), gesture_points("LArm")
    for right_point, left_point in zip(right[:-1], left[:-1]):
        by_name = dict(zip(PARTS["LArm"].joints, left_point.positions))
        for name, value in zip(PARTS["RArm"].joints, right_point.positions):
            mirrored = by_name["L" + name[1:]]
            assert mirrored == (value if name.endswith("ShoulderPitch") else -value)


def test_the_gesture_is_for_an_arm_and_takes_time():
    assert GESTURE_PART == "RArm"
    with pytest.raises(ValueError, match="for an arm"):
        gesture_points("Leg")
    with pytest.raises(ValueError, match="positive"):
        gesture_points("RArm", 0.0)


def test_the_schedule_disables_after_the_last_enabled_line_and_gestures_half_way():
    events = schedule(4.0, 2.0, gesture=True)
    assert [moment for moment, what in events if what == LINE] == [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    assert events.index((4.0, DISABLE)) == events.index((4.0, LINE)) + 1
    assert (2.0, GESTURE) in events and events.index((2.0, GESTURE)) == events.index((2.0, LINE)) + 1
    assert all(what != GESTURE for _, what in schedule(4.0, 2.0, gesture=False))


def test_the_live_line_names_what_moved_in_its_window():
    window = LiveWindow()
    names = ("RShoulderPitch", "LHand", "HipPitch")
    for step in range(60):  # 1.2 s at 50 Hz: the right arm moves, the rest holds
        window.add_joint_states(100.0 + step * 0.02, names, (1.5 + 0.002 * step, 0.6, -0.1))
        window.add_heading(100.0 + step * 0.02, 0.05)
    joint_names, positions, headings, heading = window.last(101.2, 1.0)
    assert joint_names == names and 45 <= len(positions) <= 52
    line = status_line(7, "enabled", joint_names, positions, headings, heading)
    assert line.startswith("   7 s  enabled   moving: right arm ")
    assert line.endswith("base heading +0.05 rad")
    assert len(line.split("moving: ")[1].split("  base")[0]) >= MOVING_COLUMN_WIDTH - 1
    still = status_line(8, "disabled", joint_names, positions[:1], headings, None)
    assert "moving: nothing" in still and still.endswith("base heading: no odometry")


def test_the_live_line_says_which_parts_yield_and_to_whom():
    names = ("RShoulderPitch",)
    positions = numpy.array([[1.5], [1.5]])
    line = status_line(9, "enabled", names, positions, numpy.array([0.0, 0.0]), 0.0,
                       [("right arm", "/animateBehaviourDemoGesture")])
    assert line.endswith("base heading +0.00 rad  yielding: right arm to /animateBehaviourDemoGesture")
    assert "yielding" not in status_line(9, "enabled", names, positions, numpy.array([0.0, 0.0]), 0.0, [])


def test_the_live_line_says_the_mode_when_given():
    names, positions = ("RShoulderPitch",), numpy.array([[1.5], [1.5]])
    line = status_line(9, "enabled", names, positions, numpy.array([0.0, 0.0]), 0.0,
                       [("right arm", "/gesture")], "speaking")
    assert line.endswith("base heading +0.00 rad  mode: speaking  yielding: right arm to /gesture")
    assert "mode" not in status_line(9, "enabled", names, positions, numpy.array([0.0, 0.0]), 0.0)


def test_the_schedule_starts_the_conversation_after_some_idle_motion():
    events = schedule(20.0, 3.0, gesture=False, conversation=True)
    assert (CONVERSATION_START, CONVERSATION) in events
    assert events.index((CONVERSATION_START, CONVERSATION)) == events.index((CONVERSATION_START, LINE)) + 1
    assert all(what != CONVERSATION for _, what in schedule(20.0, 3.0, gesture=False))


class ScriptedSpeech(speech.Conversation):
    """The script's calls, in order, with their times; the goal ends after `seconds`, as the server's would."""

    def __init__(self):
        super().__init__(threading.Event())
        self.calls = []
        self.start = time.monotonic()

    def set_listening(self, listening):
        self.calls.append((round(time.monotonic() - self.start, 1), "listening", listening))

    def speak(self, seconds, done):
        self.calls.append((round(time.monotonic() - self.start, 1), "speak", seconds))
        threading.Timer(seconds, done, ["SUCCEEDED"]).start()


def test_the_conversation_listens_then_speaks_with_listening_ending_once_speaking_has_begun(monkeypatch, capsys):
    monkeypatch.setattr(speech, "LISTEN_FOR", 0.3)
    monkeypatch.setattr(speech, "SPEAK_FOR", 0.4)
    monkeypatch.setattr(speech, "HANDOVER", 0.1)
    script = ScriptedSpeech()
    script.play()
    assert [call[1:] for call in script.calls] == [("listening", True), ("speak", 0.4), ("listening", False)]
    assert [call[0] for call in script.calls] == [0.0, 0.3, 0.4]
    assert "silent: the speaking goal ended (SUCCEEDED)" in capsys.readouterr().out


def test_a_stop_while_listening_ends_the_listening_and_speaks_no_more(monkeypatch):
    script = ScriptedSpeech()
    script.stop.set()
    script.play()
    assert [call[1:] for call in script.calls] == [("listening", True), ("listening", False)]
