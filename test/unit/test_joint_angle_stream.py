"""Unit tests of streaming planned motions as /joint_angles messages (motion/joint_angle_stream.py), executed by
the model of naoqi_driver (simulated_pepper.NaoqiDriver); no ROS."""
from typing import Any, List, NamedTuple

import numpy
import pytest
from conftest import default_configuration

from cssr_system.motion import joint_angle_stream as stream
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import to_points
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import JOINTS, PARTS, SPEED_FRACTION
from cssr_system.pepper.simulated_pepper import NaoqiDriver
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline, TrajectoryPoint

SECONDS = 20.0
SAMPLE_PERIOD = 0.02  # s: 50 Hz, as /joint_states
STREAMED_PARTS = ("RArm", "LArm", "Leg", "RHand", "LHand")
TRACKING = 0.02  # rad (unit for the hands): largest allowed executed - planned
MOVING = 0.01  # fraction of a joint's maximum speed above which the plan moves it
STILL_SHARE = 0.02  # largest allowed share of moving samples where the executed joint is still


class ChainedPlans:
    """A part's goals chained as the node chains them (test_breathing.run): each replaces the previous one at its
    switch time, from the state the previous one is in; sampled like one spline."""

    def __init__(self, config, style: MotionStyle, part: str, seconds: float) -> None:
        motion = {motion.part: motion for motion in animated_parts(config, tuple(PARTS))}[part]
        plan = style.planner(motion)
        count = len(PARTS[part].joints)
        state = (numpy.array(PARTS[part].centre), numpy.zeros(count), numpy.zeros(count))
        self.pieces, now = [], 0.0
        while now < seconds + 1.0:
            timed = plan(now, *state)
            spline = JointTrajectorySpline(*state, to_points(timed), start_time=now)
            self.pieces.append((now, spline))
            replaced_after = plan.replacement_time(timed)
            now = spline.end_time if replaced_after is None else now + replaced_after
            state = tuple(numpy.asarray(values) for values in spline.sample(now))

    def sample(self, t):
        started = [spline for start, spline in self.pieces if start <= t]
        return (started[-1] if started else self.pieces[0][1]).sample(t)

    @property
    def end_time(self):
        return self.pieces[-1][1].end_time


class AllParts:
    """Several parts' plans sampled as one motion of all their joints (names: PARTS order of each part)."""

    def __init__(self, style_name: str, seed: int, parts=STREAMED_PARTS, seconds: float = SECONDS) -> None:
        config = default_configuration(motion_style=style_name, random_seed=seed)
        style = MotionStyle(config, make_rng(seed))
        self.plans = [ChainedPlans(config, style, part, seconds) for part in parts]
        self.names = tuple(name for part in parts for name in PARTS[part].joints)

    def sample(self, t):
        samples = [plan.sample(t) for plan in self.plans]
        return tuple(numpy.concatenate([sample[k] for sample in samples]) for k in range(3))

    @property
    def end_time(self):
        return min(plan.end_time for plan in self.plans)


class Executed(NamedTuple):
    """A streamed motion at 50 Hz: planned and executed positions and velocities (samples x joints)."""

    times: numpy.ndarray
    planned: numpy.ndarray
    planned_velocities: numpy.ndarray
    positions: numpy.ndarray
    velocities: numpy.ndarray
    messages: List[list]  # the messages of each tick
    arrival_error: float  # largest distance between where a tick expected the joints and where they were
    driver: Any  # the NaoqiDriver, at the end of the stream


def executed(motion, names, seconds=SECONDS, jitter=0.0) -> Executed:
    """Stream `motion` into a NaoqiDriver at the send times (each late by up to `jitter` s) as the node would, each
    tick's origins being the previous tick's arrivals."""
    rng = numpy.random.default_rng(1)
    times = numpy.arange(0.0, seconds, SAMPLE_PERIOD)
    start = motion.sample(0.0)[0]
    driver = NaoqiDriver(names, start, 0.0)
    origins, messages, arrival_error = start, [], 0.0
    rows, sample = [], 0
    sends = stream.send_times(0.0, seconds)
    for index, nominal in enumerate(sends):
        now = nominal + (rng.uniform(0.0, jitter) if jitter else 0.0)
        # Samples before this tick see the previous ticks' calls only.
        while sample < len(times) and times[sample] < now:
            rows.append((times[sample],) + driver.state(times[sample]))
            sample += 1
        arrival_error = max(arrival_error, float(numpy.abs(driver.state(now)[0] - origins).max()))
        tick = stream.tick(names, motion, now, origins)
        for message in tick.messages:
            driver.set_angles(message.joint_names, message.joint_angles, message.speed, now, message.relative)
        messages.append(tick.messages)
        origins = tick.arrivals
    while sample < len(times):
        rows.append((times[sample],) + driver.state(times[sample]))
        sample += 1
    planned = [motion.sample(t) for t in times]
    return Executed(times, numpy.array([p[0] for p in planned]), numpy.array([p[1] for p in planned]),
                    numpy.array([row[1] for row in rows]), numpy.array([row[2] for row in rows]), messages,
                    arrival_error, driver)


