"""Unit tests of the first goals planned while disabled (node/first_goals.py, part_stream.PreparedGoal): no master."""
from types import SimpleNamespace

import numpy
from actionlib_msgs.msg import GoalStatus
from conftest import default_configuration
from test_part_stream import Rig

from cssr_system.animate_behaviour.motion.styles import MotionStyle
from cssr_system.animate_behaviour.motion.waypoints import animated_parts, make_rng
from cssr_system.animate_behaviour.node.first_goals import prepare_enable
from cssr_system.animate_behaviour.node.part_stream import PREPARED_START_TOLERANCE, PartState, prepare_goal
from cssr_system.pepper.joint_table import PARTS

TOPICS = {part: "/pepper_dcm/%s_controller/follow_joint_trajectory" % part for part in PARTS}


def resting_streams(offset=0.0):
    """Idle streams by action whose measured joints (`positions`, which a test may move) rest `offset` from the
    centre."""
    streams = {}
    for part in PARTS:
        stream = SimpleNamespace(active=False, positions=numpy.array(PARTS[part].centre) + offset)
        stream.measured_positions = lambda stream=stream: stream.positions
        streams[TOPICS[part]] = stream
    return streams


def test_seeded_first_goals_are_those_an_enable_would_plan():
    config = default_configuration(random_seed=11)
    streams = resting_streams(0.01)
    prepared = prepare_enable(config, TOPICS, make_rng(999), streams)
    style = MotionStyle(config, make_rng(11))
    for motion in animated_parts(config, list(TOPICS)):  # the enable's order
        start = numpy.array(PARTS[motion.part].centre) + 0.01
        zeros = numpy.zeros(start.size)
        expected = style.planner(motion)(0.0, start, zeros, zeros)
        numpy.testing.assert_array_equal(prepared.goals[motion.part][1].timed.positions, expected.positions)
        numpy.testing.assert_array_equal(prepared.goals[motion.part][1].timed.times, expected.times)
    # the generator goes on where the enable's would: the base draws the same numbers
    assert prepared.rng.bit_generator.state == style._rng.bit_generator.state


def test_without_a_seed_the_nodes_generator_is_used_and_advanced():
    rng = make_rng(5)
    before = rng.bit_generator.state
    prepared = prepare_enable(default_configuration(random_seed=None), TOPICS, rng, resting_streams())
    assert prepared.rng is rng and rng.bit_generator.state != before


def test_nothing_is_prepared_for_breathing_for_a_moving_part_or_unknown_joints():
    config = default_configuration(random_seed=3)
    assert prepare_enable(config._replace(motion_style="breathing"), TOPICS, None, resting_streams()) is None
    busy = resting_streams()
    busy[TOPICS["LArm"]].active = True
    assert prepare_enable(config, TOPICS, None, busy) is None
    unknown = resting_streams()
    unknown[TOPICS["Leg"]].measured_positions = lambda: None
    assert prepare_enable(config, TOPICS, None, unknown) is None


def test_prepared_goals_stop_fitting_when_a_part_moves_or_the_configuration_changes():
    config = default_configuration(random_seed=3)
    streams = resting_streams()
    prepared = prepare_enable(config, TOPICS, None, streams)
    assert prepared.fits(streams) and prepared.matches(config, TOPICS)
    streams[TOPICS["RArm"]].positions = streams[TOPICS["RArm"]].positions + 2 * PREPARED_START_TOLERANCE
    assert not prepared.fits(streams)
    assert not prepared.matches(config._replace(gesture_duration=config.gesture_duration + 1), TOPICS)


def test_a_stream_sends_the_prepared_goal_when_the_part_rests_where_it_starts():
    rig = Rig(measured=numpy.array(PARTS["RArm"].centre) + 0.005)
    prepared = prepare_goal("RArm", rig.plan, PARTS["RArm"].centre)
    planned = []
    rig.stream.enable(rig.motion, lambda *state: planned.append(state) or rig.plan(*state), prepared=prepared)
    assert rig.client.handles[-1].goal is prepared.goal and planned == []
    rig.finish_last(GoalStatus.SUCCEEDED)  # the goals after it come from the part's planner
    assert len(planned) == 1 and rig.stream.state == PartState.ANIMATING
    assert rig.client.handles[-1].goal is not prepared.goal


def test_a_part_that_moved_since_gets_a_goal_planned_afresh():
    rig = Rig(measured=numpy.array(PARTS["RArm"].centre) + 2 * PREPARED_START_TOLERANCE)
    prepared = prepare_goal("RArm", rig.plan, PARTS["RArm"].centre)
    rig.stream.enable(rig.motion, rig.plan, prepared=prepared)
    goal = rig.client.handles[-1].goal
    assert goal is not prepared.goal
    numpy.testing.assert_allclose(rig.stream.current_state(rig.now)[0], rig.measured, atol=1e-12)
