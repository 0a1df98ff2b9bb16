"""Unit tests of the part state machine (core/part_stream.py) with a fake action client and clock: no ROS master."""
import numpy
import pytest
from actionlib_msgs.msg import GoalStatus
from conftest import default_configuration
from fakes import FakeClient, FakeJointStates, FakeLog
from control_msgs.msg import FollowJointTrajectoryResult

from cssr_system.animate_behaviour import contract
from cssr_system.core.foreign_motion import RESULT_GRACE
from cssr_system.core.motion_stream import StreamState as PartState
from cssr_system.core.part_stream import (LOST_RESULT_GRACE, MAX_UNFINISHED_GOALS, RETRY_DELAY,
                                          TRANSITIONS, PartStream)
from cssr_system.motion.breathing import CONTINUATION_LEAD
from cssr_system.motion.planners import GOAL_TIME_TOLERANCE, SETTLE_TIME, RandomPlanner
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import PARTS

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"


class Rig:
    """A stream with every outside part faked; `now` is the clock."""

    def __init__(self, connected=True, part="RArm", measured=None):
        self.now = 100.0
        self.client = FakeClient()
        self.posted = []
        self.log = FakeLog()
        self.debug_lines = []
        self.warnings = []
        self.measured = measured
        self.joint_states = FakeJointStates(lambda joints: self.measured)
        self.stream = PartStream(part, ACTION, self.client, lambda: self.now, self.joint_states,
                                 self.posted.append, self.log,
                                 debug=lambda text, *args: self.debug_lines.append(text % args),
                                 warn=lambda text, *args: self.warnings.append(text % args))
        if connected:
            self.stream.controller_connected()
        config = default_configuration(random_seed=7)
        self.motion = {m.part: m for m in animated_parts(config, tuple(PARTS))}[part]
        self.plan = RandomPlanner(self.motion, config._replace(num_points=3, gesture_duration=1.0), make_rng(7))

    def enable(self):
        self.stream.enable(self.motion, self.plan)

    def deliver(self):
        """The supervisor's loop: events posted by actionlib's callbacks reach the stream."""
        while self.posted:
            self.stream.goal_done(self.posted.pop(0))

    def finish_last(self, status, error_code=None, error_string=""):
        self.client.handles[-1].finish(status, error_code, error_string)
        self.deliver()

    def goal_end_time(self):
        handle = self.client.handles[-1]
        return self.now + handle.goal.trajectory.points[-1].time_from_start.to_sec()

    def ending_start_time(self):
        """When the last goal's ending begins: its last point before the stop to rest and the hold."""
        handle = self.client.handles[-1]
        return self.now + handle.goal.trajectory.points[-3].time_from_start.to_sec()

    def transitions(self):
        return [line.split(": ", 2)[2] for line in self.debug_lines if " -> " in line]


def test_transition_table_allows_only_listed_changes():
    rig = Rig()
    with pytest.raises(RuntimeError, match="yielding -> homing"):
        rig.stream.transition_to(PartState.YIELDING, "allowed")
        rig.stream.transition_to(PartState.HOMING, "not allowed")
    assert PartState.HOMING not in TRANSITIONS[PartState.YIELDING]


def test_enable_sends_a_goal_and_logs_the_transition():
    rig = Rig()
    rig.enable()
    assert rig.stream.state == PartState.ANIMATING
    assert len(rig.client.handles) == 1
    goal = rig.client.handles[0].goal
    assert list(goal.trajectory.joint_names) == list(PARTS["RArm"].joints)
    assert goal.trajectory.points[0].time_from_start.to_sec() > 0
    assert rig.transitions() == ["idle -> animating (enabled)."]
    assert rig.log.events(contract.GOAL_SENT)[0]["purpose"] == contract.PURPOSE_ANIMATE


def test_success_sends_the_next_goal_at_once():
    rig = Rig()
    rig.enable()
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert len(rig.client.handles) == 2
    assert rig.stream.state == PartState.ANIMATING
    assert [entry["state"] for entry in rig.log.events(contract.GOAL_FINISHED)] == ["SUCCEEDED"]


