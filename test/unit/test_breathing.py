"""Unit tests of the breathing motion style (motion/breathing.py, motion/styles.py): no ROS."""
import numpy
import pytest
from conftest import default_configuration

from cssr_system.motion.breathing import CONTINUATION_LEAD, EASE_IN, POINT_SPACING, BreathingPlanner
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import speed_caps, to_points
from cssr_system.motion.waypoints import animated_parts, make_rng, narrow_bands
from cssr_system.pepper.joint_table import DRIVER_JOINT_PRECISION, JOINTS, PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

BREATHING = default_configuration(motion_style="breathing", random_seed=5)


def motions(config=BREATHING):
    return {motion.part: motion for motion in animated_parts(config, tuple(PARTS))}


def run(config=BREATHING, seconds=120.0, parts=("RArm", "LArm", "Leg", "RHand"), seed=5, start=None):
    """What the controllers execute when the node chains the style's goals as it does: each goal replaces the
    previous one CONTINUATION_LEAD s before its ending begins, from the state the controller is in. Returns, per
    part, the splines with their switch times, and the samples (times, positions, velocities, accelerations) at
    50 Hz."""
    style = MotionStyle(config, make_rng(seed))
    result = {}
    for part in parts:
        motion = motions(config)[part]
        plan = style.planner(motion)
        joints = PARTS[part].joints
        now = 0.0
        state = (numpy.array(PARTS[part].centre) if start is None else start, numpy.zeros(len(joints)),
                 numpy.zeros(len(joints)))
        pieces = []
        while now < seconds:
            timed = plan(now, *state)
            spline = JointTrajectorySpline(state[0], state[1], state[2], to_points(timed), start_time=now)
            switch = now + timed.times[-2] - CONTINUATION_LEAD
            pieces.append((now, spline))
            now = switch
            state = tuple(numpy.asarray(values) for values in spline.sample(now))
        times = numpy.arange(0.0, seconds, 0.02)
        samples = []
        for moment in times:
            spline = [piece for start_time, piece in pieces if start_time <= moment][-1]
            samples.append(spline.sample(moment))
        result[part] = (times, numpy.array([s[0] for s in samples]), numpy.array([s[1] for s in samples]),
                        numpy.array([s[2] for s in samples]))
    return result


@pytest.fixture(scope="module")
def two_minutes():
    return run()


def test_every_joint_stays_in_its_band_and_held_joints_at_their_centre(two_minutes):
    for part, (times, positions, _, _) in two_minutes.items():
        for index, bounds in enumerate(motions()[part].bounds):
            after_blend = positions[times > 2.0, index]
            assert after_blend.min() >= bounds.lower - 1e-9 and after_blend.max() <= bounds.upper + 1e-9, bounds.name
    held = motions(default_configuration(motion_style="breathing", behaviour=frozenset({"hands"})))["RArm"]
    planner = MotionStyle(BREATHING, make_rng(1)).planner(held)
    timed = planner(0.0, numpy.array(PARTS["RArm"].centre), numpy.zeros(5), numpy.zeros(5))
    for index, moving in enumerate(held.moving):
        if not moving:
            assert (timed.positions[:, index] == PARTS["RArm"].centre[index]).all()


def test_under_the_speed_cap_everywhere(two_minutes):
    for part, (_, _, velocities, _) in two_minutes.items():
        caps = speed_caps(PARTS[part].joints)
        assert (numpy.abs(velocities) <= caps * 1.001).all(), part


def test_c2_continuous_across_goals(two_minutes):
    """The executed velocity and acceleration change smoothly at every splice: no step larger than what the
    motion itself does from one 20 ms sample to the next."""
    for part, (times, _, velocities, accelerations) in two_minutes.items():
        after_blend = times > 2.0  # the first goal's blend from rest at enable is no splice
        assert numpy.abs(numpy.diff(velocities[after_blend], axis=0)).max() < 0.01, part
        assert numpy.abs(numpy.diff(accelerations[after_blend], axis=0)).max() < 0.05, part


def test_rhythm_at_the_configured_rate():
    for breaths in (6.0, 12.0, 18.0):
        config = BREATHING._replace(breaths_per_minute=breaths)
        times, positions, _, _ = run(config, seconds=120.0, parts=("RArm",))["RArm"]
        signal = positions[:, 0] - positions[:, 0].mean()  # RShoulderPitch
        spectrum = numpy.abs(numpy.fft.rfft(signal))
        frequencies = numpy.fft.rfftfreq(len(signal), d=times[1] - times[0])
        spectrum[frequencies < 0.05] = 0.0  # the slow variation is not the rhythm
        dominant = 1.0 / frequencies[numpy.argmax(spectrum)]
        assert dominant == pytest.approx(60.0 / breaths, rel=0.08)


def test_both_sides_move_together(two_minutes):
    _, right, _, _ = two_minutes["RArm"]
    _, left, _, _ = two_minutes["LArm"]
    pitch = numpy.corrcoef(right[:, 0], left[:, 0])[0, 1]
    roll = numpy.corrcoef(right[:, 1], -left[:, 1])[0, 1]  # roll joints mirror each other
    assert pitch > 0.8 and roll > 0.8


def test_never_repeats_exactly_over_an_hour():
    function = BreathingPlanner(motions()["RArm"], BREATHING, {}, make_rng(3), {}).function
    times = numpy.arange(0.0, 3600.0, 0.25)
    values = numpy.array([function.sample(moment)[0][0] for moment in times])
    window = int(60 / 0.25)
    first = values[:window]
    for lag in range(window, len(values) - window, 20):  # every 5 s: no minute is a copy of the first
        assert numpy.abs(values[lag:lag + window] - first).max() > 1e-3


