"""One controller's goal stream: a small state machine that owns its transitions (core/motion_stream.py).

``idle``: no goal of ours runs; ``animating``: one goal after the other; ``yielding``: another node moves the part
(README: "Sharing the robot"); ``waiting``: enabled, but waiting for the controller to appear or for a retry;
``homing``: the return-to-centre goal after a disable.

The supervisor thread is the only caller. What the stream needs from the outside is injected, so that unit tests
drive it with a fake action client and a fake clock:

- ``client``: the front-end's FollowJointTrajectory client (core/goals.py: ``goal``, ``send``, and ``ready()``: its
  action server answers);
- ``clock``: seconds, on the clock the controller executes goals on (0 while a simulated clock does not run yet);
- ``joint_states``: where the joints are (core/joint_states.py's JointStateCache: ``positions(joints)``, the current
  positions or None when unknown; ``moving(joints)``, a goal of ours moves them; ``settle(joints, positions)``, a goal
  of ours left them there);
- ``post``: puts an event on the supervisor's queue (actionlib calls back from its own threads);
- at each enable, a `motion.planners.Planner` of the part's motion style;
- ``log``: the event log; ``debug`` and ``warn``: console lines (core/console.py by default).
"""
from collections import OrderedDict
from typing import Callable, Optional

import numpy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import NODE_NAME, PURPOSE_ANIMATE, PURPOSE_HOME
from cssr_system.core.events import GoalDone
from cssr_system.core.foreign_motion import COMMAND, DEFAULT_QUIET_TIME, GOAL
from cssr_system.core.goals import (ABORTED, GOAL_TOLERANCE_VIOLATED, LOST, PREEMPTED, RUNNING_AT_EXIT, SUCCEEDED,
                                    WITHHELD, OutgoingGoal, RunningGoal)
from cssr_system.core.motion_stream import PartMotionStream, StreamState
from cssr_system.motion.planners import HomePlanner, Planner, settled
from cssr_system.motion.trajectory_timing import TimedTrajectory
from cssr_system.motion.waypoints import PartMotion
from cssr_system.pepper.joint_table import PARTS

HOME_MAX_DURATION = 2.0  # s; longer returns are reported (the speed cap wins over this bound)
# s before a part tries again after a failed goal (rejected, aborted), or after a goal that another client's replaced
# when that client's goal does not show on the action's status.
RETRY_DELAY = 2.0
MAX_RETRY_DELAY = 30.0  # s: the back-off doubles the delay after each failure in a row, up to this
HEALTHY_RUN = 5.0  # s: a goal that ran this long before failing starts the back-off afresh
MAX_UNFINISHED_GOALS = 16  # handles kept for goals whose end has not been reported yet
LOST_RESULT_GRACE = 5.0  # s after a goal's end before a missing result counts as lost
# An abort for the end state only: the trajectory has played out (give or take the two clocks' difference) and
# every joint is this close to its last point.
END_TIME_SLACK = 0.1  # s
END_POSITION_TOLERANCE = 0.01  # rad

IDLE, ANIMATING, YIELDING, WAITING, HOMING = (StreamState.IDLE, StreamState.ANIMATING, StreamState.YIELDING,
                                              StreamState.WAITING, StreamState.HOMING)
TRANSITIONS = {
    IDLE: {ANIMATING, WAITING, YIELDING, HOMING},
    ANIMATING: {ANIMATING, WAITING, YIELDING, HOMING, IDLE},
    YIELDING: {ANIMATING, WAITING, IDLE},
    WAITING: {ANIMATING, WAITING, YIELDING, HOMING, IDLE},
    HOMING: {ANIMATING, WAITING, YIELDING, IDLE},
}


