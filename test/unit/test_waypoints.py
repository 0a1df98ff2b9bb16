"""Unit tests of motion.waypoints: bounds, animated parts, leg pattern, random positions (no ROS)."""
import numpy
import pytest
from hypothesis import given, settings, strategies as st
from conftest import ROBOT_PARTS, SIMULATOR_PARTS, default_configuration

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.motion.waypoints import (JointBounds, PartMotion, animated_parts,
                                          joint_bounds, leg_pattern, make_rng,
                                          maximum_range, random_waypoints)
from cssr_system.pepper.joint_table import JOINTS, PARTS


def expected_bounds(joint_name, max_range, selected_range):
    """The band formula (README: "What moves, and how"), computed from the joint table."""
    part = next(part for part in PARTS.values() if joint_name in part.joints)
    centre = part.centre[part.joints.index(joint_name)]
    limits = JOINTS[joint_name]
    full_range = limits.upper - limits.lower
    half = full_range * max_range * selected_range / 2.0
    return centre, max(centre - half, limits.lower), min(centre + half, limits.upper)


def random_configuration(rng) -> Configuration:
    num_points = int(rng.integers(1, 120))
    leg_repeat_factor = int(rng.integers(1, num_points + 1))
    chunk = num_points // leg_repeat_factor
    return default_configuration(
        behaviour=frozenset({"body", "hands"}),
        selected_range=float(rng.uniform(0.0, 1.0)),
        arm_maximum_range=tuple(float(x) for x in rng.uniform(0.0, 1.0, 5)),
        hand_maximum_range=float(rng.uniform(0.0, 1.0)),
        leg_maximum_range=tuple(float(x) for x in rng.uniform(0.0, 1.0, 3)),
        num_points=num_points,
        leg_repeat_factor=leg_repeat_factor,
        num_points_leg=int(rng.integers(0, chunk + 1)),
    )


# ---------------------------------------------------------------------------------------------
# Bounds


@pytest.mark.parametrize("joint_name", ["RShoulderPitch", "LElbowYaw", "RHand", "KneePitch", "HipRoll"])
def test_bounds_follow_the_formula(joint_name):
    config = default_configuration()
    bounds = joint_bounds(config, joint_name)
    centre, lower, upper = expected_bounds(joint_name, maximum_range(config, joint_name),
                                           config.selected_range)
    assert bounds == JointBounds(joint_name, centre, lower, upper)
    assert bounds.lower < bounds.centre < bounds.upper


def test_bounds_are_clamped_to_the_joint_limits():
    # RShoulderRoll rests 0.088 rad from its upper limit: a full range reaches past it.
    config = default_configuration(selected_range=1.0, arm_maximum_range=(1.0,) * 5)
    bounds = joint_bounds(config, "RShoulderRoll")
    half_range = JOINTS["RShoulderRoll"].full_range / 2.0
    assert bounds.upper == JOINTS["RShoulderRoll"].upper
    assert bounds.lower == pytest.approx(bounds.centre - half_range)  # not clamped on this side
    assert joint_bounds(config, "LShoulderRoll").lower == JOINTS["LShoulderRoll"].lower


def test_zero_range_pins_the_joint_to_its_centre():
    bounds = joint_bounds(default_configuration(selected_range=0.0), "LWristYaw")
    assert bounds.lower == bounds.upper == bounds.centre


def test_maximum_range_picks_the_configured_value_of_each_joint():
    config = default_configuration(arm_maximum_range=(0.1, 0.2, 0.3, 0.4, 0.5), hand_maximum_range=0.6,
                                   leg_maximum_range=(0.7, 0.8, 0.9))
    for arm in ("RArm", "LArm"):
        for index, name in enumerate(PARTS[arm].joints):
            assert maximum_range(config, name) == config.arm_maximum_range[index]
    assert PARTS["RArm"].joints[2:4] == ("RElbowRoll", "RElbowYaw")  # order of armMaximumRange
    assert maximum_range(config, "RHand") == maximum_range(config, "LHand") == 0.6
    for index, name in enumerate(("HipPitch", "HipRoll", "KneePitch")):
        assert maximum_range(config, name) == config.leg_maximum_range[index]
    with pytest.raises(KeyError):
        maximum_range(config, "HeadYaw")


# ---------------------------------------------------------------------------------------------
# Parts per behaviour and platform


def moving_joints(parts):
    return {motion.part: {name for name, moves in zip(motion.joints, motion.moving) if moves}
            for motion in parts}