@pytest.mark.parametrize("status", [GoalStatus.REJECTED, GoalStatus.ABORTED, GoalStatus.PREEMPTED])
def test_retry_after_a_failed_goal(status):
    rig = Rig()
    rig.enable()
    rig.finish_last(status)
    assert rig.stream.state == PartState.WAITING
    assert len(rig.client.handles) == 1
    assert rig.stream.next_deadline() == pytest.approx(rig.now + RETRY_DELAY)
    rig.now += RETRY_DELAY - 0.01
    rig.stream.tick()
    assert len(rig.client.handles) == 1, "no goal before the retry is due"
    rig.now += 0.02
    rig.stream.tick()
    assert len(rig.client.handles) == 2
    assert rig.stream.state == PartState.ANIMATING
    assert "animating -> waiting" in rig.transitions()[1] and "waiting -> animating (retry)" in rig.transitions()[2]
    # PREEMPTED: another client's goal replaced ours (no failure), but the part moves again if none shows.
    assert len(rig.warnings) == (0 if status == GoalStatus.PREEMPTED else 1)


def test_lost_result_counts_as_the_end_of_the_goal():
    rig = Rig()
    rig.enable()
    end = rig.goal_end_time()
    rig.now = end + LOST_RESULT_GRACE - 0.1
    rig.stream.tick()
    assert len(rig.client.handles) == 1
    rig.now = end + LOST_RESULT_GRACE + 0.1
    rig.stream.tick()
    assert len(rig.client.handles) == 2, "a lost result does not stop the part"
    assert rig.log.events(contract.ERROR)[0]["message"] == "goal result lost"
    # The lost goal's late result changes nothing.
    rig.client.handles[0].finish(GoalStatus.SUCCEEDED)
    rig.deliver()
    assert len(rig.client.handles) == 2


def test_reconfiguration_while_animating_replaces_the_goal_from_where_the_controller_is():
    rig = Rig()
    rig.enable()
    first = rig.client.handles[0]
    rig.now += 0.7
    expected, _, _ = rig.stream.current_state(rig.now)
    rig.enable()
    assert len(rig.client.handles) == 2
    assert not first.cancelled, "the new goal is spliced onto the running one, not cancelled"
    start = rig.log.events(contract.GOAL_SENT)[1]
    spline_start = rig.stream.current_state(rig.now)[0]
    numpy.testing.assert_allclose(spline_start, expected, atol=1e-12)
    assert start["goal"] == 2
    # The replaced goal's end (PREEMPTED) is logged and changes nothing.
    first.finish(GoalStatus.PREEMPTED)
    rig.deliver()
    assert rig.stream.state == PartState.ANIMATING
    assert len(rig.client.handles) == 2


def test_a_replaced_goal_keeps_only_what_its_end_needs():
    rig = Rig()
    rig.enable()
    first = rig.client.handles[0]
    assert first.goal.trajectory.points, "sent whole"
    rig.now += 0.5
    rig.stream.disable(home=True)
    home = rig.client.handles[1]
    assert first.goal.trajectory.points == [], "the replaced goal's points are let go"
    assert home.goal.trajectory.points, "the running goal keeps its points"
    first.finish(GoalStatus.PREEMPTED)
    rig.deliver()
    assert [entry["state"] for entry in rig.log.events(contract.GOAL_FINISHED)] == ["PREEMPTED"], \
        "its end still reaches the log"
    rig.now += 0.1
    positions, velocities, _ = rig.stream.current_state(rig.now)
    assert numpy.all(numpy.isfinite(positions)), "the running goal still gives the next start"


def test_disable_homes_then_idles_and_re_enable_animates_again():
    rig = Rig()
    rig.enable()
    rig.now += 0.5
    rig.stream.disable(home=True)
    assert rig.stream.state == PartState.HOMING
    home = rig.client.handles[-1].goal.trajectory.points[-1]
    numpy.testing.assert_allclose(home.positions, PARTS["RArm"].centre)
    assert home.time_from_start.to_sec() <= 2.0
    rig.stream.disable(home=True)
    assert len(rig.client.handles) == 2, "a second disable while homing sends nothing"
    rig.enable()  # re-enabled while homing: animates from where the home goal has the joints
    assert rig.stream.state == PartState.ANIMATING and len(rig.client.handles) == 3
    rig.client.handles[1].finish(GoalStatus.PREEMPTED)  # the home goal, replaced
    rig.deliver()
    assert rig.stream.state == PartState.ANIMATING
    rig.stream.disable(home=True)
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert rig.stream.state == PartState.IDLE
    assert rig.transitions()[-1].startswith("homing -> idle")


