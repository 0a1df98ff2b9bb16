"""The ease-in (README: "Motion styles"): after an enable, a resume after yielding or a style switch, every joint is in
its band within 3 s, from 0.03, 0.1 and 0.2 rad off its centre on either side. The node's part streams (core/) drive
the simulated Pepper's model (pepper/simulated_pepper.py) in simulated time, no ROS: its controllers' interpolation for
pepper_dcm goals, its naoqi_driver for `/joint_angles`. The ROS 1 rostests breathing_robot.test and
joint_angles_breathing.test start the simulated Pepper off its centres too."""
import numpy
import pytest
from conftest import default_configuration
from fakes import FakeJointStates, FakeLog

from cssr_system.core.foreign_motion import GOAL
from cssr_system.core.joint_angle_stream import JointAngleStream
from cssr_system.core.motion_stream import StreamState
from cssr_system.core.part_stream import PartStream
from cssr_system.motion.joint_angle_stream import PERIOD
from cssr_system.motion.report import band_entry_times, off_centre_starts
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import speed_caps
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.pepper.simulated_pepper import COMMANDED, NAOQI_DRIVER, GoalPoint, SimulatedPepper

EASE_IN = 3.0  # s: the README's bound
STEP = 0.02  # s between the simulated clock's ticks (the joint states' 50 Hz)
WATCH = 4.0  # s watched after each start
STYLES = ("random", "breathing")
ACTUATIONS = ("trajectory", "joint_angles")
ACCELERATION_JUMP = 20.0  # rad/s^2: a velocity jump between two ticks shows far beyond any planned acceleration


class Handle:
    def cancel(self):
        pass

    def release(self):
        pass


class ControllerClient:
    """core/goals.py's client of one controller of the simulated Pepper: each goal is submitted to it at once."""

    def __init__(self, rig, part):
        self.rig, self.part, self.count = rig, part, 0

    @staticmethod
    def ready():
        return True

    @staticmethod
    def goal(joints, timed):
        return joints, [GoalPoint(float(time), p.tolist(), v.tolist(), a.tolist()) for time, p, v, a in
                        zip(timed.times, timed.positions, timed.velocities, timed.accelerations)]

    def send(self, goal, done):
        self.count += 1
        acceptance = self.rig.pepper.controllers[self.part].submit((self.part, self.count), *goal, self.rig.now)
        assert acceptance.accepted, acceptance
        return Handle()


class Topic:
    """naoqi_driver's /joint_angles topic: the simulated Pepper runs each call at once."""

    name = "/joint_angles"

    def __init__(self, rig):
        self.rig = rig

    def send(self, call, now):
        assert self.rig.pepper.joint_angles(call.joint_names, call.joint_angles, call.speed, call.relative, now) is None

    @staticmethod
    def listened():
        return True


class Rig:
    """One part's stream of the node on the simulated Pepper, whose joints start at `start`."""

    def __init__(self, motion, start, actuation):
        self.now, self.part = 0.0, motion.part
        self.joints = PARTS[motion.part].joints
        self.pepper = SimulatedPepper("robot", initial_positions=dict(zip(self.joints, start)),
                                      driver=NAOQI_DRIVER if actuation == "joint_angles" else "ideal",
                                      velocity_report=COMMANDED)
        states = FakeJointStates(self.positions)
        quiet = dict(debug=lambda *args: None, warn=lambda *args: None)
        if actuation == "joint_angles":
            self.stream = JointAngleStream(motion.part, motion.part, Topic(self), lambda: self.now, states, FakeLog(),
                                           **quiet)
        else:
            self.stream = PartStream(motion.part, motion.part, ControllerClient(self, motion.part), lambda: self.now,
                                     states, lambda event: None, FakeLog(), **quiet)
        self.stream.controller_connected()

    def state(self):
        sample = self.pepper.joint_state(self.now)
        index = [sample.names.index(name) for name in self.joints]
        return numpy.array(sample.positions)[index], numpy.array(sample.velocities)[index]

    def positions(self, joints):
        return self.state()[0]

    def run(self, seconds):
        """Ticks the stream for `seconds`: (times since the start of the run, positions, velocities)."""
        origin, times, positions, velocities = self.now, [], [], []
        for _ in range(int(round(seconds / STEP))):
            self.stream.tick()
            where, speed = self.state()
            times.append(self.now - origin)
            positions.append(where)
            velocities.append(speed)
            self.now += STEP
        return numpy.array(times), numpy.array(positions), numpy.array(velocities)


def config_of(style):
    return default_configuration(random_seed=3, motion_style=style, behaviour={"body"})


def motions(style):
    return animated_parts(config_of(style), tuple(PARTS))


