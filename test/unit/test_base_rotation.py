"""Unit tests of the base rotation planner (pure Python, no ROS)."""
import math

import numpy
import pytest
from hypothesis import given, settings, strategies as st

from cssr_system.motion.base_rotation import (MAX_TURN_TIME, MIN_SAMPLE_RATE, MIN_TURN,
                                              RELATIVE_COMMAND_MARGIN, RETURN_TOLERANCE,
                                              BaseRotationPlanner, RotationStep,
                                              heading_after_interruption,
                                              raised_cosine_velocities)
from cssr_system.pepper.joint_table import (RELATIVE, VELOCITY, wheels_command_kind,
                                            BASE_MAX_ANGULAR_ACCELERATION, BASE_MAX_ANGULAR_VELOCITY,
                                            BASE_MOVETO_ANGULAR_VELOCITY, BASE_MOVETO_SETTLE_TIME,
                                            BASE_VELOCITY_COMMAND_TIMEOUT)

ROUNDING = 1e-12


def planner(kind, rot_maximum_range=0.3, heading_bound=0.3, seed=0, sample_rate=20.0):
    return BaseRotationPlanner(kind, rot_maximum_range, heading_bound,
                               numpy.random.default_rng(seed), sample_rate)


def check_velocity_step(step: RotationStep, rot_maximum_range: float) -> None:
    """Every promise a VELOCITY step makes."""
    assert step.kind == VELOCITY
    samples = numpy.array(step.velocities)
    assert len(samples) >= 2
    assert step.velocities[-1] == 0.0  # an explicit stop, exactly zero
    assert 0.0 < step.period <= 0.1
    assert step.period < BASE_VELOCITY_COMMAND_TIMEOUT
    assert abs(math.fsum(step.velocities) * step.period - step.angle) <= 1e-9
    assert numpy.max(numpy.abs(samples)) <= rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY
    # From rest, through the samples, to the final zero: the plugin's acceleration limit holds.
    accelerations = numpy.diff(numpy.concatenate(([0.0], samples))) / step.period
    assert numpy.max(numpy.abs(accelerations)) <= BASE_MAX_ANGULAR_ACCELERATION
    # One direction only: a smooth bump, no reversal.
    assert numpy.all(samples * math.copysign(1.0, step.angle) >= 0.0)
    assert step.duration >= len(samples) * step.period - ROUNDING
    # The robot is busy while samples are streamed; anything after that is a pause.
    assert step.busy_time == pytest.approx(len(samples) * step.period)
    assert step.busy_time <= step.duration


def check_relative_step(step: RotationStep) -> None:
    assert step.kind == RELATIVE
    assert step.velocities == ()
    assert step.angle != 0.0
    assert step.duration >= abs(step.angle) / BASE_MOVETO_ANGULAR_VELOCITY + BASE_MOVETO_SETTLE_TIME
    # The driver turns then sleeps: the robot is busy that long, and will drop anything sent then.
    assert step.busy_time == pytest.approx(abs(step.angle) / BASE_MOVETO_ANGULAR_VELOCITY
                                           + BASE_MOVETO_SETTLE_TIME + RELATIVE_COMMAND_MARGIN)
    assert step.busy_time <= step.duration


# --- wheels_command_kind ---------------------------------------------------------------------

@pytest.mark.parametrize("topic, kind", [
    ("/pepper_dcm/cmd_moveto", RELATIVE),
    ("/pepper/cmd_vel", VELOCITY),
    ("cmd_moveto", RELATIVE),
    ("/robot1/pepper_dcm/cmd_moveto", RELATIVE),
    ("robot1/pepper_dcm/cmd_moveto/", RELATIVE),
    ("~cmd_moveto", RELATIVE),
    ("/sim/pepper/cmd_vel", VELOCITY),
    ("/pepper_dcm/cmd_moveto_extra", VELOCITY),
    ("/cmd_moveto/cmd_vel", VELOCITY),
    ("/pepper_dcm/cmd.moveto", VELOCITY),  # a dotted name (illegal in ROS) is not special
])
def test_wheels_command_kind(topic, kind):
    assert wheels_command_kind(topic) == kind