def test_disable_without_home_cancels():
    rig = Rig()
    rig.enable()
    rig.stream.disable(home=False)
    assert rig.client.handles[-1].cancelled
    assert rig.stream.state == PartState.IDLE
    assert len(rig.client.handles) == 1


def test_controller_that_appears_late():
    rig = Rig(connected=False)
    rig.enable()
    assert rig.stream.state == PartState.WAITING
    assert rig.client.handles == []
    rig.now += 30.0
    rig.stream.tick()
    assert rig.client.handles == []
    rig.stream.controller_connected()
    assert rig.stream.state == PartState.ANIMATING
    assert len(rig.client.handles) == 1
    assert rig.log.events(contract.CONTROLLER_CONNECTED) == [{"part": "RArm", "action": ACTION}]


def test_disable_while_waiting_for_the_controller_sends_nothing():
    rig = Rig(connected=False)
    rig.enable()
    rig.stream.disable(home=True)
    assert rig.stream.state == PartState.IDLE
    rig.stream.controller_connected()
    assert rig.client.handles == []


def test_first_goal_starts_from_the_measured_joints():
    measured = numpy.array(PARTS["RArm"].centre) + 0.3
    rig = Rig(measured=measured)
    rig.enable()
    # The first segment of the goal starts where the joints are: its spline at time 0 is the measurement.
    numpy.testing.assert_allclose(rig.stream.current_state(rig.now)[0], measured, atol=1e-12)


# -- sharing the robot ------------------------------------------------------------------------------

def test_another_nodes_goal_makes_the_part_yield_until_its_end_and_the_quiet_time():
    rig = Rig()
    rig.enable()
    ours = rig.client.handles[0]
    rig.stream.foreign_motion("gesture-1", "/gestureExecution", "goal", last_point_at=rig.now + 4.0)
    assert rig.stream.state == PartState.YIELDING and rig.stream.yielding_to == "/gestureExecution"
    assert not ours.cancelled, "nothing is sent to the controller, not even a cancel"
    ours.finish(GoalStatus.PREEMPTED)  # the controller replaced our goal with the gesture
    rig.deliver()
    assert rig.stream.state == PartState.YIELDING and len(rig.client.handles) == 1
    rig.now += 3.0
    rig.stream.tick()
    assert len(rig.client.handles) == 1
    rig.now += 1.0  # the gesture's result arrives at its last point
    rig.stream.foreign_result("gesture-1")
    rig.stream.tick()
    assert rig.stream.state == PartState.YIELDING, "the quiet time first"
    assert rig.stream.next_deadline() == pytest.approx(rig.now + 1.0)
    rig.now += 0.99
    rig.stream.tick()
    assert len(rig.client.handles) == 1
    rig.now += 0.02
    rig.stream.tick()
    assert rig.stream.state == PartState.ANIMATING and len(rig.client.handles) == 2
    resumed = rig.log.events(contract.PART_RESUMED)[0]
    assert resumed["caller"] == "/gestureExecution" and resumed["seconds"] == pytest.approx(5.01)


def test_a_chain_of_goals_keeps_the_part_yielding():
    rig = Rig()
    rig.enable()
    for number in range(3):
        rig.stream.foreign_motion("g%d" % number, "/gestureExecution", "goal", last_point_at=rig.now + 1.0)
        rig.now += 1.0
        rig.stream.foreign_result("g%d" % number)
        rig.now += 0.05  # the next goal of the chain follows its result at once
        rig.stream.tick()
        assert rig.stream.state == PartState.YIELDING
    rig.now += 1.0
    rig.stream.tick()
    assert rig.stream.state == PartState.ANIMATING


