"""One part's motion streamed to naoqi_driver's JointAngles topic (actuation ``joint_angles``, README: "Actuation on
the robot"): the states of core/motion_stream.py, the planners of core/part_stream.py, and the streaming of
motion/joint_angle_stream.py.

The part plans as a goal stream does: a planned trajectory from where the part is, the next one when it is about to end
(a continuous style: at its `replacement_time`, before its ending). Instead of sending it as a goal, at every send time
(a grid of PERIOD on the stream's clock) it publishes the setAngles calls that `joint_angle_stream.tick` makes of it:
one per joint speed, up to five for an arm. Each part's grid is offset by PERIOD / 5 from the previous part's:
naoqi_driver queues ten messages of the topic (the simulated Pepper's rospy subscriber keeps ten of one read), and the
parts' calls all at once, up to fifteen, would lose the first ones. naoqi_driver runs each call at once, so the robot
moves along the plan with no dead band (unlike pepper_dcm's). A disable stops the stream at once and sends one call:
every joint to its centre at STOP_SPEED (the part is ``homing`` until the slowest arrives), or, without homeOnDisable,
to where it is measured now.

The supervisor thread is the only caller. What the stream needs from the outside is injected, so that unit tests
drive it with a fake topic and a fake clock:

- ``topic``: the front-end's shared JointAngles publisher (ros1/joint_angles_topic.py on ROS 1,
  ros2/joint_angles_topic.py on ROS 2: ``name``, ``send(angles, now)``, ``listened()``);
- ``clock``: seconds, on the clock naoqi_driver's joints move on (0 while a simulated clock does not run yet);
- ``joint_states``: where the joints are (core/joint_states.py's JointStateCache: ``positions(joints)``, the current
  positions or None when unknown; ``moving(joints)``, calls of ours move them);
- at each enable, a `motion.planners.Planner` of the part's motion style;
- ``log``: the event log; ``debug`` and ``warn``: console lines (core/console.py by default).
"""
import math
from typing import Callable, NamedTuple, Optional

import numpy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import NODE_NAME, PURPOSE_ANIMATE, PURPOSE_HOME
from cssr_system.core.motion_stream import PartMotionStream, StreamState
from cssr_system.core.part_stream import HOME_MAX_DURATION, TRANSITIONS
from cssr_system.motion import joint_angle_stream as streaming
from cssr_system.motion.planners import Planner
from cssr_system.motion.trajectory_timing import to_points
from cssr_system.motion.waypoints import PartMotion
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

IDLE, ANIMATING, YIELDING, WAITING, HOMING = (StreamState.IDLE, StreamState.ANIMATING, StreamState.YIELDING,
                                              StreamState.WAITING, StreamState.HOMING)
SUMMARY_PERIOD = 1.0  # s of stream summed up in one angles_sent line


class LatestTick(NamedTuple):
    """The latest tick: when it was sent, where the joints were then, where they arrive at the next send time."""
    at: float
    origins: numpy.ndarray
    arrivals: numpy.ndarray
    next_send: float


def send_phase(part: str, period: float = streaming.PERIOD) -> float:
    """Where `part`'s send times lie in each period: the parts (joint_table.PARTS order) spread evenly over it."""
    return list(PARTS).index(part) * period / len(PARTS)


def next_send_time(now: float, phase: float = 0.0, period: float = streaming.PERIOD) -> float:
    """The grid time (`phase` plus a multiple of `period` on the clock) after which the joints are to be where the
    next call sends them: at least half a period after `now`, so that no call asks a joint to cover a distance in a
    moment."""
    return phase + math.floor((now - phase + 0.5 * period) / period + 1.0) * period


