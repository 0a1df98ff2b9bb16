"""Unit tests of one part's joint_angles stream (core/joint_angle_stream.py) with a fake topic and clock, its calls
executed by the model of naoqi_driver (simulated_pepper.NaoqiDriver): no ROS master."""
import numpy
import pytest
from conftest import default_configuration
from fakes import FakeJointStates, FakeLog

from cssr_system.animate_behaviour import contract
from cssr_system.core.foreign_motion import JOINT_ANGLES
from cssr_system.core.joint_angle_stream import JointAngleStream, next_send_time, send_phase
from cssr_system.core.motion_stream import StreamState
from cssr_system.motion import joint_angle_stream as streaming
from cssr_system.motion.breathing import CONTINUATION_LEAD
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import JOINTS, PARTS, SPEED_FRACTION
from cssr_system.pepper.simulated_pepper import NaoqiDriver

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"
TOPIC = "/joint_angles"
OTHER = "/gestureExecution"


class FakeTopic:
    def __init__(self):
        self.name = TOPIC
        self.calls = []  # (time, JointAngles)
        self.listening = True

    def send(self, angles, now):
        self.calls.append((now, angles))

    def listened(self):
        return self.listening


class Rig:
    """A part's stream whose calls a NaoqiDriver executes; `now` is the clock, /joint_states the driver's state."""

    def __init__(self, part="RArm", style="random", connected=True, measured=True):
        self.now = 100.0
        self.part = part
        self.joints = PARTS[part].joints
        self.topic = FakeTopic()
        self.log = FakeLog()
        self.warnings = []
        self.driver = NaoqiDriver(self.joints, PARTS[part].centre, self.now)
        self.measured = measured
        self.joint_states = FakeJointStates(self.positions)
        self.stream = JointAngleStream(part, ACTION, self.topic, lambda: self.now, self.joint_states, self.log,
                                       debug=lambda *args: None,
                                       warn=lambda text, *args: self.warnings.append(text % args))
        if connected:
            self.stream.controller_connected()
        config = default_configuration(random_seed=7, motion_style=style)
        self.motion = {m.part: m for m in animated_parts(config, tuple(PARTS))}[part]
        self.plan = MotionStyle(config, make_rng(7)).planner(self.motion)

    def positions(self, joints):
        assert joints == self.joints
        return self.driver.state(self.now)[0] if self.measured else None

    def enable(self):
        self.stream.enable(self.motion, self.plan)

    def step(self):
        """The supervisor's tick: the stream runs what is due, and naoqi_driver executes the new calls at once."""
        count = len(self.topic.calls)
        self.stream.tick()
        self.execute(count)

    def execute(self, since):
        for at, call in self.topic.calls[since:]:
            self.driver.set_angles(call.joint_names, call.joint_angles, call.speed, at, call.relative)

    def run_until(self, end, samples=None):
        """The supervisor's loop: it wakes at each deadline; `samples` gets the driver's state every 20 ms."""
        while True:
            deadline = self.stream.next_deadline()
            wake = min(deadline if deadline is not None else end, end)
            if samples is not None:
                for t in numpy.arange(self.now, wake, 0.02):
                    samples.append((t,) + self.driver.state(t))
            self.now = wake
            if self.now >= end:
                return
            self.step()

    def bands(self):
        return numpy.array([b.lower for b in self.motion.bounds]), numpy.array([b.upper for b in self.motion.bounds])


def test_enable_streams_at_once_then_at_every_tenth_of_a_second_on_a_grid():
    rig = Rig()
    rig.now = 100.03
    rig.enable()
    assert rig.stream.state == StreamState.ANIMATING and rig.topic.calls == []
    rig.step()
    assert {at for at, _ in rig.topic.calls} == {100.03}
    assert rig.stream.next_deadline() == pytest.approx(100.1)  # the grid time after half a period
    rig.run_until(103.0)
    times = sorted({at for at, _ in rig.topic.calls})
    assert numpy.allclose(numpy.diff(times[1:]), streaming.PERIOD) and times[1] == pytest.approx(100.1)
    assert len(rig.log.events(contract.GOAL_SENT)) >= 1
    assert next_send_time(100.06) == pytest.approx(100.2) and next_send_time(100.1) == pytest.approx(100.2)