@pytest.mark.parametrize("kind, grace", [("goal", RESULT_GRACE), ("command", 0.0)])
def test_without_an_end_reported_the_other_motion_ends_at_its_last_point(kind, grace):
    """A goal whose end is not reported counts as over RESULT_GRACE after its last point; a command trajectory,
    which has no result, at its last point. Then the quiet time."""
    rig = Rig()
    rig.enable()
    rig.stream.foreign_motion("motion-1", "/teleop", kind, last_point_at=rig.now + 2.0)
    rig.now += 2.0 + grace + 0.99
    rig.stream.tick()
    assert rig.stream.state == PartState.YIELDING
    rig.now += 0.02
    rig.stream.tick()
    assert rig.stream.state == PartState.ANIMATING


def test_resume_starts_from_the_measured_joints_not_from_our_old_plan():
    measured = numpy.array(PARTS["RArm"].centre) + 0.4  # where the gesture left the arm
    rig = Rig()
    rig.enable()
    rig.stream.foreign_motion("g", "/gestureExecution", "goal", last_point_at=rig.now + 1.0)
    rig.now += 1.0
    rig.stream.foreign_result("g")
    rig.measured = measured
    rig.now += 1.01
    rig.stream.tick()
    positions, velocities, _ = rig.stream.current_state(rig.now)
    numpy.testing.assert_allclose(positions, measured, atol=1e-12)
    numpy.testing.assert_allclose(velocities, 0.0, atol=1e-12)


def test_disable_while_yielding_sends_nothing():
    rig = Rig()
    rig.enable()
    rig.stream.foreign_motion("g", "/gestureExecution", "goal", last_point_at=rig.now + 3.0)
    rig.stream.disable(home=True)
    assert rig.stream.state == PartState.IDLE and len(rig.client.handles) == 1
    assert not rig.client.handles[0].cancelled
    rig.now += 10.0
    rig.stream.tick()
    assert len(rig.client.handles) == 1


def test_enable_while_another_node_moves_the_part_waits_for_it():
    rig = Rig()
    rig.stream.foreign_motion("g", "/gestureExecution", "goal", last_point_at=rig.now + 3.0)
    rig.enable()
    assert rig.stream.state == PartState.YIELDING and rig.client.handles == []
    rig.now += 3.0 + RESULT_GRACE + 1.01
    rig.stream.tick()
    assert rig.stream.state == PartState.ANIMATING


def test_another_nodes_motion_replaces_our_return_home():
    rig = Rig()
    rig.enable()
    rig.stream.disable(home=True)
    assert rig.stream.state == PartState.HOMING
    rig.stream.foreign_motion("g", "/gestureExecution", "goal", last_point_at=rig.now + 3.0)
    assert rig.stream.state == PartState.IDLE and len(rig.client.handles) == 2


# -- faults ------------------------------------------------------------------------------------------

def test_a_controller_that_rejects_everything_is_retried_with_back_off():
    rig = Rig()
    rig.enable()
    delays = []
    for _ in range(7):
        rig.finish_last(GoalStatus.REJECTED)
        delays.append(round(rig.stream.retry_at - rig.now, 6))
        rig.now = rig.stream.retry_at
        rig.stream.tick()
    assert delays == [2.0, 4.0, 8.0, 16.0, 30.0, 30.0, 30.0]
    assert len(rig.warnings) == 7, "one line per back-off"
    # The controller works again: the retried goal runs, succeeds, and the next failure starts afresh.
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert rig.stream.state == PartState.ANIMATING
    rig.finish_last(GoalStatus.ABORTED)
    assert rig.stream.retry_at - rig.now == pytest.approx(RETRY_DELAY)


def test_a_failure_after_a_long_healthy_run_starts_the_back_off_afresh():
    rig = Rig()
    rig.enable()
    rig.finish_last(GoalStatus.ABORTED)
    rig.now = rig.stream.retry_at
    rig.stream.tick()
    rig.now += 10.0  # the retried goal runs well
    rig.finish_last(GoalStatus.ABORTED)
    assert rig.stream.retry_at - rig.now == pytest.approx(RETRY_DELAY)