class JointAngleStream(PartMotionStream):
    """One part's motion as a stream of setAngles calls. Only the supervisor thread calls its methods."""

    not_connected = "naoqi_driver not listening"

    def __init__(self, part: str, action: str, topic, clock: Callable[[], float],
                 joint_states, log,
                 debug: Callable[..., None] = console.debug, warn: Callable[..., None] = console.warning) -> None:
        super().__init__(part, topic.name, TRANSITIONS, log, debug)
        self.action = action  # the topic file's name of the part: the supervisor's key of this stream
        self.topic = topic
        self.motion: Optional[PartMotion] = None
        self._clock = clock
        self._joint_states = joint_states
        self._warn = warn
        self._plan: Optional[Planner] = None
        self._followed: Optional[JointTrajectorySpline] = None  # the planned trajectory the stream follows
        self._replaced_at = 0.0  # when the next plan replaces the followed one, on the stream's clock
        self._sent: Optional[LatestTick] = None  # None: the stream does not run
        self._animated = False  # a call of ours moved the part away from its centre since the last return
        self._homing_until: Optional[float] = None
        self._goal_number = 0  # numbers the planned trajectories, as a goal stream numbers its goals
        self._summary_since: Optional[float] = None
        self._summary_messages = 0

    @property
    def joints(self) -> tuple:
        return PARTS[self.name].joints

    # -- commands from the supervisor ---------------------------------------------------------------
    def plan_stop(self, home: bool) -> Optional[streaming.JointAngles]:
        """The call `disable(home)` would send, made now without sending it (None: it sends none): every joint to
        its centre (`home`), else to where it is."""
        if not (self.connected and self._animated and self.state in (ANIMATING, WAITING)):
            return None
        where = dict(zip(self.joints, self._where_now(self._clock()).tolist()))
        return streaming.stop_message(where, dict(zip(self.joints, PARTS[self.name].centre)) if home else where)

    def return_duration(self, planned: Optional[streaming.JointAngles]) -> float:
        """How long the return `plan_stop` made a moment ago takes (0: none)."""
        if planned is None:
            return 0.0
        return streaming.stop_duration(dict(zip(self.joints, self._where_now(self._clock()).tolist())), planned)

    def disable(self, home: bool, planned: Optional[streaming.JointAngles] = None) -> None:
        """Stop the stream at once, then one call (`plan_stop`, or `planned` made by it a moment ago)."""
        if self._disabled_without_sending():
            return
        now = self._clock()
        call = planned or self.plan_stop(home)
        where = self._where_now(now)
        self._stop_streaming(now)
        if call is None:
            self.transition_to(IDLE, "disabled")
            return
        self._send_stop(now, call, where, home)
        if not home:
            self.transition_to(IDLE, "disabled; stopped where the joints are")
            return
        self.transition_to(HOMING, "disabled; returning to the centre")

    def _send_home(self) -> None:
        now = self._clock()
        where = self._where_now(now)
        self._send_stop(now, streaming.stop_message(dict(zip(self.joints, where.tolist())),
                                                    dict(zip(self.joints, PARTS[self.name].centre))), where, True)

    def _send_stop(self, now: float, call: streaming.JointAngles, where: numpy.ndarray, returns_home: bool) -> None:
        """Sends a stop's call; one to the centres (`returns_home`) is logged as the return it is, and timed."""
        self._joint_states.moving(self.joints)
        self.topic.send(call, now)
        if not returns_home:
            return
        duration = streaming.stop_duration(dict(zip(self.joints, where.tolist())), call)
        self._log_planned(PURPOSE_HOME, [0.0, duration], [where.tolist(), list(PARTS[self.name].centre)])
        if duration > HOME_MAX_DURATION:
            self._warn("%s: %s returns to its centre in %.1f s.", NODE_NAME, self.name, duration)
        self._homing_until = now + duration

    # -- naoqi_driver and the other nodes -------------------------------------------------------------
    def controller_ready(self) -> bool:
        """For the controller watcher: naoqi_driver subscribes to the topic."""
        return self.topic.listened()

    def controller_connected(self) -> None:
        if not self._connection_changed(True):
            return
        console.info("%s: %s listens to %s.", NODE_NAME, self.name, self.controller)
        if self.state == WAITING:
            self._animate("naoqi_driver listening")

    def controller_lost(self) -> None:
        """Nobody listens to the topic any more: the stream pauses and starts again from the measured joints."""
        if not self._connection_changed(False):
            return
        self._warn("%s: nobody listens to %s any more; %s waits.", NODE_NAME, self.controller, self.name)
        self._stop_streaming(self._clock())
        if self.state in (ANIMATING, WAITING):
            self.transition_to(WAITING, "naoqi_driver gone")
        elif self.state == HOMING:
            self._animated = False
            self._homing_until = None
            self.transition_to(IDLE, "naoqi_driver gone while returning to the centre")

    def _abandon_home(self) -> None:
        self._animated = False
        self._homing_until = None

    def _yield(self, caller: str, why: str) -> None:
        now = self._clock()
        self._stop_streaming(now)
        self._followed = None  # the part resumes from where the other node leaves it
        self.start_yielding(caller, now, why)

    # -- time --------------------------------------------------------------------------------------
    def tick(self) -> None:
        """Whatever is due: the end of a yield or of the return home, the next plan, the calls of a send time."""
        now = self._clock()
        if self.state == YIELDING:
            if self.foreign.calm(now):
                self._resume(now)
            return
        if self.state == HOMING and now >= self._homing_until:
            self._animated = False
            self._homing_until = None
            self.transition_to(IDLE, "at the centre")
            return
        if self.state != ANIMATING:
            return
        if self._continuation_due(now):
            self.motions_completed += 1
            self._animate("continuing the motion")
        if self._sent is None or now >= self._sent.next_send:
            self._send(now)

    def next_deadline(self) -> Optional[float]:
        """When `tick` next has something to do, on the stream's clock (None: nothing planned)."""
        if self.state == ANIMATING:
            return self._sent.next_send if self._sent is not None else self._clock()
        if self.state == HOMING:
            return self._homing_until
        if self.state == YIELDING:
            return self.foreign.next_deadline(self._clock())
        return None

    def _continuation_due(self, now: float) -> bool:
        """The followed plan is due to be replaced: at its end, or at its `replacement_time` for a continuous style."""
        if self._followed is None or self._plan is None:
            return False
        return now >= self._replaced_at

    # -- the stream ---------------------------------------------------------------------------------
    def _animate(self, why: str, planned=None) -> None:
        """Follow the next plan, from the state of the followed one, else from the measured joints (`planned` is
        always None: this stream makes nothing ahead)."""
        now = self._clock()
        start_state = self._current_state(now)
        timed = self._plan(now, *start_state)
        self._followed = JointTrajectorySpline(*start_state, to_points(timed), start_time=now)
        replaced_after = self._plan.replacement_time(timed)
        self._replaced_at = self._followed.end_time if replaced_after is None else now + replaced_after
        self._log_planned(PURPOSE_ANIMATE, timed.times, timed.positions)
        self._animated = True
        self._homing_until = None
        self._joint_states.moving(self.joints)
        self.transition_to(ANIMATING, why)

    @property
    def drives_joints(self) -> bool:
        """Calls of ours move the part: the plan, not a measurement, says where its joints are."""
        return self.state in (ANIMATING, HOMING)

    def _current_state(self, now: float):
        """Positions, velocities and accelerations to plan from: the followed plan's (it holds its last point
        after its end), else the measured joints (else where the stream sent them, else the centre), at rest."""
        if self._followed is not None:
            return tuple(numpy.asarray(values, dtype=float) for values in self._followed.sample(now))
        zeros = numpy.zeros(len(self.joints))
        return self._where_now(now), zeros, zeros

    def _where_now(self, now: float) -> numpy.ndarray:
        """The measured joints, else where the latest call has brought them by `now`, else the centre."""
        measured = self._joint_states.positions(self.joints)
        if measured is not None:
            return numpy.asarray(measured, dtype=float)
        if self._sent is not None:
            share = min(1.0, max(0.0, (now - self._sent.at) / (self._sent.next_send - self._sent.at)))
            return self._sent.origins + share * (self._sent.arrivals - self._sent.origins)
        return numpy.array(PARTS[self.name].centre, dtype=float)

    def _send(self, now: float) -> None:
        """The calls of one send time: the followed plan at the next send time, reached exactly then."""
        origins = self._sent.arrivals if self._sent is not None else self._where_now(now)
        following = next_send_time(now, send_phase(self.name))
        tick = streaming.tick(self.joints, self._followed, now, origins, period=following - now,
                              look_ahead=following - now)
        for call in tick.messages:
            self.topic.send(call, now)
        self._sent = LatestTick(now, numpy.asarray(origins, dtype=float), tick.arrivals, following)
        self._count(now, len(tick.messages))

    def _stop_streaming(self, now: float) -> None:
        self._flush_summary(now)
        self._sent = None
        self._followed = None

    # -- the log ------------------------------------------------------------------------------------
    def _count(self, now: float, messages: int) -> None:
        """One angles_sent line per SUMMARY_PERIOD of stream, counting the calls sent in it."""
        # Half a period's slack: the send times' sums of floats fall a hair short of a whole second.
        if self._summary_since is not None and now - self._summary_since >= SUMMARY_PERIOD - streaming.PERIOD / 2:
            self._flush_summary(now)
        if self._summary_since is None:
            self._summary_since = now
        self._summary_messages += messages

    def _flush_summary(self, now: float) -> None:
        if self._summary_since is not None:
            self._log.write(contract.ANGLES_SENT, part=self.name, topic=self.controller,
                            messages=self._summary_messages, seconds=round(now - self._summary_since, 3))
        self._summary_since = None
        self._summary_messages = 0

    def _log_planned(self, purpose: str, times, positions) -> None:
        """One goal_sent line per planned trajectory, as a goal stream writes for each goal (the harness and the
        plot read the bands and positions from it)."""
        self._goal_number += 1
        part, bands = PARTS[self.name], self.motion.bounds if self.motion is not None else ()
        self._debug("%s: %s trajectory %d (%s) streamed to %s: %d points over %.1f s.", NODE_NAME, self.name,
                    self._goal_number, purpose, self.controller, len(times), times[-1])
        self._log.write(contract.GOAL_SENT, part=self.name, label=part.label, action=self.controller,
                        purpose=purpose, goal=self._goal_number, joints=part.joints, centre=part.centre,
                        lower=[b.lower for b in bands], upper=[b.upper for b in bands],
                        moving=self.motion.moving if self.motion is not None else (),
                        times=times, positions=positions)