def test_each_part_sends_a_fifth_of_a_period_after_the_previous_one_so_no_burst_holds_more_than_an_arm():
    assert [send_phase(part) for part in PARTS] == pytest.approx([0.0, 0.02, 0.04, 0.06, 0.08])
    assert next_send_time(100.03, 0.02) == pytest.approx(100.12)
    assert next_send_time(100.0, 0.08) == pytest.approx(100.08)
    rig = Rig(part="Leg")
    rig.enable()
    rig.run_until(102.0)
    times = sorted({round(at, 6) for at, _ in rig.topic.calls})[1:]
    assert numpy.allclose(numpy.remainder(numpy.array(times) - 0.08 + 0.05, 0.1), 0.05)
    assert max(len([1 for at, _ in rig.topic.calls if round(at, 6) == t]) for t in times) <= len(PARTS["Leg"].joints)


def test_a_tick_between_send_times_sends_nothing():
    rig = Rig()
    rig.enable()
    rig.step()
    count = len(rig.topic.calls)
    rig.now += 0.03
    rig.step()
    assert len(rig.topic.calls) == count


def test_the_calls_stay_inside_the_bands_under_the_speed_cap_and_the_joints_follow_the_plan():
    rig = Rig()
    rig.enable()
    samples = []
    rig.run_until(120.0, samples)
    lower, upper = rig.bands()
    band = dict(zip(rig.joints, zip(lower - 1e-6, upper + 1e-6)))
    assert all(band[name][0] <= angle <= band[name][1]
               for _, call in rig.topic.calls for name, angle in zip(call.joint_names, call.joint_angles))
    assert all(0.0 < call.speed <= SPEED_FRACTION for _, call in rig.topic.calls)
    positions = numpy.array([sample[1] for sample in samples])
    velocities = numpy.array([sample[2] for sample in samples])
    assert numpy.all((positions >= lower - 1e-6) & (positions <= upper + 1e-6))
    assert numpy.all(numpy.abs(velocities) <= SPEED_FRACTION * numpy.array([JOINTS[n].max_velocity
                                                                            for n in rig.joints]) + 1e-9)
    moved = positions.max(axis=0) - positions.min(axis=0)
    assert (moved[numpy.array(rig.motion.moving)] > 0.05).all()
    # One goal_sent per planned trajectory: the random style's plans take numPoints x gestureDuration.
    assert 1 <= len(rig.log.events(contract.GOAL_SENT)) <= 3


def test_one_angles_sent_line_per_second_of_stream():
    rig = Rig()
    rig.enable()
    rig.run_until(105.05)
    lines = rig.log.events(contract.ANGLES_SENT)
    assert len(lines) == 5
    assert all(line["part"] == "RArm" and line["topic"] == TOPIC and line["seconds"] == pytest.approx(1.0, abs=0.01)
               for line in lines)
    assert sum(line["messages"] for line in lines) <= len(rig.topic.calls)


def test_the_breathing_style_plans_the_next_trajectory_before_the_ending():
    rig = Rig(style="breathing")
    rig.enable()
    rig.step()
    first = rig.log.events(contract.GOAL_SENT)[0]
    end = rig.now + first["times"][-2]  # the last point is the stop to rest
    rig.run_until(end - CONTINUATION_LEAD - 0.05)
    assert len(rig.log.events(contract.GOAL_SENT)) == 1
    rig.run_until(end - CONTINUATION_LEAD + 0.15)
    assert len(rig.log.events(contract.GOAL_SENT)) == 2


@pytest.mark.parametrize("measured", [True, False])
def test_disable_stops_the_stream_and_sends_every_joint_to_its_centre_calmly(measured):
    rig = Rig(measured=measured)
    rig.enable()
    rig.run_until(103.0)
    rig.step()
    count = len(rig.topic.calls)
    planned = rig.stream.plan_stop(True)
    rig.stream.disable(True, planned)
    rig.execute(count)
    assert [call for _, call in rig.topic.calls[count:]] == [planned]
    assert planned.joint_names == rig.joints and planned.speed == pytest.approx(streaming.STOP_SPEED)
    assert rig.stream.state == StreamState.HOMING
    home = rig.log.events(contract.GOAL_SENT)[-1]
    assert home["purpose"] == contract.PURPOSE_HOME and home["positions"][-1] == list(PARTS["RArm"].centre)
    rig.run_until(110.0)
    assert rig.stream.state == StreamState.IDLE and len(rig.topic.calls) == count + 1
    numpy.testing.assert_allclose(rig.driver.state(rig.now)[0], PARTS["RArm"].centre, atol=1e-6)
    assert rig.stream.next_deadline() is None