def test_a_controller_that_goes_away_and_comes_back():
    rig = Rig()
    rig.enable()
    rig.stream.controller_lost()
    assert rig.stream.state == PartState.WAITING and not rig.stream.connected
    rig.now += 1.0
    rig.stream.tick()
    assert len(rig.client.handles) == 1, "nothing is sent to a controller that is gone"
    rig.measured = numpy.array(PARTS["RArm"].centre) + 0.1
    rig.stream.controller_connected()
    assert rig.stream.state == PartState.ANIMATING and len(rig.client.handles) == 2
    numpy.testing.assert_allclose(rig.stream.current_state(rig.now)[0], rig.measured, atol=1e-12)
    assert rig.log.events(contract.CONTROLLER_LOST) == [{"part": "RArm", "action": ACTION}]


def test_a_continuous_style_replaces_each_goal_before_its_ending_begins():
    rig = Rig()
    style = MotionStyle(default_configuration(motion_style="breathing", random_seed=2), make_rng(2))
    rig.stream.enable(rig.motion, style.planner(rig.motion))
    points = rig.client.handles[0].goal.trajectory.points
    assert points[-1].velocities == [0.0] * len(points[-1].velocities), "the goal ends at rest"
    assert any(points[-3].velocities), "after a stop that begins moving"
    first_end = rig.ending_start_time()
    assert rig.stream.next_deadline() == pytest.approx(first_end - CONTINUATION_LEAD)
    rig.now = first_end - CONTINUATION_LEAD - 0.01
    rig.stream.tick()
    assert len(rig.client.handles) == 1
    rig.now += 0.02
    rig.stream.tick()
    assert len(rig.client.handles) == 2 and not rig.client.handles[0].cancelled
    rig.client.handles[0].finish(GoalStatus.PREEMPTED)  # replaced by ours: logged, changes nothing
    rig.deliver()
    assert rig.stream.state == PartState.ANIMATING and len(rig.client.handles) == 2
    rig.stream.disable(home=True)
    assert rig.stream.next_deadline() != pytest.approx(rig.goal_end_time() - CONTINUATION_LEAD)


def test_a_start_planned_ahead_sends_what_enable_would_plan():
    """The supervisor plans every part's first goal before the first one leaves (plan_start), then enables each."""
    planned_rig, direct_rig = Rig(), Rig()
    planned = planned_rig.stream.plan_start(planned_rig.plan)
    assert planned_rig.client.handles == [] and planned_rig.stream.state == PartState.IDLE, \
        "planning sends nothing and changes nothing"
    planned_rig.stream.enable(planned_rig.motion, planned_rig.plan, planned=planned)
    direct_rig.enable()
    sent, direct = (rig.client.handles[-1].goal.trajectory.points for rig in (planned_rig, direct_rig))
    assert planned_rig.stream.state == PartState.ANIMATING and len(planned_rig.client.handles) == 1
    assert [(p.positions, p.velocities, p.time_from_start) for p in sent] == \
        [(p.positions, p.velocities, p.time_from_start) for p in direct]
    assert Rig(connected=False).stream.plan_start(direct_rig.plan) is None, "a part waiting for its controller"


def test_a_stop_planned_ahead_sends_what_disable_would_plan():
    """The supervisor plans every part's return goal before the first one leaves (plan_stop), then sends each."""
    planned_rig, direct_rig = Rig(), Rig()
    for rig in (planned_rig, direct_rig):
        rig.enable()
        rig.now += 0.7
    planned = planned_rig.stream.plan_stop(home=True)
    assert len(planned_rig.client.handles) == 1 and planned_rig.stream.state == PartState.ANIMATING, \
        "planning sends nothing and changes nothing"
    planned_rig.stream.disable(home=True, planned=planned)
    direct_rig.stream.disable(home=True)
    sent, direct = (rig.client.handles[-1].goal.trajectory.points for rig in (planned_rig, direct_rig))
    assert planned_rig.stream.state == PartState.HOMING
    assert [(p.positions, p.velocities, p.time_from_start) for p in sent] == \
        [(p.positions, p.velocities, p.time_from_start) for p in direct]
    assert planned_rig.log.events(contract.GOAL_SENT)[-1]["purpose"] == contract.PURPOSE_HOME
    assert Rig().stream.plan_stop(home=True) is None, "an idle part returns nowhere"
    assert planned_rig.stream.plan_stop(home=True) is None, "nor does one already returning"
    assert direct_rig.stream.plan_stop(home=False) is None