def maximum_velocities(names):
    return numpy.array([JOINTS[name].max_velocity for name in names])


@pytest.fixture(scope="module", params=[("breathing", 5), ("random", 3), ("random", 11)], ids=str)
def streamed(request):
    style_name, seed = request.param
    motion = AllParts(style_name, seed)
    return motion, executed(motion, motion.names)


def test_the_choices():
    assert stream.RATE >= 10.0 and stream.PERIOD == 1.0 / stream.RATE and stream.LOOK_AHEAD == stream.PERIOD
    assert 0.0 < stream.SPEED_FLOOR < stream.STOP_SPEED <= SPEED_FRACTION and stream.GROUP_RATIO > 1.0


def test_send_times_every_period_up_to_the_end():
    times = stream.send_times(2.0, 3.05)
    numpy.testing.assert_allclose(numpy.diff(times), stream.PERIOD)
    assert times[0] == 2.0 and times[-1] < 3.05 <= times[-1] + stream.LOOK_AHEAD
    assert stream.send_times(1.0, 1.0).tolist() == [1.0]  # a plan that has ended still gets its last message
    assert len(stream.send_times(0.0, 1000.0)) == 10000 and stream.send_times(0.0, 1000.0)[-1] == 999.9


def test_targets_are_the_plan_one_look_ahead_ahead_clamped_into_the_limits():
    names = ("HipPitch", "RShoulderPitch")
    upper = JOINTS["HipPitch"].upper
    spline = JointTrajectorySpline([0.0, 1.0], None, None, [TrajectoryPoint(1.0, [upper + 0.5, 1.5])])
    targets = stream.stream_targets(spline, 0.4, 0.1, names)
    planned = spline.sample(0.5)[0]
    assert targets[1] == planned[1] and targets[0] == min(planned[0], upper)
    assert stream.stream_targets(spline, 5.0, 0.1, names).tolist() == [upper, 1.5]


def test_speed_fraction_covers_the_distance_in_one_period_within_its_bounds():
    names = ("RShoulderPitch", "HipRoll", "LHand", "KneePitch")
    vmax = maximum_velocities(names)
    needed = numpy.array([0.05, 0.15, 0.0001, 0.7])
    origins = numpy.array([1.0, 0.0, 0.5, 0.0])
    targets = origins + numpy.array([1.0, -1.0, 1.0, 1.0]) * needed * vmax * stream.PERIOD
    fractions = stream.speed_fraction(names, origins, targets)
    assert (fractions[:2] >= needed[:2]).all() and (fractions[:2] <= needed[:2] * stream.GROUP_RATIO * 1.0001).all()
    assert fractions[2] == pytest.approx(stream.SPEED_FLOOR, rel=1e-6)  # slower than the floor
    assert fractions[3] <= SPEED_FRACTION and fractions[3] == pytest.approx(SPEED_FRACTION)  # faster than the cap
    assert numpy.array(fractions, dtype=numpy.float32).tolist() == fractions.tolist()
    arrivals = stream.arrivals(names, origins, targets, fractions)
    numpy.testing.assert_array_equal(arrivals[:3], targets[:3])  # in time: exactly at their targets
    assert arrivals[3] == pytest.approx(SPEED_FRACTION * vmax[3] * stream.PERIOD, rel=1e-6)  # the capped one lags


def test_one_message_per_speed_and_none_for_joints_that_stay():
    names = ("RShoulderPitch", "LShoulderPitch", "HipPitch", "HipRoll")
    messages = stream.group_messages(names, [1.0, 2.0, 0.1, 0.2], [0.05, 0.05, 0.01, 0.2], [True, True, True, False])
    assert messages == [stream.JointAngles(("HipPitch",), (0.1,), 0.01),
                        stream.JointAngles(("RShoulderPitch", "LShoulderPitch"), (1.0, 2.0), 0.05)]
    held = JointTrajectorySpline([0.1, 0.2], None, None, [TrajectoryPoint(5.0, [0.1, 0.2])])
    tick = stream.tick(("HipPitch", "HipRoll"), held, 1.0, numpy.array([0.1, 0.2], dtype=numpy.float32))
    assert tick.messages == []