def test_wheels_command_kind_rejects_an_empty_name():
    with pytest.raises(ValueError):
        wheels_command_kind("  ")


# --- construction and impossible rotation ----------------------------------------------------

@pytest.mark.parametrize("kind", [RELATIVE, VELOCITY])
def test_no_rotation_when_range_or_bound_is_zero(kind):
    assert planner(kind, rot_maximum_range=0.0).next_step() is None
    assert planner(kind, rot_maximum_range=0.0).return_step() is None
    assert planner(kind, heading_bound=0.0).next_step() is None
    assert planner(kind, heading_bound=0.0).return_step() is None  # already at 0


@pytest.mark.parametrize("arguments", [
    dict(kind="spin"),
    dict(rot_maximum_range=1.5),
    dict(rot_maximum_range=-0.1),
    dict(heading_bound=-0.1),
    dict(heading_bound=float("nan")),
    dict(sample_rate=MIN_SAMPLE_RATE / 2),
])
def test_invalid_arguments_are_refused(arguments):
    values = dict(kind=VELOCITY, rot_maximum_range=0.3, heading_bound=0.3, sample_rate=20.0)
    values.update(arguments)
    with pytest.raises(ValueError):
        BaseRotationPlanner(values["kind"], values["rot_maximum_range"], values["heading_bound"],
                            numpy.random.default_rng(0), values["sample_rate"])


def test_planner_starts_at_heading_zero():
    assert planner(VELOCITY).heading == 0.0


# --- long runs: the heading never drifts ------------------------------------------------------

@pytest.mark.parametrize("kind", [RELATIVE, VELOCITY])
@pytest.mark.parametrize("seed", [1, 2024])
def test_heading_stays_bounded_over_10000_steps(kind, seed):
    bound, rot_range = 0.3, 0.3
    rotation = planner(kind, rot_range, bound, seed)
    integrated = 0.0  # what the base actually does with the commands, open loop
    for _ in range(10000):
        step = rotation.next_step()
        assert -bound <= step.target_heading <= bound
        assert rotation.heading == step.target_heading
        assert abs(step.angle) >= MIN_TURN - ROUNDING
        assert abs(step.angle) <= rot_range * BASE_MAX_ANGULAR_VELOCITY * MAX_TURN_TIME + ROUNDING
        if kind == VELOCITY:
            integrated += math.fsum(step.velocities) * step.period
        else:
            check_relative_step(step)
            integrated += step.angle
        assert abs(integrated - step.target_heading) < 1e-6  # no drift from accumulated rounding
    home = rotation.return_step()
    if home is not None:
        integrated += math.fsum(home.velocities) * home.period if kind == VELOCITY else home.angle
    assert rotation.heading == 0.0
    assert abs(integrated) < 1e-6
    assert rotation.return_step() is None


@pytest.mark.parametrize("kind", [RELATIVE, VELOCITY])
def test_targets_cover_the_whole_interval(kind):
    rotation = planner(kind, seed=7)
    targets = [rotation.next_step().target_heading for _ in range(2000)]
    assert min(targets) < -0.25 and max(targets) > 0.25


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1),
       rot_range=st.floats(0.01, 1.0),
       bound=st.floats(0.001, 1.0),
       sample_rate=st.floats(MIN_SAMPLE_RATE, 100.0),
       kind=st.sampled_from([RELATIVE, VELOCITY]))
def test_every_step_keeps_its_promises(seed, rot_range, bound, sample_rate, kind):
    rotation = planner(kind, rot_range, bound, seed, sample_rate)
    for _ in range(40):
        step = rotation.next_step()
        assert -bound <= step.target_heading <= bound
        assert step.angle != 0.0
        if kind == VELOCITY:
            check_velocity_step(step, rot_range)
        else:
            check_relative_step(step)
    home = rotation.return_step()
    if home is not None:
        (check_velocity_step(home, rot_range) if kind == VELOCITY else check_relative_step(home))
        assert home.target_heading == 0.0
        assert rotation.heading == 0.0
    else:  # already home, to within the tolerance below which no turn is sent
        assert abs(rotation.heading) < RETURN_TOLERANCE