def last_point(handle):
    return numpy.array(handle.goal.trajectory.points[-1].positions)


def test_every_goal_carries_a_goal_time_tolerance_and_ends_with_a_hold():
    rig = Rig()
    for send in (rig.enable, lambda: rig.stream.disable(home=True)):  # an animation goal, the return to the centre
        send()
        rig.now += 0.7
        goal = rig.client.handles[-1].goal
        assert goal.goal_time_tolerance.to_sec() == pytest.approx(GOAL_TIME_TOLERANCE)
        assert goal.goal_tolerance == [] and goal.path_tolerance == [], "the controller's own tolerances apply"
        held, last = goal.trajectory.points[-2:]
        assert held.positions == last.positions and not any(last.velocities) and not any(held.velocities)
        assert (last.time_from_start - held.time_from_start).to_sec() == pytest.approx(SETTLE_TIME)


def aborted_at_its_end(rig, measured_offset, late=0.0):
    """The running goal ends ABORTED for its end state `late` s after its last point, the joints measured
    `measured_offset` rad from that point."""
    handle = rig.client.handles[-1]
    rig.now = rig.goal_end_time() + late
    rig.measured = last_point(handle) + measured_offset
    rig.finish_last(GoalStatus.ABORTED, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED,
                    "RShoulderPitch goal error -0.000038")


def test_an_abort_for_the_end_state_only_is_no_failure():
    rig = Rig()
    rig.enable()
    end = rig.goal_end_time()
    aborted_at_its_end(rig, 0.002, late=GOAL_TIME_TOLERANCE)
    finished = rig.log.events(contract.GOAL_FINISHED)[-1]
    assert finished["state"] == "ABORTED" and finished["reached"] is True
    assert finished["error_string"] == "RShoulderPitch goal error -0.000038"
    assert rig.stream.state == PartState.ANIMATING and rig.stream.retry_at is None, "no back-off"
    assert len(rig.client.handles) == 2 and rig.warnings == [], "the next goal leaves at once"
    assert end <= rig.now
    rig.now += 0.7
    rig.stream.disable(home=True)
    aborted_at_its_end(rig, -0.001)
    assert rig.stream.state == PartState.IDLE and rig.log.events(contract.GOAL_FINISHED)[-1]["reached"] is True


@pytest.mark.parametrize("offset, late, error_code", [
    (0.05, 0.5, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED),  # the joints are not at the last point
    (0.0, -1.0, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED),  # the trajectory had not played out
    (0.0, 0.5, FollowJointTrajectoryResult.PATH_TOLERANCE_VIOLATED),  # another reason
])
def test_other_aborts_back_off(offset, late, error_code):
    rig = Rig()
    rig.enable()
    handle = rig.client.handles[-1]
    rig.now = rig.goal_end_time() + late
    rig.measured = last_point(handle) + offset
    rig.finish_last(GoalStatus.ABORTED, error_code, "RShoulderPitch error")
    assert rig.log.events(contract.GOAL_FINISHED)[-1]["reached"] is False
    assert rig.stream.state == PartState.WAITING and rig.stream.retry_at == pytest.approx(rig.now + RETRY_DELAY)


def test_goals_sent_before_a_simulated_clock_runs_count_from_its_start():
    """rospy's clock reads 0 until the first /clock message: a goal sent then starts when the clock starts, however
    late that is, and is neither called lost nor replaced before its end."""
    rig = Rig()
    rig.now = 0.0
    rig.enable()
    duration = rig.client.handles[-1].goal.trajectory.points[-1].time_from_start.to_sec()
    rig.stream.tick()
    assert rig.stream.next_deadline() is None, "nothing is due before the clock runs"
    rig.now = 1.0e6  # the clock starts late, far from 0
    rig.stream.tick()
    assert rig.stream.next_deadline() == pytest.approx(1.0e6 + duration + LOST_RESULT_GRACE)
    rig.now += duration + LOST_RESULT_GRACE - 0.01
    rig.stream.tick()
    assert len(rig.client.handles) == 1 and rig.log.events(contract.ERROR) == [], "not lost while it may run"
    rig.finish_last(GoalStatus.SUCCEEDED, 0)
    assert len(rig.client.handles) == 2


