"""The first goal of the random style (motion/planners.py): from the measured pose at rest, as after an enable or a
yield, it accelerates no more than the style does later on (the breathing style's own check is in test_breathing)."""
import numpy
import pytest
from conftest import default_configuration

from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import to_points
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

GOALS = 6  # the first goal, then five more from where each ends


def peak_accelerations(spline, start, end):
    times = numpy.linspace(start, end, 400)
    return numpy.abs(numpy.array([spline.sample(moment)[2] for moment in times])).max(axis=0)


@pytest.mark.parametrize("seed", range(4))
def test_the_first_random_segment_accelerates_no_more_than_the_style(seed):
    config = default_configuration(random_seed=seed)
    style = MotionStyle(config, make_rng(seed))
    for motion in animated_parts(config, tuple(PARTS)):
        planner = style.planner(motion)
        zeros = numpy.zeros(len(motion.joints))
        state, now, first, later = (numpy.array(PARTS[motion.part].centre), zeros, zeros), 0.0, None, 0.0
        for goal in range(GOALS):
            timed = planner(now, *state)
            spline = JointTrajectorySpline(*state, to_points(timed), start_time=now)
            if goal == 0:
                first = peak_accelerations(spline, now, now + timed.times[0])
                later = peak_accelerations(spline, now + timed.times[0], spline.end_time)
            else:
                later = numpy.maximum(later, peak_accelerations(spline, now, spline.end_time))
            now = spline.end_time
            state = (numpy.asarray(spline.sample(now)[0]), zeros, zeros)
        assert first.max() <= later.max() * 1.0001, motion.part


def test_the_tempo_paces_the_random_style():
    """breathsPerMinute is the tempo of both styles: at twice the reference tempo gestures take half as long."""
    for tempo, factor in ((12.0, 1.0), (24.0, 0.5), (6.0, 2.0)):
        config = default_configuration(random_seed=3, breaths_per_minute=tempo, num_points=6)
        motion = animated_parts(config, ("RArm",))[0]
        start = numpy.array(PARTS["RArm"].centre)
        timed = MotionStyle(config, make_rng(3)).planner(motion)(0.0, start, numpy.zeros(5), numpy.zeros(5))
        assert numpy.diff(timed.times).min() >= config.gesture_duration * factor - 1e-9
        assert numpy.diff(timed.times).min() == pytest.approx(config.gesture_duration * factor, rel=0.5)
