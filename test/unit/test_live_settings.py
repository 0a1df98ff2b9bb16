"""Unit tests of the live settings (live_settings.py) and of the animate action's sessions (ros1/animate_action.py):
no ROS master."""
import pytest
from conftest import default_configuration

from cssr_system.animate_behaviour.live_settings import (changed_settings, goal_overrides, moving_parts,
                                                         setting_overrides, setting_values)
from cssr_system.core.session import (FEEDBACK_PERIOD, LONGEST_HOMING, RESULT_MARGIN, RETURN_POLL, RETURN_WINDOW,
                                      Session, checked_goal, starts_return)


def test_dynamic_reconfigures_names_map_onto_the_configuration_keys_and_back():
    config = default_configuration(intensity=0.4, breaths_per_minute=9.0, motion_style="breathing", move_leg=False)
    values = setting_values(config)
    assert values == {"intensity": 0.4, "tempo": 9.0, "style": "breathing", "arms": True, "hands": True,
                      "leg": False, "base": True, "mode": "auto"}
    overrides = setting_overrides(dict(values, groups={"name": "Default"}))
    assert overrides == {"intensity": 0.4, "breathsPerMinute": 9.0, "motionStyle": "breathing", "moveArms": True,
                         "moveHands": True, "moveLeg": False, "turnBase": True, "mode": "auto"}


def test_changes_are_listed_as_the_configuration_file_writes_them():
    old, new = default_configuration(), default_configuration(intensity=0.5, turn_base=False)
    assert changed_settings(old, new) == [("intensity", "1.0", "0.5"), ("turnBase", "true", "false")]
    assert changed_settings(old, old) == []
    assert moving_parts(new) == ["arms", "hands", "leg"]


def test_an_animate_goal_becomes_overrides():
    assert goal_overrides(["arms"], "breathing", 0.5, 0.0) == {
        "moveArms": True, "moveHands": False, "moveLeg": False, "turnBase": False, "intensity": 0.5,
        "motionStyle": "breathing"}
    assert goal_overrides(["base", "leg"], "", 0.5, 0.0)["turnBase"], "the base is a part like the others"
    every = goal_overrides([], "", 1.0, 10.0)
    assert every["moveArms"] and every["moveHands"] and every["moveLeg"] and every["turnBase"], \
        "no part named: every part, the base included"
    assert every["breathsPerMinute"] == 10.0 and "motionStyle" not in every, "empty style and tempo 0 keep them"
    with pytest.raises(ValueError, match="unknown part 'head'; expected any of: arms, hands, leg, base"):
        goal_overrides(["arms", "head"], "", 1.0, 0.0)


def test_a_session_plans_the_returns_in_its_last_seconds_and_succeeds_at_its_duration_once_the_parts_are_home():
    session = Session("handle", started=100.0, duration=5.0)
    assert session.next_deadline(100.0) == pytest.approx(min(100.0 + FEEDBACK_PERIOD, 105.0 - RETURN_WINDOW))
    session.next_feedback = 200.0  # the deadlines of the end alone
    assert session.next_deadline(100.5) == pytest.approx(105.0 - RETURN_WINDOW), "the window opens"
    assert not session.returns_due(105.0 - RETURN_WINDOW - 0.01)
    assert session.returns_due(105.0 - RETURN_WINDOW)
    assert session.next_deadline(104.0) == pytest.approx(104.0 + RETURN_POLL), "a look every poll in the window"
    session.homing = True
    assert not session.returns_due(104.5)
    assert session.next_deadline(104.5) == pytest.approx(105.0), "the end"
    assert session.next_deadline(105.5) == pytest.approx(105.0 + LONGEST_HOMING), "no busy loop after the end"
    assert not session.succeeds(104.9, parts_active=False), "not before the duration"
    assert not session.succeeds(105.0, parts_active=True)
    assert session.succeeds(105.0, parts_active=False)
    assert session.succeeds(105.0 + LONGEST_HOMING, parts_active=True), "a part that never reports home"


def test_a_return_starts_when_the_next_look_would_be_too_late():
    ends_at, lasts = 10.0, 1.3
    latest = ends_at - lasts - RESULT_MARGIN
    assert not starts_return(latest - RETURN_POLL - 0.01, lasts, ends_at)
    assert starts_return(latest - RETURN_POLL, lasts, ends_at)
    assert starts_return(ends_at + 1.0, lasts, ends_at), "late: at once"


def test_a_home_session_succeeds_once_the_parts_are_back():
    session = Session("handle", started=100.0, duration=0.0, home=True)
    assert session.homing and not session.returns_due(100.0)
    assert not session.succeeds(100.5, parts_active=True) and session.succeeds(100.6, parts_active=False)


def test_a_session_without_a_duration_runs_until_cancelled_and_gives_feedback_once_a_period():
    session = Session("handle", started=0.0, duration=0.0)
    assert not session.returns_due(1.0e6) and not session.succeeds(1.0e6, parts_active=False)
    assert not session.feedback_due(FEEDBACK_PERIOD - 0.01)
    assert session.feedback_due(FEEDBACK_PERIOD) and not session.feedback_due(FEEDBACK_PERIOD + 0.5)
    assert session.feedback_due(2 * FEEDBACK_PERIOD)


class Goal:
    """An animate goal's fields, as either front-end's message has them."""

    def __init__(self, parts=(), style="", intensity=1.0, tempo=0.0, duration=0.0):
        self.parts, self.style, self.intensity, self.tempo, self.duration = parts, style, intensity, tempo, duration


def test_a_goal_is_checked_before_it_is_accepted():
    asked = []
    (configured, duration) = checked_goal(Goal(parts=["base"], duration=3.0), lambda overrides: asked.append(
        overrides) or "configuration")
    assert (configured, duration) == ("configuration", 3.0)
    assert asked[0]["turnBase"] and not asked[0]["moveArms"]
    with pytest.raises(ValueError, match="duration -1.0: expected a number of seconds >= 0"):
        checked_goal(Goal(duration=-1.0), lambda overrides: "configuration")
    with pytest.raises(ValueError, match="unknown part 'head'"):
        checked_goal(Goal(parts=["head"]), lambda overrides: "configuration")