def test_a_continuous_goal_sent_before_the_clock_runs_is_continued_before_its_end():
    rig = Rig()
    rig.now = 0.0
    style = MotionStyle(default_configuration(motion_style="breathing", random_seed=2), make_rng(2))
    rig.stream.enable(rig.motion, style.planner(rig.motion))
    ending_start = rig.client.handles[-1].goal.trajectory.points[-3].time_from_start.to_sec()
    rig.now = 5000.0
    rig.stream.tick()
    assert len(rig.client.handles) == 1, "not replaced when the clock starts"
    assert rig.stream.next_deadline() == pytest.approx(5000.0 + ending_start - CONTINUATION_LEAD)


def test_the_measured_joints_are_needed_while_the_part_waits_but_never_while_a_goal_of_ours_runs():
    rig = Rig(connected=False)
    rig.enable()
    assert rig.stream.needs_measurements(), "waiting for the controller: it starts again from them"
    rig.stream.controller_connected()
    assert rig.stream.drives_joints and not rig.stream.needs_measurements()
    assert rig.joint_states.moved == [PARTS["RArm"].joints], "the goal takes the joints away from their measurements"
    rig.now = rig.goal_end_time()
    assert not rig.stream.needs_measurements(), "not even at its end: the controller holds its last point"
    rig.stream.disable(home=True)
    assert rig.stream.drives_joints and not rig.stream.needs_measurements(), "returning home"
    rig.stream.controller_lost()
    assert rig.stream.needs_measurements(), "the controller is gone: the joints may be anywhere"


def test_a_goal_that_succeeds_leaves_the_joints_at_its_last_point_and_the_next_goal_starts_there():
    rig = Rig(measured=None)
    rig.enable()
    last = rig.client.handles[-1].goal.trajectory.points[-1].positions
    rig.now = rig.goal_end_time()
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert rig.joint_states.settled == [(PARTS["RArm"].joints, pytest.approx(list(last)))]
    rig.finish_last(GoalStatus.ABORTED)
    assert len(rig.joint_states.settled) == 1, "an aborted goal left the joints where nothing says"


def test_an_abort_for_the_end_state_needs_a_measurement_to_be_judged_only_when_none_is_current():
    rig = Rig(measured=None)
    rig.enable()
    rig.now = rig.goal_end_time()
    rig.client.handles[-1].finish(GoalStatus.ABORTED, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED, "moving")
    ended = rig.posted[-1]
    assert rig.stream.end_needs_measurement(ended)
    rig.measured = numpy.array(rig.client.handles[-1].goal.trajectory.points[-1].positions)
    assert not rig.stream.end_needs_measurement(ended), "measured: judged at once"
    rig.measured = None
    assert not rig.stream.end_needs_measurement(ended._replace(error_code=-1)), "an abort for another reason"
    rig.now -= 1.0
    assert not rig.stream.end_needs_measurement(ended), "before its end: a failure, whatever the joints"


def test_without_a_measurement_the_next_goal_starts_where_the_ended_goal_left_the_joints():
    rig = Rig(measured=None)
    starts = []
    planner = rig.plan

    def recording_plan(now, positions, velocities, accelerations):
        starts.append(numpy.array(positions, dtype=float))
        return planner(now, positions, velocities, accelerations)
    recording_plan.replacement_time = planner.replacement_time
    rig.plan = recording_plan
    rig.enable()
    ended_at = numpy.array(rig.client.handles[-1].goal.trajectory.points[-1].positions)
    rig.now = rig.goal_end_time()
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert len(rig.client.handles) == 2
    assert starts[-1] == pytest.approx(ended_at), "not from the centre"
    assert not numpy.allclose(ended_at, PARTS["RArm"].centre)