# --- odometry feedback and the way home -------------------------------------------------------

@pytest.mark.parametrize("kind", [RELATIVE, VELOCITY])
def test_return_step_brings_a_measured_heading_back(kind):
    rotation = planner(kind)
    rotation.set_heading(0.25)
    home = rotation.return_step()
    assert home.target_heading == 0.0 and home.angle == pytest.approx(-0.25)
    assert rotation.heading == 0.0
    if kind == VELOCITY:
        check_velocity_step(home, 0.3)
    else:
        check_relative_step(home)
        # The way home waits only for the robot, no random pause.
        assert home.duration == pytest.approx(0.25 / BASE_MOVETO_ANGULAR_VELOCITY + RELATIVE_COMMAND_MARGIN
                                              + BASE_MOVETO_SETTLE_TIME)


def test_return_step_is_none_within_tolerance():
    rotation = planner(VELOCITY)
    rotation.set_heading(RETURN_TOLERANCE / 2)
    assert rotation.return_step() is None


@pytest.mark.parametrize("kind", [RELATIVE, VELOCITY])
def test_a_measured_heading_beyond_the_bound_is_brought_inside(kind):
    rotation = planner(kind)
    for measured in (2.0, -2.0, 0.31, -0.45):
        rotation.set_heading(measured)
        step = rotation.next_step()
        assert -0.3 <= step.target_heading <= 0.3
        assert step.angle == pytest.approx(step.target_heading - measured)


def test_set_heading_refuses_nan():
    with pytest.raises(ValueError):
        planner(VELOCITY).set_heading(float("nan"))


def test_a_bound_smaller_than_the_minimum_turn_still_moves():
    rotation = planner(RELATIVE, heading_bound=0.005)
    for _ in range(100):
        step = rotation.next_step()
        assert -0.005 <= step.target_heading <= 0.005 and step.angle != 0.0


# --- velocity profile --------------------------------------------------------------------------

def test_raised_cosine_is_smooth_and_exact():
    samples = raised_cosine_velocities(0.3, 40, 0.05)
    assert samples[-1] == 0.0
    assert abs(math.fsum(samples) * 0.05 - 0.3) <= 1e-12
    assert samples[0] == pytest.approx(samples[-2])  # symmetric: starts and ends gently
    assert max(samples) == pytest.approx(2 * 0.3 / (40 * 0.05))


def test_same_seed_same_plan():
    first, second = planner(VELOCITY, seed=5), planner(VELOCITY, seed=5)
    assert [first.next_step() for _ in range(20)] == [second.next_step() for _ in range(20)]


def test_velocity_duration_includes_a_pause():
    step = planner(VELOCITY, seed=3).next_step()
    assert step.duration > len(step.velocities) * step.period


def test_an_interrupted_turn_leaves_the_heading_where_the_sent_samples_and_braking_take_it():
    rotation = planner(VELOCITY, 0.3, 0.3, seed=5)
    step = rotation.next_step()
    start = step.target_heading - step.angle
    assert heading_after_interruption(step, 0) == start
    assert heading_after_interruption(step, len(step.velocities)) == pytest.approx(step.target_heading)
    middle = len(step.velocities) // 2
    speed = step.velocities[middle - 1]
    expected = (start + math.fsum(step.velocities[:middle]) * step.period
                + math.copysign(speed * speed / (2 * BASE_MAX_ANGULAR_ACCELERATION), speed))
    assert heading_after_interruption(step, middle) == pytest.approx(expected)
    # Braking carries the base further the way it was turning.
    assert abs(heading_after_interruption(step, middle) - start) > abs(
        math.fsum(step.velocities[:middle]) * step.period)