def test_parts_have_every_joint_of_their_controller_with_consistent_bounds():
    for motion in animated_parts(default_configuration(behaviour=frozenset({"hands"})), ROBOT_PARTS):
        assert isinstance(motion, PartMotion)
        assert motion.joints == PARTS[motion.part].joints
        assert tuple(bound.name for bound in motion.bounds) == motion.joints
        assert motion.is_leg == (motion.part == "Leg")
        for bound, moves, centre in zip(motion.bounds, motion.moving, PARTS[motion.part].centre):
            assert bound.centre == centre
            if not moves:
                assert bound.lower == bound.upper == centre


def test_body_on_the_robot_moves_arms_hands_and_leg_fully():
    parts = animated_parts(default_configuration(behaviour=frozenset({"body"})), ROBOT_PARTS)
    assert [motion.part for motion in parts] == ["RArm", "LArm", "RHand", "LHand", "Leg"]
    assert moving_joints(parts) == {key: set(part.joints) for key, part in PARTS.items()}


def test_body_on_the_simulator_has_no_hands():
    parts = animated_parts(default_configuration(behaviour=frozenset({"body"})), SIMULATOR_PARTS)
    assert [motion.part for motion in parts] == ["RArm", "LArm", "Leg"]


def test_hands_on_the_robot_moves_hands_and_forearms_only():
    parts = animated_parts(default_configuration(behaviour=frozenset({"hands"})), ROBOT_PARTS)
    assert moving_joints(parts) == {
        "RArm": {"RElbowRoll", "RWristYaw"},
        "LArm": {"LElbowRoll", "LWristYaw"},
        "RHand": {"RHand"},
        "LHand": {"LHand"},
    }


def test_hands_on_the_simulator_moves_elbow_roll_and_wrist_yaw_only():
    parts = animated_parts(default_configuration(behaviour=frozenset({"hands"})), SIMULATOR_PARTS)
    assert moving_joints(parts) == {"RArm": {"RElbowRoll", "RWristYaw"},
                                    "LArm": {"LElbowRoll", "LWristYaw"}}


def test_rotation_moves_no_joint():
    assert animated_parts(default_configuration(behaviour=frozenset({"rotation"})), ROBOT_PARTS) == ()


@pytest.mark.parametrize("platform_parts", [ROBOT_PARTS, SIMULATOR_PARTS])
def test_all_and_combinations_are_the_union_without_duplicates(platform_parts):
    body = animated_parts(default_configuration(behaviour=frozenset({"body"})), platform_parts)
    for behaviour in ({"body", "hands", "rotation"}, {"body", "hands"}, {"body", "rotation"}):
        parts = animated_parts(default_configuration(behaviour=frozenset(behaviour)), platform_parts)
        assert parts == body
        assert len({motion.part for motion in parts}) == len(parts)
    hands = animated_parts(default_configuration(behaviour=frozenset({"hands"})), platform_parts)
    assert animated_parts(default_configuration(behaviour=frozenset({"hands", "rotation"})),
                          platform_parts) == hands


def test_parts_missing_from_the_topic_file_are_skipped():
    parts = animated_parts(default_configuration(), ["Leg", "LHand", "Wheels"])
    assert [motion.part for motion in parts] == ["LHand", "Leg"]


# ---------------------------------------------------------------------------------------------
# Leg pattern


def test_leg_pattern_of_the_default_configuration():
    pattern = leg_pattern(100, 8, 2)
    chunk = 12
    assert len(pattern) == 100
    expected = ([True, True] + [False] * (chunk - 2)) * 8 + [False] * 4
    assert list(pattern) == expected
    assert sum(pattern) == 16


@pytest.mark.parametrize("num_points, factor, per_chunk, expected", [
    (10, 3, 2, "TTF" "TTF" "TTF" "F"),  # chunk 3, one left over
    (11, 4, 1, "TF" "TF" "TF" "TF" "FFF"),  # chunk 2, three left over
    (5, 5, 1, "TTTTT"),  # legRepeatFactor == numPoints: chunks of one
    (9, 3, 3, "TTTTTTTTT"),  # numPointsLeg == chunk: always random
    (10, 3, 3, "TTTTTTTTT" "F"),
    (7, 1, 0, "FFFFFFF"),
    (1, 1, 1, "T"),
])
def test_leg_pattern_edge_cases(num_points, factor, per_chunk, expected):
    assert leg_pattern(num_points, factor, per_chunk) == tuple(c == "T" for c in expected)