class PartStream(PartMotionStream):
    """One controller's goal stream. Only the supervisor thread calls its methods."""

    def __init__(self, part: str, action: str, client, clock: Callable[[], float],
                 joint_states, post: Callable[[object], None], log,
                 debug: Callable[..., None] = console.debug, warn: Callable[..., None] = console.warning) -> None:
        super().__init__(part, action, TRANSITIONS, log, debug)
        self.client = client
        self.motion: Optional[PartMotion] = None
        self.retry_at: Optional[float] = None
        self._clock = clock
        self._joint_states = joint_states
        self._post = post
        self._warn = warn
        self._plan: Optional[Planner] = None
        self._animated = False  # a goal of ours moved the part away from its centre since the last return
        self._failures = 0  # failed goals in a row: the back-off
        self._goal_number = 0
        self._sent: Optional[RunningGoal] = None
        # Goals that have not reported their end, replaced and cancelled ones too: holding their handles keeps
        # their transitions coming, so every goal's final state reaches the log.
        self._unfinished: "OrderedDict[int, RunningGoal]" = OrderedDict()

    @property
    def action(self) -> str:
        return self.controller

    # -- commands from the supervisor ---------------------------------------------------------------
    def enable(self, motion: PartMotion, plan: Planner, quiet_time: float = DEFAULT_QUIET_TIME,
               planned: Optional[OutgoingGoal] = None) -> None:
        """Animate `motion` with goals from `plan`; a running goal is replaced smoothly (the controller splices).
        `planned`: the first goal, from `plan_start(plan, quiet_time)` a moment ago (planned now when None)."""
        self.retry_at = None
        super().enable(motion, plan, quiet_time, planned)

    def _plan_first(self, plan: Planner) -> OutgoingGoal:
        return self._outgoing(PURPOSE_ANIMATE, plan)

    def _returns_home(self, home: bool) -> bool:
        """A stop of this part sends a return-to-centre goal (else it cancels, or sends nothing)."""
        return home and self.connected and self._animated and self.state in (ANIMATING, WAITING)

    def plan_stop(self, home: bool) -> Optional[OutgoingGoal]:
        """The goal `disable(home)` would send, planned now without sending it (None: it sends none)."""
        return self._outgoing(PURPOSE_HOME, HomePlanner(self.part, self.motion)) if self._returns_home(home) else None

    @staticmethod
    def return_duration(planned: Optional[OutgoingGoal]) -> float:
        """How long the return `plan_stop` planned takes, with its hold (0: none)."""
        return planned.duration if planned is not None else 0.0

    def _send_home(self) -> None:
        self._dispatch(self._outgoing(PURPOSE_HOME, HomePlanner(self.part, self.motion)))

    def disable(self, home: bool, planned: Optional[OutgoingGoal] = None) -> None:
        """Stop: one return-to-centre goal when `home` (and a goal of ours moves the part), else cancel.
        `planned`: that goal, from `plan_stop(home)` a moment ago (planned now when None)."""
        self.retry_at = None
        if self._disabled_without_sending():
            return
        if self._returns_home(home):
            timed = self._dispatch(planned or self.plan_stop(home))
            if timed.times[-1] > HOME_MAX_DURATION:
                self._warn("%s: %s returns to its centre in %.1f s (speed cap).", NODE_NAME, self.part,
                           timed.times[-1])
            self.transition_to(HOMING, "disabled; returning to the centre")
            return
        self.cancel()
        self.transition_to(IDLE, "disabled")

    # -- what the controller and the other nodes do --------------------------------------------------
    def goal_done(self, event: GoalDone) -> None:
        """A goal of ours reported its end (any goal: replaced and cancelled ones too)."""
        sent = self._unfinished.pop(event.goal_number, None)
        if sent is None:
            return  # reported already
        current = self.is_current(event.goal_number) and self.state != IDLE
        state_name = self._final_state(sent, event.state, current)
        reached = self._reached_its_end(sent, event)
        self._log_finished(event.goal_number, sent, state_name, event.error_code, event.error_string, reached)
        if not current:
            return  # a goal we replaced or cancelled: its end changes nothing
        if reached:  # the controller holds the joints at the goal's last point: the next goal starts there
            self._joint_states.settle(PARTS[self.part].joints, sent.last_positions)
        if reached or sent.purpose == PURPOSE_HOME:
            self._failures = 0
            self._finish_goal("goal %d %s" % (event.goal_number, state_name))
        elif sent.replaced_by or state_name == WITHHELD:  # no failure: the other client's goal makes the part yield
            self._wait_for_the_other_client(event.goal_number, sent.replaced_by)
        else:
            self._retry_later(sent, event.goal_number, state_name, event.error_string)

    def _wait_for_the_other_client(self, number: int, replaced_by: str) -> None:
        """Our goal was replaced by another client's, or withheld by the last look because one had come: its
        ForeignGoal makes the part yield; without one (not on the status), the part tries again later."""
        self._sent = None
        self.retry_at = self._clock() + RETRY_DELAY
        self.transition_to(WAITING, "goal %d %s" % (number, "replaced by " + replaced_by if replaced_by else
                                                    "withheld: another client's goal had come"))

    def _final_state(self, sent: RunningGoal, state_name: str, current: bool) -> str:
        """The log's final state. Another node's goal that replaced ours makes it PREEMPTED with `replaced_by`:
        joint_trajectory_controller on ROS 2 may abort the goal it replaces; and a goal of ours still current
        (none of ours replaced it) that ends PREEMPTED was replaced by another client, whose goal may show on the
        action's status only after our result."""
        if sent.replaced_by and state_name in (ABORTED, PREEMPTED):
            return PREEMPTED
        if state_name == PREEMPTED and current:
            sent.replaced_by = "another client of %s" % self.action
        return state_name

    def _log_finished(self, number: int, sent: RunningGoal, state_name: str, error_code: Optional[int],
                      error_string: str, reached: bool) -> None:
        """The goal's one goal_finished line (`replaced_by` when another node's goal or trajectory replaced it)."""
        extra = {"replaced_by": sent.replaced_by} if sent.replaced_by and state_name == PREEMPTED else {}
        self._log.write(contract.GOAL_FINISHED, part=self.part, action=self.action, purpose=sent.purpose,
                        goal=number, state=state_name, error_code=error_code, error_string=error_string,
                        reached=reached, **extra)

    def finish_at_exit(self) -> None:
        """The node exits: each goal whose end has not been reported gets its one goal_finished line now."""
        for number, sent in self._unfinished.items():
            self._log_finished(number, sent, RUNNING_AT_EXIT, None, "still running when the node exited", False)
        self._unfinished.clear()

    def _reached_its_end(self, sent: RunningGoal, event: GoalDone) -> bool:
        """The goal did what it was sent for: SUCCEEDED, or ABORTED only for its end state (GOAL_TOLERANCE_VIOLATED:
        the controller judged the joints still moving) once it had played out with the joints at its last point."""
        if event.state == SUCCEEDED:
            return True
        if not self._aborted_for_its_end_state(sent, event):
            return False
        measured = self.measured_positions()
        return measured is not None and float(numpy.max(numpy.abs(measured - sent.last_positions))) <= \
            END_POSITION_TOLERANCE

    def _aborted_for_its_end_state(self, sent: RunningGoal, event: GoalDone) -> bool:
        return (event.state == ABORTED and event.error_code == GOAL_TOLERANCE_VIOLATED
                and self._clock() >= sent.end_time - END_TIME_SLACK)

    def end_needs_measurement(self, event: GoalDone) -> bool:
        """Whether this goal's end is judged from the measured joints and none is current yet: the supervisor then
        has them measured and hands the end over once they are (or after a short wait)."""
        sent = self._unfinished.get(event.goal_number)
        return sent is not None and self._aborted_for_its_end_state(sent, event) and self.measured_positions() is None

    def _retry_later(self, sent: RunningGoal, number: int, state_name: str, error_string: str) -> None:
        now = self._clock()
        if sent.dated and now - sent.start_time >= HEALTHY_RUN:
            self._failures = 0
        self._failures += 1
        delay = min(RETRY_DELAY * 2 ** (self._failures - 1), MAX_RETRY_DELAY)
        self._warn("%s: %s goal ended %s (%s); trying again in %.0f s.", NODE_NAME, self.part, state_name,
                   error_string or "no reason given", delay)
        self._sent = None  # the controller does not run it: the retry starts from the measured joints
        self.retry_at = now + delay
        self.transition_to(WAITING, "goal %d %s; retry in %.0f s" % (number, state_name, delay))

    @property
    def drives_joints(self) -> bool:
        """A goal of ours runs on the part: the plan, not a measurement, says where its joints are."""
        return self.state in (ANIMATING, HOMING) and self._sent is not None

    def controller_ready(self) -> bool:
        """For the controller watcher: the controller's action server answers."""
        return self.client.ready()

    def controller_connected(self) -> None:
        if not self._connection_changed(True):
            return
        console.info("%s: controller %s connected.", NODE_NAME, self.action)
        if self.state == WAITING and self.retry_at is None:
            self._animate("controller connected")

    def controller_lost(self) -> None:
        """The controller went away (its server no longer answers): our goal is gone with it. The part waits
        and animates again from the measured joints as soon as the controller is back."""
        if not self._connection_changed(False):
            return
        self._sent = None
        self.retry_at = None
        self._warn("%s: controller %s is gone; %s waits for it.", NODE_NAME, self.action, self.part)
        if self.state in (ANIMATING, WAITING):
            self.transition_to(WAITING, "controller gone")
        elif self.state == HOMING:
            self._animated = False
            self.transition_to(IDLE, "controller gone while returning to the centre")

    def _abandon_home(self) -> None:
        self._sent = None
        self._animated = False

    def foreign_motion(self, key: str, caller: str, kind: str, last_point_at: Optional[float]) -> None:
        """Another node's goal or trajectory on the controller replaces our goal there (a setAngles call does not)."""
        if kind in (GOAL, COMMAND) and self._sent is not None and self.state in (ANIMATING, WAITING, HOMING):
            self._sent.replaced_by = caller
        super().foreign_motion(key, caller, kind, last_point_at)

    def _yield(self, caller: str, why: str) -> None:
        self._sent = None  # the controller runs the other node's motion now; ours is kept only for its result
        self.retry_at = None
        self.start_yielding(caller, self._clock(), why)

    # -- time --------------------------------------------------------------------------------------
    def tick(self) -> None:
        """Time-driven transitions: the end of a yield, a continuation or a retry that is due, a lost result."""
        now = self._clock()
        if now > 0.0:
            self._date_goals(now)
        if self.state == YIELDING:
            if self.foreign.calm(now):
                self._resume(now)
            return
        if self._continuation_due(now):
            self.motions_completed += 1
            self._animate("continuing the motion")
        if self.overdue(now):
            self._warn("%s: no result for the %s goal; sending the next one.", NODE_NAME, self.part)
            self._log.write(contract.ERROR, where=self.part, message="goal result lost")
            self._finish_goal("goal result lost")
        if self.retry_at is not None and now >= self.retry_at:
            self.retry_at = None
            if self.state == WAITING:
                self._animate("retry")

    def _date_goals(self, now: float) -> None:
        """Goals sent before a simulated clock ran start when it starts: their deadlines count from now."""
        for sent in self._unfinished.values():
            if not sent.dated:
                sent.start(now)

    def _continuation_at(self) -> Optional[float]:
        """When a continuous style's goal is replaced by the next, before it ends."""
        if self.state != ANIMATING or self.sent_purpose != PURPOSE_ANIMATE:
            return None
        return self._sent.replacement_time

    def _continuation_due(self, now: float) -> bool:
        at = self._continuation_at()
        return at is not None and now >= at

    def next_deadline(self) -> Optional[float]:
        """When `tick` next has something to do, on the stream's clock (None: nothing planned)."""
        deadlines = [self.retry_at, self._continuation_at()]
        if self.state == YIELDING:
            deadlines.append(self.foreign.next_deadline(self._clock()))
        if self._sent is not None:
            deadlines.append(self._sent.end_time + LOST_RESULT_GRACE)
        deadlines = [deadline for deadline in deadlines if deadline is not None and deadline < float("inf")]
        return min(deadlines) if deadlines else None

    def overdue(self, now: float) -> bool:
        """True when our goal should long have ended but no result came (a lost result)."""
        return self._sent is not None and now > self._sent.end_time + LOST_RESULT_GRACE

    # -- goals --------------------------------------------------------------------------------------
    def _finish_goal(self, why: str) -> None:
        """A goal of ours ended as planned: a part going home is done, an animating one goes on."""
        if self.state == ANIMATING and self.sent_purpose == PURPOSE_ANIMATE:
            self.motions_completed += 1
            self._animate(why)  # from the measured joints, else from where the ended goal left them
            return
        purpose, self._sent = self.sent_purpose, None
        if purpose == PURPOSE_HOME and self.state == HOMING:
            self._animated = False
            self.transition_to(IDLE, why + "; at the centre")

    def _animate(self, why: str, planned: Optional[OutgoingGoal] = None) -> None:
        self._dispatch(planned or self._outgoing(PURPOSE_ANIMATE, self._plan))
        self._animated = True
        self.transition_to(ANIMATING, why)

    def measured_positions(self) -> Optional[numpy.ndarray]:
        return self._joint_states.positions(PARTS[self.part].joints)

    def current_state(self, now: float):
        """Positions, velocities and accelerations to start the next goal from: what the controller is executing
        for us (it splices new goals onto that), else the joints as measured or as a goal of ours that succeeded left
        them, else where the ended goal left them, else the centre."""
        joints = PARTS[self.part].joints
        if self._sent is not None and self._sent.dated and now <= self._sent.end_time:
            positions, velocities, accelerations = self._sent.spline.sample(now)
            return numpy.asarray(positions), numpy.asarray(velocities), numpy.asarray(accelerations)
        measured = self._joint_states.positions(joints)
        if measured is None and self._sent is not None and self._sent.dated:
            measured = numpy.asarray(self._sent.spline.sample(now)[0])
        if measured is None:
            measured = numpy.array(PARTS[self.part].centre, dtype=float)
        zeros = numpy.zeros(len(joints))
        return measured, zeros, zeros

    def _outgoing(self, purpose: str, plan: Planner) -> OutgoingGoal:
        """The next goal, planned from where the part is now."""
        now = self._clock()
        start_state = self.current_state(now)
        timed = plan(now, *start_state)
        held = settled(timed)
        return OutgoingGoal(purpose, now if now > 0.0 else None, start_state, timed, held.times[-1],
                            self.client.goal(PARTS[self.part].joints, held), plan.replacement_time(timed))

    def _dispatch(self, outgoing: OutgoingGoal) -> TimedTrajectory:
        self._goal_number += 1
        number = self._goal_number

        def done(state: str, error_code: Optional[int], error_string: str, part=self.part, action=self.action):
            self._post(GoalDone(part, action, number, state, error_code, error_string))

        self._joint_states.moving(PARTS[self.part].joints)
        handle = self.client.send(outgoing.goal, done)
        for unfinished in self._unfinished.values():  # none of them runs for us any more
            unfinished.release()
        self._sent = RunningGoal(number, outgoing.purpose, handle, outgoing)
        self._unfinished[number] = self._sent
        while len(self._unfinished) > MAX_UNFINISHED_GOALS:  # a controller that never answers
            dropped, lost = self._unfinished.popitem(last=False)
            self._log_finished(dropped, lost, LOST, None, "no result after %d newer goals" % MAX_UNFINISHED_GOALS,
                               False)
        self._log_sent(number, outgoing)
        return outgoing.timed

    def _log_sent(self, number: int, outgoing: OutgoingGoal) -> None:
        timed, part = outgoing.timed, PARTS[self.part]
        bands = self.motion.bounds if self.motion is not None else ()
        self._debug("%s: %s goal %d (%s) sent to %s: %d points over %.1f s.", NODE_NAME, self.part, number,
                    outgoing.purpose, self.action, len(timed.times), timed.times[-1])
        self._log.write(contract.GOAL_SENT, part=self.part, label=part.label, action=self.action,
                        purpose=outgoing.purpose, goal=number, joints=part.joints, centre=part.centre,
                        lower=[b.lower for b in bands], upper=[b.upper for b in bands],
                        moving=self.motion.moving if self.motion is not None else (),
                        times=timed.times, positions=timed.positions)

    def prepare(self) -> None:
        """Work for later done now, while nothing waits (the supervisor calls it when its queue is empty)."""
        if self._sent is not None:
            self._sent.prepare()

    def cancel(self) -> None:
        if self._sent is not None and self.connected:
            self._sent.handle.cancel()
        self._sent = None

    def is_current(self, goal_number: int) -> bool:
        return self._sent is not None and self._sent.number == goal_number

    @property
    def sent_purpose(self) -> Optional[str]:
        return None if self._sent is None else self._sent.purpose
