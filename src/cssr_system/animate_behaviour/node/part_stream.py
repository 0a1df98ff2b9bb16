"""One controller's goal stream: a small state machine that owns its transitions.

States (README: "Status"): ``idle`` (no goal of ours runs), ``animating`` (one goal after the other),
``yielding`` (another node moves the part: we send nothing until it is done and calm, README: "Sharing the
robot"), ``waiting`` (enabled, but waiting for the controller to appear or for a retry), ``homing`` (the
return-to-centre goal after a disable). Every change goes through `transition_to`, which checks it
against `TRANSITIONS` and logs ``old -> new`` at debug level.

The supervisor thread is the only caller. What the stream needs from the outside is injected, so
that unit tests drive it with a fake action client and a fake clock:

- ``client``: an actionlib ``ActionClient`` (``send_goal(goal, transition_cb)`` returns a handle with
  ``cancel()``, ``get_comm_state()``, ``get_goal_status()`` and ``get_result()``);
- ``clock``: seconds, on the clock the controller executes goals on;
- ``positions``: the measured positions of a list of joints, or None when unknown;
- ``post``: puts an event on the supervisor's queue (actionlib calls back from its own threads);
- at each enable, ``plan(now, positions, velocities, accelerations)``: the next animation goal of the part,
  a `TimedTrajectory` starting from the given state (times relative to ``now``), from the motion style;
- ``log``: the event log; ``debug`` and ``warn``: console lines.
"""
import enum
import io
import time
from collections import OrderedDict
from typing import Callable, NamedTuple, Optional

import actionlib
import numpy
import rospy
from actionlib.action_client import CommState
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryActionGoal, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import NODE_NAME, PURPOSE_ANIMATE, PURPOSE_HOME
from cssr_system.animate_behaviour.event_log import format_log_line, format_timestamp
from cssr_system.animate_behaviour.motion.styles import Planner
from cssr_system.animate_behaviour.motion.trajectory_timing import TimedTrajectory, time_trajectory, to_points
from cssr_system.animate_behaviour.motion.waypoints import PartMotion
from cssr_system.animate_behaviour.node.events import GoalDone
from cssr_system.animate_behaviour.node.foreign_motion import COMMAND, DEFAULT_QUIET_TIME, ForeignMotionTracker
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

HOME_GESTURE_DURATION = 0.5  # s, the shortest return to the centre on disable (stretched as needed)
HOME_MAX_DURATION = 2.0  # s; longer returns are reported (the speed cap wins over this bound)
RETRY_DELAY = 2.0  # s before a part tries again after a failed goal (rejected, aborted, preempted by an unseen node)
MAX_RETRY_DELAY = 30.0  # s: the back-off doubles the delay after each failure in a row, up to this
HEALTHY_RUN = 5.0  # s: a goal that ran this long before failing starts the back-off afresh
MAX_UNFINISHED_GOALS = 16  # handles kept for goals whose end has not been reported yet
LOST_RESULT_GRACE = 5.0  # s after a goal's end before a missing result counts as lost


class PartState(enum.Enum):
    IDLE = "idle"
    ANIMATING = "animating"
    YIELDING = "yielding"
    WAITING = "waiting"
    HOMING = "homing"


TRANSITIONS = {
    PartState.IDLE: {PartState.ANIMATING, PartState.WAITING, PartState.YIELDING},
    PartState.ANIMATING: {PartState.ANIMATING, PartState.WAITING, PartState.YIELDING, PartState.HOMING,
                          PartState.IDLE},
    PartState.YIELDING: {PartState.ANIMATING, PartState.WAITING, PartState.IDLE},
    PartState.WAITING: {PartState.ANIMATING, PartState.WAITING, PartState.YIELDING, PartState.HOMING,
                        PartState.IDLE},
    PartState.HOMING: {PartState.ANIMATING, PartState.WAITING, PartState.YIELDING, PartState.IDLE},
}

_GOAL_STATE_NAMES = {getattr(GoalStatus, name): name for name in (
    "PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING",
    "RECALLING", "RECALLED", "LOST")}


def goal_state_name(state: int) -> str:
    return _GOAL_STATE_NAMES.get(state, str(state))