def test_the_executed_motion_tracks_the_plan(streamed):
    motion, run = streamed
    error = numpy.abs(run.positions - run.planned).max()
    assert error < TRACKING, error
    assert run.arrival_error < 1e-6  # every joint is where the stream expects it at each send time


def test_no_joint_moves_faster_than_the_cap(streamed):
    motion, run = streamed
    assert (numpy.abs(run.velocities) <= SPEED_FRACTION * maximum_velocities(motion.names)).all()


def test_the_joints_move_continuously(streamed):
    motion, run = streamed
    moving = numpy.abs(run.planned_velocities) > MOVING * maximum_velocities(motion.names)
    still = moving & (run.velocities == 0.0)
    assert moving.sum() > 1000
    assert still.sum() / moving.sum() < STILL_SHARE
    assert numpy.mean([len(tick) for tick in run.messages]) <= len(motion.names)


def test_send_times_up_to_10_ms_late_still_track():
    motion = AllParts("random", 3, parts=("RArm", "Leg"))
    run = executed(motion, motion.names, jitter=0.01)
    assert numpy.abs(run.positions - run.planned).max() < TRACKING
    assert (numpy.abs(run.velocities) <= SPEED_FRACTION * maximum_velocities(motion.names)).all()


def test_a_start_far_from_the_plan_is_capped_and_the_arrivals_follow_it():
    names = ("RShoulderPitch", "HipPitch")
    spline = JointTrajectorySpline([1.5, 0.0], None, None, [TrajectoryPoint(1.0, [1.6, 0.1])])
    driver = NaoqiDriver(names, [0.5, 0.0], 0.0)  # a whole radian away from the plan's start
    origins = numpy.array([0.5, 0.0])
    for now in stream.send_times(0.0, 3.0):
        numpy.testing.assert_allclose(driver.state(now)[0], origins, atol=1e-9)
        tick = stream.tick(names, spline, now, origins)
        for message in tick.messages:
            assert message.speed <= SPEED_FRACTION
            driver.set_angles(message.joint_names, message.joint_angles, message.speed, now)
        origins = tick.arrivals
    numpy.testing.assert_allclose(driver.state(3.0)[0], [1.6, 0.1], atol=1e-6)


def test_the_stop_message_sends_every_joint_to_its_centre_calmly(streamed):
    motion, run = streamed
    driver = run.driver
    positions, _ = driver.state(SECONDS)
    current = dict(zip(motion.names, positions.tolist()))
    centre = {name: part.centre[part.joints.index(name)] for part in PARTS.values() for name in part.joints}
    message = stream.stop_message(current, centre)
    assert message.joint_names == motion.names and message.speed == pytest.approx(stream.STOP_SPEED)
    driver.set_angles(message.joint_names, message.joint_angles, message.speed, SECONDS, message.relative)
    duration = stream.stop_duration(current, message)
    assert 0.0 < duration < 2.0
    _, velocities = driver.state(SECONDS + 0.01)
    assert (numpy.abs(velocities) <= stream.STOP_SPEED * maximum_velocities(motion.names) * 1.0001).all()
    arrived, velocities = driver.state(SECONDS + duration + 1e-9)  # a rounding error after the slowest arrives
    numpy.testing.assert_allclose(arrived, [centre[name] for name in motion.names], atol=0.01)
    assert not velocities.any()


def test_how_long_another_nodes_set_angles_call_runs():
    where = {"RShoulderPitch": 1.5, "HipPitch": 0.0}
    vmax = maximum_velocities(("RShoulderPitch", "HipPitch"))
    duration = stream.set_angles_duration(("RShoulderPitch", "HipPitch", "HeadYaw"), (1.0, 0.05, 0.5), 0.1, 0, where)
    assert duration == pytest.approx(max(0.5 / (0.1 * vmax[0]), 0.05 / (0.1 * vmax[1])))
    relative = stream.set_angles_duration(("HipPitch",), (0.05,), 0.1, 1, where)
    assert relative == pytest.approx(0.05 / (0.1 * vmax[1]))
    beyond = stream.set_angles_duration(("HipPitch",), (10.0,), 1.0, 0, where)  # clamped into the limits
    assert beyond == pytest.approx(JOINTS["HipPitch"].upper / vmax[1])
    assert stream.set_angles_duration(("HipPitch",), (0.5,), 0.0, 0, where) == 0.0  # refused by naoqi_driver
    assert stream.set_angles_duration(("HipPitch", "RShoulderPitch"), (0.5,), 0.1, 0, where) == 0.0