def assert_eases_in(motion, times, positions, velocities, why, actuation):
    """Every moving joint in its band within EASE_IN for good, under the speed cap, without a velocity jump (through
    naoqi_driver the speed changes at each call, every PERIOD: each change no more than a smooth motion's then)."""
    moving = numpy.array(motion.moving)
    entry = band_entry_times(times, positions, [b.lower for b in motion.bounds], [b.upper for b in motion.bounds])
    late = {name: float(seconds) for name, seconds, moves in zip(motion.joints, entry, moving)
            if moves and seconds > EASE_IN}
    assert not late, "%s: out of the band after %.1f s: %s" % (why, EASE_IN, late)
    assert (numpy.abs(velocities) <= speed_caps(motion.joints) * 1.001 + 1e-9).all(), why
    jumps = numpy.abs(numpy.diff(velocities, axis=0)).max(axis=0) / (PERIOD if actuation == "joint_angles" else STEP)
    assert (jumps[moving] <= ACCELERATION_JUMP).all(), why
    return entry[moving].max()


@pytest.mark.parametrize("actuation", ACTUATIONS)
@pytest.mark.parametrize("style", STYLES)
def test_after_an_enable_every_joint_enters_its_band_within_3_s_from_off_its_centre(style, actuation):
    latest = 0.0
    for motion in motions(style):
        for offset, start in off_centre_starts(motion):
            rig = Rig(motion, start, actuation)
            rig.stream.enable(motion, MotionStyle(config_of(style), make_rng(3)).planner(motion))
            why = "%s %s %s from %+.2f rad" % (style, actuation, motion.part, offset)
            latest = max(latest, assert_eases_in(motion, *rig.run(WATCH), why, actuation))
    assert latest > 0.5, "the starts lie outside the bands: the approach takes time"


@pytest.mark.parametrize("actuation", ACTUATIONS)
@pytest.mark.parametrize("style", STYLES)
def test_after_a_yield_every_joint_enters_its_band_within_3_s_of_the_resume(style, actuation):
    """Another node's goal moves the leg 0.2 rad off its centres while the part yields; the resume eases in."""
    motion = {m.part: m for m in motions(style)}["Leg"]
    centre = numpy.array(PARTS["Leg"].centre)
    rig = Rig(motion, centre, actuation)
    rig.stream.enable(motion, MotionStyle(config_of(style), make_rng(3)).planner(motion))
    rig.run(2.0)
    away = centre + numpy.array([0.2, -0.2, 0.2])
    zeros = [0.0] * len(away)
    rig.pepper.controllers["Leg"].submit("gesture", motion.joints, [GoalPoint(1.0, away.tolist(), zeros, zeros)],
                                         rig.now)
    if actuation == "joint_angles":  # naoqi_driver moves the joints: the other node's call does it there
        rig.pepper.joint_angles(motion.joints, away.tolist(), 0.1, 0, rig.now)
    rig.stream.foreign_motion("gesture", "/gestureExecution", GOAL, last_point_at=rig.now + 1.0)
    for _ in range(int(round(1.0 / STEP))):
        rig.stream.tick()
        rig.now += STEP
    rig.stream.foreign_result("gesture")
    while rig.stream.state == StreamState.YIELDING:
        rig.stream.tick()
        rig.now += STEP
    numpy.testing.assert_allclose(rig.state()[0], away, atol=1e-3)  # it resumes from where the other node left it
    assert_eases_in(motion, *rig.run(WATCH), "%s %s resumed" % (style, actuation), actuation)


@pytest.mark.parametrize("actuation", ACTUATIONS)
@pytest.mark.parametrize("style,switched_to", [("random", "breathing"), ("breathing", "random")])
def test_after_a_style_switch_every_joint_stays_in_its_band(style, switched_to, actuation):
    """A live switch while the part moves: the new style's first goal starts from the running motion, smoothly."""
    for motion in motions(style):
        start = numpy.array(PARTS[motion.part].centre)
        rig = Rig(motion, start, actuation)
        rig.stream.enable(motion, MotionStyle(config_of(style), make_rng(3)).planner(motion))
        rig.run(2.5)
        switched = {m.part: m for m in motions(switched_to)}[motion.part]
        rig.stream.enable(switched, MotionStyle(config_of(switched_to), make_rng(4)).planner(switched))
        assert_eases_in(switched, *rig.run(WATCH), "%s to %s %s %s" % (style, switched_to, actuation, motion.part),
                        actuation)


def test_the_starts_lie_on_both_sides_of_the_bands_within_the_limits():
    for motion in motions("breathing"):
        starts = list(off_centre_starts(motion))
        assert sorted({offset for offset, _ in starts}) == [-0.2, -0.1, -0.03, 0.03, 0.1, 0.2]
        for _, start in starts:
            assert all(JOINTS[name].lower <= value <= JOINTS[name].upper for name, value in zip(motion.joints, start))