@pytest.mark.parametrize("arguments", [(5, 6, 1), (10, 3, 4), (10, 0, 1), (0, 1, 0)])
def test_leg_pattern_rejects_what_the_configuration_forbids(arguments):
    with pytest.raises(ValueError):
        leg_pattern(*arguments)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 300).flatmap(
    lambda n: st.tuples(st.just(n), st.integers(1, n)).flatmap(
        lambda nf: st.tuples(st.just(nf[0]), st.just(nf[1]), st.integers(0, nf[0] // nf[1])))))
def test_leg_pattern_counts(arguments):
    num_points, factor, per_chunk = arguments
    pattern = leg_pattern(num_points, factor, per_chunk)
    chunk = num_points // factor
    assert len(pattern) == num_points
    assert sum(pattern) == factor * per_chunk
    assert not any(pattern[factor * chunk:])
    for index in range(factor):
        assert pattern[index * chunk:(index + 1) * chunk] == (True,) * per_chunk + (False,) * (
            chunk - per_chunk)


# ---------------------------------------------------------------------------------------------
# Random positions


def test_random_positions_stay_within_bounds_and_limits_for_random_configurations():
    rng = numpy.random.default_rng(20261121)
    for _ in range(200):
        config = random_configuration(rng)
        for motion in animated_parts(config, ROBOT_PARTS):
            positions = random_waypoints(motion, config, rng)
            assert positions.shape == (config.num_points, len(motion.joints))
            lower = numpy.array([bound.lower for bound in motion.bounds])
            upper = numpy.array([bound.upper for bound in motion.bounds])
            assert numpy.all(positions >= lower) and numpy.all(positions <= upper)
            assert numpy.all(positions >= [JOINTS[name].lower for name in motion.joints])
            assert numpy.all(positions <= [JOINTS[name].upper for name in motion.joints])


def test_random_positions_cover_the_bounds_uniformly():
    config = default_configuration(num_points=20000, leg_repeat_factor=1, num_points_leg=1)
    motion = animated_parts(config, ["RArm"])[0]
    positions = random_waypoints(motion, config, make_rng(3))
    for column, bound in enumerate(motion.bounds):
        fraction = (positions[:, column] - bound.lower) / (bound.upper - bound.lower)
        assert abs(fraction.mean() - 0.5) < 0.02
        assert fraction.min() < 0.01 and fraction.max() > 0.99


def test_held_joints_are_exactly_at_their_centre():
    config = default_configuration(behaviour=frozenset({"hands"}))
    for motion in animated_parts(config, ROBOT_PARTS):
        positions = random_waypoints(motion, config, make_rng(1))
        for column, (bound, moves) in enumerate(zip(motion.bounds, motion.moving)):
            if moves:
                assert len(set(positions[:, column])) == config.num_points
            else:
                assert numpy.all(positions[:, column] == bound.centre)


def test_leg_positions_follow_the_leg_pattern():
    config = default_configuration(num_points=30, leg_repeat_factor=4, num_points_leg=3)
    leg = animated_parts(config, ["Leg"])[0]
    positions = random_waypoints(leg, config, make_rng(7))
    pattern = numpy.array(leg_pattern(30, 4, 3))
    centre = numpy.array(PARTS["Leg"].centre)
    assert numpy.all(positions[~pattern] == centre)
    assert numpy.all(positions[pattern] != centre)


def test_same_seed_gives_same_waypoints():
    config = default_configuration()
    parts = animated_parts(config, ROBOT_PARTS)
    first_rng, second_rng = make_rng(42), make_rng(42)
    for motion in parts:
        assert numpy.array_equal(random_waypoints(motion, config, first_rng),
                                 random_waypoints(motion, config, second_rng))
    assert not numpy.array_equal(random_waypoints(parts[0], config, make_rng(42)),
                                 random_waypoints(parts[0], config, make_rng(43)))
    assert isinstance(make_rng(None), numpy.random.Generator)


def test_intensity_scales_every_band_about_its_centre():
    full = {m.part: m for m in animated_parts(default_configuration(), tuple(PARTS))}
    half = {m.part: m for m in animated_parts(default_configuration(intensity=0.5), tuple(PARTS))}
    still = {m.part: m for m in animated_parts(default_configuration(intensity=0.0), tuple(PARTS))}
    for part, motion in full.items():
        for wide, narrow, none in zip(motion.bounds, half[part].bounds, still[part].bounds):
            assert narrow.upper - narrow.centre == pytest.approx(0.5 * (wide.upper - wide.centre))
            assert narrow.centre - narrow.lower == pytest.approx(0.5 * (wide.centre - wide.lower))
            assert none.lower == none.upper == none.centre


def test_switched_off_parts_do_not_move():
    config = default_configuration(move_arms=False, move_leg=False)
    assert [m.part for m in animated_parts(config, tuple(PARTS))] == ["RHand", "LHand"]
    config = default_configuration(move_hands=False)
    assert [m.part for m in animated_parts(config, tuple(PARTS))] == ["RArm", "LArm", "Leg"]