class SentGoal:
    """A goal of ours: its number, purpose, actionlib handle, and the motion the controller makes of it."""

    def __init__(self, number: int, purpose: str, handle, start_state, points, start_time: float,
                 goal: Optional[FollowJointTrajectoryGoal] = None) -> None:
        self.number = number
        self.purpose = purpose  # PURPOSE_ANIMATE or PURPOSE_HOME
        self.handle = handle  # actionlib ClientGoalHandle
        self._goal = goal  # the message sent (actionlib keeps it with the handle)
        self.start_time = start_time  # on the stream's clock
        self.end_time = start_time + points[-1].time
        self._start_state = tuple(None if vector is None else numpy.array(vector, dtype=float)
                                  for vector in start_state)  # a copy: the callers' arrays may change
        self._points = points
        self._spline: Optional[JointTrajectorySpline] = None

    @property
    def spline(self) -> JointTrajectorySpline:
        """What the controller executes. Built when first needed (the next goal's start), not while goals are
        being sent: at an enable every millisecond before the last part's goal counts."""
        if self._spline is None:
            self._spline = JointTrajectorySpline(*self._start_state, self._points, start_time=self.start_time)
        return self._spline

    def release(self) -> None:
        """The goal is no longer what the controller executes for us (replaced, cancelled, yielded): only its end
        is still awaited, for the log. Its motion and the message's points (actionlib keeps the message with the
        handle, and needs its goal id only) are let go, so that up to MAX_UNFINISHED_GOALS of them cost little."""
        if self._goal is not None:
            self._goal.trajectory.points = []
            self._goal = None
        self._start_state = self._points = self._spline = None


def goal_message(joints, points) -> FollowJointTrajectoryGoal:
    """The goal of a trajectory (`trajectory_timing.to_points`), to start as soon as it arrives."""
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.header.stamp = rospy.Time(0)  # start now
    nanoseconds = numpy.rint(numpy.array([point.time for point in points]) * 1e9).astype(numpy.int64).tolist()
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=list(point.positions), velocities=list(point.velocities),
                             accelerations=list(point.accelerations),
                             time_from_start=rospy.Duration(*divmod(nanosecond, 1000000000)))
        for point, nanosecond in zip(points, nanoseconds)]
    return goal


def action_client(action: str) -> actionlib.ActionClient:
    """The client of a controller's FollowJointTrajectory action. The goal-handle client, not SimpleActionClient:
    its transitions carry their handle, so a result that arrives before send_goal returns is not lost."""
    client = actionlib.ActionClient(action, FollowJointTrajectoryAction)
    # Feedback is not used: no connection, no thread, no decoding at the controller's rate (the controller
    # watcher's server_ready does not need it).
    client.feedback_sub.unregister()
    # Goals and cancels are written by the thread that sends them, not handed to a queue thread per connection:
    # a goal is on the wire when send_goal returns (so a stop is never lost to an exit), there is no thread hop
    # before the first goal, and no thread per subscriber. The controllers read them at once; a goal is ~20 kB,
    # far below a socket's buffer.
    client.pub_goal.impl.set_queue_size(None)
    client.pub_cancel.impl.set_queue_size(None)
    return client


PREPARED_START_TOLERANCE = 0.02  # rad: how far a part may have moved from where its prepared first goal starts


class PreparedGoal(NamedTuple):
    """A first animation goal planned while the node is disabled (README: "Performance"), from where the part
    rests. An enable sends it as it is, or plans afresh when the part has moved since."""
    start: numpy.ndarray  # the positions it was planned from
    timed: TimedTrajectory
    points: list
    goal: FollowJointTrajectoryGoal

    def fits(self, positions, velocities=None) -> bool:
        """The part is at rest (no velocities given: known to be idle) within PREPARED_START_TOLERANCE of `start`."""
        return ((velocities is None or not numpy.any(velocities))
                and float(numpy.max(numpy.abs(numpy.asarray(positions) - self.start))) <= PREPARED_START_TOLERANCE)


class OutgoingGoal(NamedTuple):
    """A goal planned and built, not yet sent: a stop plans every part's goal before the first one leaves."""
    purpose: str  # PURPOSE_ANIMATE or PURPOSE_HOME
    planned_at: float  # on the stream's clock: when the goal starts
    start_state: tuple  # (positions, velocities, accelerations) it starts from
    timed: TimedTrajectory
    points: list
    goal: FollowJointTrajectoryGoal


def prepare_goal(part: str, plan: Planner, start_positions) -> PreparedGoal:
    """The first goal of `part` from rest at `start_positions`, ready to send."""
    start = numpy.array(start_positions, dtype=float)
    zeros = numpy.zeros(start.size)
    timed = plan(0.0, start, zeros, zeros)
    points = to_points(timed)
    return PreparedGoal(start, timed, points, goal_message(PARTS[part].joints, points))