def test_disable_without_home_stops_the_joints_where_they_are():
    rig = Rig()
    rig.enable()
    rig.run_until(102.0)
    count = len(rig.topic.calls)
    where = rig.driver.state(rig.now)[0]
    rig.stream.disable(False)
    rig.execute(count)
    (_, call), = rig.topic.calls[count:]
    numpy.testing.assert_allclose(call.joint_angles, where, atol=1e-6)
    assert rig.stream.state == StreamState.IDLE
    rig.run_until(104.0)
    assert len(rig.topic.calls) == count + 1


def test_another_callers_joint_angles_make_the_part_yield_then_it_resumes_from_the_measured_joints():
    rig = Rig()
    rig.enable()
    rig.run_until(102.0)
    rig.step()
    key = "%s:%s" % (OTHER, "RShoulderPitch")
    rig.stream.foreign_command(OTHER, rig.now + 0.5, JOINT_ANGLES, key)
    assert rig.stream.state == StreamState.YIELDING and rig.stream.yielding_to == OTHER
    assert rig.log.events(contract.PART_YIELDED)[-1]["kind"] == JOINT_ANGLES
    count = len(rig.topic.calls)
    rig.driver.set_angles(("RShoulderPitch",), (1.2,), 0.1, rig.now)  # the other node's call
    for _ in range(10):  # it streams on: each call replaces the previous one
        rig.now += 0.1
        rig.stream.foreign_command(OTHER, rig.now + 0.3, JOINT_ANGLES, key)
        rig.step()
    assert len(rig.topic.calls) == count and rig.stream.state == StreamState.YIELDING
    rig.run_until(rig.now + 0.3 + 1.0 - 0.05)  # its last call's end plus the quiet time, not yet
    assert rig.stream.state == StreamState.YIELDING
    rig.run_until(rig.now + 0.2)
    assert rig.stream.state == StreamState.ANIMATING and rig.log.events(contract.PART_RESUMED)
    # The first calls start from where the other node left the arm, at rest: within 0.1 s a plan that starts at
    # rest, accelerating by at most ~3 rad/s^2, moves a joint by a few hundredths of a radian at most.
    resumed_at = rig.topic.calls[count][0]
    start = dict(zip(rig.joints, rig.driver.state(resumed_at)[0]))
    calls = [(at, call) for at, call in rig.topic.calls[count:] if at == resumed_at]
    assert calls and all(call.speed <= SPEED_FRACTION for _, call in calls)
    for _, call in calls:
        for name, angle in zip(call.joint_names, call.joint_angles):
            assert abs(angle - start[name]) <= 0.03, name
    assert abs(start["RShoulderPitch"] - 1.2) < abs(PARTS["RArm"].centre[0] - 1.2)  # the other node moved it


def test_a_disable_while_yielding_sends_nothing():
    rig = Rig()
    rig.enable()
    rig.step()
    rig.stream.foreign_command(OTHER, rig.now + 5.0, JOINT_ANGLES, OTHER)
    count = len(rig.topic.calls)
    assert rig.stream.plan_stop(True) is None
    rig.stream.disable(True)
    assert rig.stream.state == StreamState.IDLE and len(rig.topic.calls) == count


def test_it_waits_for_naoqi_driver_and_pauses_when_it_goes():
    rig = Rig(connected=False)
    rig.topic.listening = False
    assert not rig.stream.controller_ready()
    rig.enable()
    assert rig.stream.state == StreamState.WAITING
    rig.step()
    assert rig.topic.calls == []
    rig.stream.controller_connected()
    rig.step()
    assert rig.stream.state == StreamState.ANIMATING and rig.topic.calls
    rig.stream.controller_lost()
    count = len(rig.topic.calls)
    rig.run_until(rig.now + 1.0)
    assert rig.stream.state == StreamState.WAITING and len(rig.topic.calls) == count
    assert rig.log.events(contract.CONTROLLER_LOST)[0]["action"] == TOPIC


def test_the_stream_names_its_topic_as_its_controller_and_the_action_as_its_key():
    rig = Rig()
    assert rig.stream.controller == TOPIC and rig.stream.action == ACTION and rig.stream.part == "RArm"