def test_our_goal_replaced_by_another_nodes_goal_ends_preempted_naming_it_without_a_back_off():
    rig = Rig()
    rig.enable()
    rig.stream.foreign_motion("gesture-1", "/gestureExecution", "goal", last_point_at=rig.now + 1.0)
    # ros2_control's joint_trajectory_controller aborts the goal a new one replaces.
    rig.finish_last(GoalStatus.ABORTED, -1, "Current goal preempted by new incoming action.")
    (finished,) = rig.log.events(contract.GOAL_FINISHED)
    assert (finished["state"], finished["replaced_by"]) == ("PREEMPTED", "/gestureExecution")
    assert rig.warnings == [] and rig.stream.retry_at is None, "no failure, no back-off"
    assert rig.log.events(contract.PART_YIELDED)[0]["caller"] == "/gestureExecution"


def test_a_failure_of_our_own_goal_names_no_other_node():
    rig = Rig()
    rig.enable()
    rig.finish_last(GoalStatus.ABORTED, -1, "tolerance")
    (finished,) = rig.log.events(contract.GOAL_FINISHED)
    assert finished["state"] == "ABORTED" and "replaced_by" not in finished


def test_goals_still_running_at_exit_get_one_final_line_each():
    rig = Rig()
    rig.enable()
    rig.now += 0.5
    rig.stream.disable(home=True)
    rig.stream.finish_at_exit()
    finished = rig.log.events(contract.GOAL_FINISHED)
    assert [(entry["goal"], entry["purpose"], entry["state"]) for entry in finished] == [
        (1, "animate", "RUNNING_AT_EXIT"), (2, "home", "RUNNING_AT_EXIT")]
    rig.finish_last(GoalStatus.SUCCEEDED)
    assert len(rig.log.events(contract.GOAL_FINISHED)) == 2, "a result after the exit line adds none"


def test_a_goal_dropped_unanswered_gets_its_final_line():
    rig = Rig()
    rig.enable()
    for _ in range(MAX_UNFINISHED_GOALS):  # each enable replaces the running goal; the controller never answers
        rig.enable()
    (dropped,) = rig.log.events(contract.GOAL_FINISHED)
    assert (dropped["goal"], dropped["state"]) == (1, "LOST")


def test_our_goal_preempted_before_the_other_clients_goal_shows_is_no_failure():
    rig = Rig()
    rig.enable()
    rig.finish_last(GoalStatus.PREEMPTED)  # our result comes before the status that shows the other goal
    (finished,) = rig.log.events(contract.GOAL_FINISHED)
    assert (finished["state"], finished["replaced_by"]) == ("PREEMPTED", "another client of %s" % ACTION)
    assert rig.warnings == [], "no failure"
    rig.stream.foreign_motion("gesture-1", "/gestureExecution", "goal", last_point_at=rig.now + 1.0)
    assert rig.stream.state == PartState.YIELDING and rig.stream.retry_at is None


def test_a_goal_the_last_look_withheld_makes_no_failure_and_the_other_clients_goal_makes_the_part_yield():
    rig = Rig()
    rig.enable()
    rig.now += 1.0
    rig.stream.foreign_motion("gesture-1", "/gestureExecution", "goal", last_point_at=None)
    rig.client.handles[-1].done("WITHHELD", None, "not sent: another client's goal gesture-1 is on the controller")
    rig.deliver()
    (finished,) = rig.log.events(contract.GOAL_FINISHED)
    assert finished["state"] == "WITHHELD" and rig.warnings == []
    assert rig.stream.state == PartState.YIELDING and rig.stream.retry_at is None


def test_a_withheld_goal_reported_before_the_other_clients_goal_waits_without_a_back_off():
    rig = Rig()
    rig.enable()
    rig.client.handles[-1].done("WITHHELD", None, "not sent")
    rig.deliver()
    assert rig.stream.state == PartState.WAITING and rig.stream.retry_at == rig.now + RETRY_DELAY
    assert rig.warnings == [], "no failure"
    rig.stream.foreign_motion("gesture-1", "/gestureExecution", "goal", last_point_at=None)
    assert rig.stream.state == PartState.YIELDING and len(rig.client.handles) == 1