def rehearse(part: str, plan: Planner) -> None:
    """Plans, builds and encodes one goal of `part` and its log line without sending them, so that the first
    `enabled` pays no first-use costs (on the robot laptop's Python they made it take ~80 ms)."""
    joints = PARTS[part].joints
    centre, zeros = numpy.array(PARTS[part].centre), numpy.zeros(len(joints))
    timed = plan(0.0, centre, zeros, zeros)
    FollowJointTrajectoryActionGoal(goal=goal_message(joints, to_points(timed))).serialize(io.BytesIO())
    format_log_line(format_timestamp(time.time()), contract.GOAL_SENT, dict(times=timed.times,
                                                                            positions=timed.positions))


class PartStream:
    """One controller's goal stream. Only the supervisor thread calls its methods."""

    def __init__(self, part: str, action: str, client, clock: Callable[[], float],
                 positions: Callable[[tuple], Optional[numpy.ndarray]], post: Callable[[object], None], log,
                 debug: Callable[..., None] = rospy.logdebug, warn: Callable[..., None] = rospy.logwarn) -> None:
        self.part = part
        self.action = action
        self.client = client
        self.connected = False
        self.state = PartState.IDLE
        self.motion: Optional[PartMotion] = None
        self.retry_at: Optional[float] = None
        self._clock = clock
        self._positions = positions
        self._post = post
        self._log = log
        self._debug = debug
        self._warn = warn
        self._plan: Optional[Planner] = None
        self._prepared: Optional[PreparedGoal] = None  # the first animation goal, planned ahead
        self._animated = False  # a goal of ours moved the part away from its centre since the last return
        self._failures = 0  # failed goals in a row: the back-off
        self.foreign = ForeignMotionTracker()  # other nodes' motion on this controller
        self.yielding_to = ""  # the caller id of the node the part yields to
        self._yield_started = 0.0
        self._command_count = 0  # numbers other nodes' command-topic trajectories
        self._goal_number = 0
        self._sent: Optional[SentGoal] = None
        # Goals that have not reported their end, replaced and cancelled ones too: holding their
        # handles keeps their transitions coming, so every goal's final state reaches the log.
        self._unfinished: "OrderedDict[int, SentGoal]" = OrderedDict()
        self._replaced_unreleased = False  # goals replaced since the last prepare() still hold their points

    # -- the state machine --------------------------------------------------------------------
    def transition_to(self, new_state: PartState, why: str) -> None:
        if new_state not in TRANSITIONS[self.state]:
            raise RuntimeError("%s: no transition %s -> %s (%s)" % (self.part, self.state.value, new_state.value, why))
        self._debug("%s: %s: %s -> %s (%s).", NODE_NAME, self.part, self.state.value, new_state.value, why)
        self.state = new_state

    @property
    def active(self) -> bool:
        return self.state != PartState.IDLE

    def enable(self, motion: PartMotion, plan: Planner, quiet_time: float = DEFAULT_QUIET_TIME,
               prepared: Optional[PreparedGoal] = None) -> None:
        """Animate `motion` with goals from `plan`, the first one `prepared` if it still fits where the part is; a
        running goal is replaced smoothly (the controller splices)."""
        self.motion = motion
        self._plan = plan
        self._prepared = prepared
        self.foreign.quiet_time = quiet_time
        self.retry_at = None
        if self.state == PartState.YIELDING:
            return
        if not self.foreign.calm(self._clock()):
            self._yield(self.foreign.caller, "enabled while another node moves the part")
        elif self.connected:
            self._send_animation("enabled")
        else:
            self.transition_to(PartState.WAITING, "enabled; controller not connected yet")

    def _returns_home(self, home: bool) -> bool:
        """A stop of this part sends a return-to-centre goal (else it cancels, or sends nothing)."""
        return (home and self.connected and self._animated
                and self.state not in (PartState.IDLE, PartState.HOMING, PartState.YIELDING))

    def plan_stop(self, home: bool) -> Optional[OutgoingGoal]:
        """The goal `disable(home)` would send, planned now without sending it (None: it sends none)."""
        return self._outgoing(PURPOSE_HOME, self._plan_home) if self._returns_home(home) else None

    def disable(self, home: bool, planned: Optional[OutgoingGoal] = None) -> None:
        """Stop: one return-to-centre goal when `home` (and a goal of ours moves the part), else cancel.
        `planned`: that goal, from `plan_stop(home)` a moment ago (planned now when None)."""
        self.retry_at = None
        if self.state == PartState.IDLE or self.state == PartState.HOMING:
            return
        if self.state == PartState.YIELDING:  # the other node owns the part: send nothing
            self.yielding_to = ""
            self.transition_to(PartState.IDLE, "disabled while yielding")
            return
        if self._returns_home(home):
            timed = self._dispatch(planned or self._outgoing(PURPOSE_HOME, self._plan_home))
            if timed.times[-1] > HOME_MAX_DURATION:
                self._warn("%s: %s returns to its centre in %.1f s (speed cap).", NODE_NAME, self.part,
                           timed.times[-1])
            self.transition_to(PartState.HOMING, "disabled; returning to the centre")
            return
        self.cancel()
        self.transition_to(PartState.IDLE, "disabled")

    def goal_done(self, event: GoalDone) -> None:
        """A goal of ours reported its end (any goal: replaced and cancelled ones too)."""
        sent = self._unfinished.pop(event.goal_number, None)
        if sent is None:
            return  # reported already
        state_name = goal_state_name(event.state)
        self._log.write(contract.GOAL_FINISHED, part=self.part, action=self.action, purpose=sent.purpose,
                        goal=event.goal_number, state=state_name, error_code=event.error_code,
                        error_string=event.error_string)
        if not self.is_current(event.goal_number) or self.state == PartState.IDLE:
            return  # a goal we replaced or cancelled: its end changes nothing
        if event.state == GoalStatus.SUCCEEDED or sent.purpose == PURPOSE_HOME:
            self._failures = 0
            self._finish_goal("goal %d %s" % (event.goal_number, state_name))
            return
        now = self._clock()
        if now - sent.start_time >= HEALTHY_RUN:
            self._failures = 0
        self._failures += 1
        delay = min(RETRY_DELAY * 2 ** (self._failures - 1), MAX_RETRY_DELAY)
        self._warn("%s: %s goal ended %s (%s); trying again in %.0f s.", NODE_NAME, self.part, state_name,
                   event.error_string or "no reason given", delay)
        self._sent = None  # the controller does not run it: the retry starts from the measured joints
        self.retry_at = now + delay
        self.transition_to(PartState.WAITING, "goal %d %s; retry in %.0f s" % (event.goal_number, state_name, delay))

    def controller_connected(self) -> None:
        if self.connected:
            return
        self.connected = True
        self._log.write(contract.CONTROLLER_CONNECTED, part=self.part, action=self.action)
        rospy.loginfo("%s: controller %s connected.", NODE_NAME, self.action)
        if self.state == PartState.WAITING and self.retry_at is None:
            self._send_animation("controller connected")

    def foreign_motion(self, key: str, caller: str, kind: str, last_point_at: float) -> None:
        """Another node sent this controller a goal or a trajectory (`last_point_at`: when its last point passes)."""
        self.foreign.started(key, caller, kind, self._clock(), last_point_at)
        if self.state in (PartState.ANIMATING, PartState.WAITING):
            self._yield(caller, "%s sent a %s" % (caller, kind))
        elif self.state == PartState.HOMING:  # its motion replaced our return to the centre
            self._sent = None
            self._animated = False
            self._log.write(contract.PART_YIELDED, part=self.part, controller=self.action, caller=caller, kind=kind)
            self.transition_to(PartState.IDLE, "%s moves the part instead of our return to the centre" % caller)
        elif self.state == PartState.YIELDING:
            self.yielding_to = caller

    def foreign_command(self, caller: str, last_point_at: float) -> None:
        """Another node's trajectory on the controller's command topic."""
        self._command_count += 1
        self.foreign_motion("command-%d" % self._command_count, caller, COMMAND, last_point_at)

    def foreign_result(self, key: str) -> None:
        """A goal's result on the controller's action (ours are ignored by the tracker)."""
        self.foreign.result(key, self._clock())

    def _yield(self, caller: str, why: str) -> None:
        self._sent = None  # the controller runs the other node's motion now; ours is kept only for its result
        self.retry_at = None
        self.yielding_to = caller
        self._yield_started = self._clock()
        self._log.write(contract.PART_YIELDED, part=self.part, controller=self.action, caller=caller,
                        kind=self.foreign.kind_of_latest())
        self.transition_to(PartState.YIELDING, why)

    def _resume(self, now: float) -> None:
        seconds = round(now - self._yield_started, 3)
        self._log.write(contract.PART_RESUMED, part=self.part, controller=self.action, caller=self.yielding_to,
                        seconds=seconds)
        why = "%s done, calm for %.1f s" % (self.yielding_to, self.foreign.quiet_time)
        self.yielding_to = ""
        if self.connected:
            self._send_animation(why)  # from the measured joints: nothing of ours runs
        else:
            self.transition_to(PartState.WAITING, why + "; controller not connected")

    def controller_lost(self) -> None:
        """The controller went away (its server no longer answers): our goal is gone with it. The part waits
        and animates again from the measured joints as soon as the controller is back."""
        if not self.connected:
            return
        self.connected = False
        self._sent = None
        self.retry_at = None
        self._warn("%s: controller %s is gone; %s waits for it.", NODE_NAME, self.action, self.part)
        self._log.write(contract.CONTROLLER_LOST, part=self.part, action=self.action)
        if self.state in (PartState.ANIMATING, PartState.WAITING):
            self.transition_to(PartState.WAITING, "controller gone")
        elif self.state == PartState.HOMING:
            self._animated = False
            self.transition_to(PartState.IDLE, "controller gone while returning to the centre")

    def tick(self) -> None:
        """Time-driven transitions: a lost result, a retry that is due, the end of a yield."""
        now = self._clock()
        if self.state == PartState.YIELDING:
            if self.foreign.calm(now):
                self._resume(now)
            return
        if self._continuation_due(now):
            self._send_animation("continuing the motion")
        if self.overdue(now):
            self._warn("%s: no result for the %s goal; sending the next one.", NODE_NAME, self.part)
            self._log.write(contract.ERROR, where=self.part, message="goal result lost")
            self._finish_goal("goal result lost")
        if self.retry_at is not None and now >= self.retry_at:
            self.retry_at = None
            if self.state == PartState.WAITING:
                self._send_animation("retry")

    def _continuation_at(self) -> Optional[float]:
        """When a continuous style's goal is replaced by the next, before it ends (a goal that ends moving would be
        aborted by the controller's stopped-velocity tolerance)."""
        lead = getattr(self._plan, "continuation_lead", None)
        if lead is None or self.state != PartState.ANIMATING or self.sent_purpose != PURPOSE_ANIMATE:
            return None
        return self._sent.end_time - lead

    def _continuation_due(self, now: float) -> bool:
        at = self._continuation_at()
        return at is not None and now >= at

    def next_deadline(self) -> Optional[float]:
        """When `tick` next has something to do, on the stream's clock (None: nothing planned)."""
        deadlines = [self.retry_at] if self.retry_at is not None else []
        if self._continuation_at() is not None:
            deadlines.append(self._continuation_at())
        if self.state == PartState.YIELDING:
            deadline = self.foreign.next_deadline(self._clock())
            if deadline is not None:
                deadlines.append(deadline)
        if self._sent is not None:
            deadlines.append(self._sent.end_time + LOST_RESULT_GRACE)
        return min(deadlines) if deadlines else None

    # -- goals --------------------------------------------------------------------------------
    def _finish_goal(self, why: str) -> None:
        """A goal of ours ended as planned: a part going home is done, an animating one goes on."""
        purpose = self.sent_purpose
        self._sent = None
        if purpose == PURPOSE_HOME and self.state == PartState.HOMING:
            self._animated = False
            self.transition_to(PartState.IDLE, why + "; at the centre")
        elif self.state == PartState.ANIMATING:
            self._send_animation(why)

    def _send_animation(self, why: str) -> None:
        prepared, self._prepared = self._prepared, None
        self._send(PURPOSE_ANIMATE, self._plan, prepared)
        self._animated = True
        self.transition_to(PartState.ANIMATING, why)

    def _plan_home(self, now: float, positions, velocities, accelerations) -> TimedTrajectory:
        """One goal to the centre; from a moving joint it brakes inside the band it was animated in."""
        bands = self.motion.bounds if self.motion is not None else ()
        bounds = ([b.lower for b in bands], [b.upper for b in bands]) if bands else None
        return time_trajectory(numpy.array([PARTS[self.part].centre]), PARTS[self.part].joints, positions,
                               velocities, HOME_GESTURE_DURATION, start_accelerations=accelerations,
                               position_bounds=bounds)

    def measured_positions(self) -> Optional[numpy.ndarray]:
        return self._positions(PARTS[self.part].joints)

    def current_state(self, now: float):
        """Positions and velocities to start the next goal from: what the controller is executing
        for us (it splices new goals onto that), else the measured joints, else the centre."""
        joints = PARTS[self.part].joints
        if self._sent is not None and now <= self._sent.end_time:
            positions, velocities, accelerations = self._sent.spline.sample(now)
            return numpy.asarray(positions), numpy.asarray(velocities), numpy.asarray(accelerations)
        measured = self._positions(joints)
        if measured is None and self._sent is not None:
            measured = numpy.asarray(self._sent.spline.sample(now)[0])
        if measured is None:
            measured = numpy.array(PARTS[self.part].centre, dtype=float)
        zeros = numpy.zeros(len(joints))
        return measured, zeros, zeros

    def _send(self, purpose: str, plan: Planner, prepared: Optional[PreparedGoal] = None) -> TimedTrajectory:
        return self._dispatch(self._outgoing(purpose, plan, prepared))

    def _outgoing(self, purpose: str, plan: Planner, prepared: Optional[PreparedGoal] = None) -> OutgoingGoal:
        """The next goal, planned from where the part is now (or the prepared one, where it still fits)."""
        now = self._clock()
        positions, velocities, accelerations = self.current_state(now)
        if prepared is not None and prepared.fits(positions, velocities):
            timed, points, goal = prepared.timed, prepared.points, prepared.goal
        else:
            timed = plan(now, positions, velocities, accelerations)
            points = to_points(timed)
            goal = goal_message(PARTS[self.part].joints, points)
        return OutgoingGoal(purpose, now, (positions, velocities, accelerations), timed, points, goal)

    def _dispatch(self, outgoing: OutgoingGoal) -> TimedTrajectory:
        purpose, now, timed, points = outgoing.purpose, outgoing.planned_at, outgoing.timed, outgoing.points
        joints = PARTS[self.part].joints
        bands = self.motion.bounds if self.motion is not None else ()
        lower, upper = [b.lower for b in bands], [b.upper for b in bands]
        self._goal_number += 1
        number = self._goal_number

        def transition(handle, part=self.part, action=self.action):
            if handle.get_comm_state() != CommState.DONE:
                return
            result = handle.get_result()
            self._post(GoalDone(part, action, number, handle.get_goal_status(),
                                None if result is None else result.error_code,
                                "" if result is None else result.error_string))

        # On the wire when it returns: the message may change.
        handle = self.client.send_goal(outgoing.goal, transition)
        self._replaced_unreleased = bool(self._unfinished)  # none of them runs for us any more: see prepare()
        self._sent = SentGoal(number, purpose, handle, outgoing.start_state, points, now, outgoing.goal)
        self._unfinished[number] = self._sent
        while len(self._unfinished) > MAX_UNFINISHED_GOALS:  # a controller that never answers
            self._unfinished.popitem(last=False)
        self._debug("%s: %s goal %d (%s) sent to %s: %d points over %.1f s.", NODE_NAME,
                    self.part, number, purpose, self.action, len(points), timed.times[-1])
        self._log.write(contract.GOAL_SENT, part=self.part, label=PARTS[self.part].label,
                        action=self.action, purpose=purpose, goal=number, joints=joints,
                        centre=PARTS[self.part].centre, lower=lower, upper=upper,
                        moving=self.motion.moving if self.motion is not None else (),
                        times=timed.times, positions=timed.positions)
        return timed

    def prepare(self) -> None:
        """Builds what the next goal or the stop will need from the goal just sent (its spline, with every
        segment's polynomial), and lets go of the goals it replaced (freeing 100 points takes a quarter of a
        millisecond), while nothing waits: after an enable's or a stop's goals have all left, not between them."""
        if self._replaced_unreleased:
            for unfinished in self._unfinished.values():
                if unfinished is not self._sent:
                    unfinished.release()
            self._replaced_unreleased = False
        if self._sent is not None:
            self._sent.spline.compute_segments()

    def cancel(self) -> None:
        if self._sent is not None and self.connected:
            self._sent.handle.cancel()
        self._sent = None

    def overdue(self, now: float) -> bool:
        """True when our goal should long have ended but no result came (a lost result)."""
        return self._sent is not None and now > self._sent.end_time + LOST_RESULT_GRACE

    def is_current(self, goal_number: int) -> bool:
        return self._sent is not None and self._sent.number == goal_number

    @property
    def sent_purpose(self) -> Optional[str]:
        return None if self._sent is None else self._sent.purpose