def test_reproducible_with_a_seed():
    first = run(seconds=30.0, parts=("LArm", "Leg"), seed=9)
    second = run(seconds=30.0, parts=("LArm", "Leg"), seed=9)
    other = run(seconds=30.0, parts=("LArm", "Leg"), seed=10)
    for part in ("LArm", "Leg"):
        numpy.testing.assert_array_equal(first[part][1], second[part][1])
        assert numpy.abs(first[part][1] - other[part][1]).max() > 1e-3


def test_the_first_goal_blends_from_far_away_under_the_cap():
    start = numpy.array(PARTS["RArm"].centre) + numpy.array([-0.25, -0.2, 0.3, 0.2, 0.2])  # after a gesture
    times, positions, velocities, _ = run(seconds=15.0, parts=("RArm",), start=start)["RArm"]
    numpy.testing.assert_allclose(positions[0], start, atol=1e-9)
    assert (numpy.abs(velocities) <= speed_caps(PARTS["RArm"].joints) * 1.001).all()


def test_the_robot_driver_dead_band_warning_names_the_narrow_joints():
    lines = narrow_bands(list(motions().values()), DRIVER_JOINT_PRECISION)
    assert [line.split()[0] for line in lines] == ["HipRoll", "KneePitch"]
    wide = default_configuration(leg_maximum_range=(0.3, 0.3, 0.3))
    assert narrow_bands(list(motions(wide).values()), DRIVER_JOINT_PRECISION) == []


@pytest.mark.parametrize("offset", [0.0, 0.15])
def test_the_first_goal_accelerates_no_more_than_the_style(offset):
    """After an enable (at rest at the centre) or a yield (at rest wherever another node left the part), the first
    goal eases in: its accelerations stay within the most the style itself ever accelerates, unless so gentle a
    blend would leave a joint out of its band past EASE_IN (the leg, whose narrow bands barely accelerate): then the
    blend is the gentlest that still brings every joint in by then."""
    for part in ("RArm", "LHand", "Leg"):
        joints = PARTS[part].joints
        start = numpy.array(PARTS[part].centre) + offset * numpy.resize([1.0, -1.0], len(joints))
        start = numpy.clip(start, [JOINTS[name].lower for name in joints], [JOINTS[name].upper for name in joints])
        times, _, _, accelerations = run(seconds=12.0, parts=(part,), start=start)[part]
        planner = MotionStyle(BREATHING, make_rng(5)).planner(motions()[part])
        state = (start, numpy.zeros(len(joints)), numpy.zeros(len(joints)))
        first = planner(0.0, *state).times[0]
        peak = numpy.abs(accelerations[times <= first]).max()
        assert planner.ease_in(0.0, state, first) <= EASE_IN, part
        if peak > planner.function.peak_acceleration * 1.001:
            assert planner.ease_in(0.0, state, first + POINT_SPACING) > EASE_IN, part


def test_the_style_bound_of_acceleration_holds_over_two_minutes(two_minutes):
    for part, (times, _, _, accelerations) in two_minutes.items():
        bound = MotionStyle(BREATHING, make_rng(5)).planner(motions()[part]).function.peak_acceleration
        assert numpy.abs(accelerations).max() <= bound * 1.001, part


ENDING_CASES = [(12.0, 0.6, 3.0), (5.0, 1.0, 17.0), (20.0, 1.0, 41.0), (20.0, 0.3, 8.0), (8.0, 1.0, 63.0)]


@pytest.mark.parametrize("breaths_per_minute,amplitude,start", ENDING_CASES)
def test_a_goal_that_no_next_goal_replaces_comes_to_rest_smoothly_in_its_band(breaths_per_minute, amplitude, start):
    """Every goal ends at rest (velocity and acceleration exactly 0, as ROS 2 Jazzy's controller requires). Played
    to its end, as when the node dies, each joint slows to rest inside its band, accelerating no more than the style
    does on that joint, under the speed cap, and the ending begins after the time the next goal would replace it."""
    config = default_configuration(motion_style="breathing", random_seed=5, breaths_per_minute=breaths_per_minute,
                                   breathing_amplitude=amplitude)
    style = MotionStyle(config, make_rng(5))
    for part, motion in motions(config).items():
        plan = style.planner(motion)
        joints = PARTS[part].joints
        state = (numpy.array(PARTS[part].centre), numpy.zeros(len(joints)), numpy.zeros(len(joints)))
        plan(0.0, *state)  # the style's clock starts at 0
        for goal_start in (start, start + 2.9, start + 7.7):
            state = plan.function.sample(goal_start)
            timed = plan(goal_start, *state)
            assert not timed.velocities[-1].any() and not timed.accelerations[-1].any(), part
            assert plan.replacement_time(timed) < timed.times[-2], "replaced before the ending begins"
            spline = JointTrajectorySpline(*state, to_points(timed), start_time=0.0)
            moments = numpy.linspace(timed.times[-2], timed.times[-1] + 0.5, 400)
            samples = [spline.sample(moment) for moment in moments]
            positions, velocities, accelerations = (numpy.array([s[k] for s in samples]) for k in range(3))
            assert (numpy.abs(velocities) <= speed_caps(joints)).all(), part
            assert (numpy.abs(accelerations) <= plan.function.peak_accelerations * 1.001 + 1e-12).all(), part
            lower = [bounds.lower for bounds in motion.bounds]
            upper = [bounds.upper for bounds in motion.bounds]
            assert (positions >= numpy.array(lower) - 1e-9).all() and (positions <= numpy.array(upper) + 1e-9).all()
            assert numpy.abs(velocities[-1]).max() < 1e-12, "at rest after the last point"
