"""The base's rotation commands on the Wheels topic, as a small state machine driven by the supervisor
(core/motion_stream.py): ``animating`` turns it, ``homing`` turns it back to its heading at enable, ``waiting``
while nothing listens to the topic (a turn nobody hears would be "undone" by a return that somebody does hear).
"""
from typing import Callable, Optional

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import NODE_NAME, PURPOSE_ANIMATE, PURPOSE_HOME
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.core.foreign_motion import TWIST
from cssr_system.core.motion_stream import MotionStream, StreamState
from cssr_system.motion.base_rotation import BaseRotationPlanner, heading_after_interruption
from cssr_system.pepper.joint_table import VELOCITY, base_busy_time, wheels_command_kind

IDLE, ANIMATING, YIELDING, WAITING, HOMING = (StreamState.IDLE, StreamState.ANIMATING, StreamState.YIELDING,
                                              StreamState.WAITING, StreamState.HOMING)
TRANSITIONS = {
    IDLE: {ANIMATING, YIELDING, WAITING, HOMING},
    ANIMATING: {ANIMATING, YIELDING, WAITING, HOMING, IDLE},
    YIELDING: {ANIMATING, WAITING, IDLE},  # another node commands the base: no turn of ours, no return
    WAITING: {ANIMATING, YIELDING, WAITING, IDLE},  # nothing listens to the topic: no turn of ours, no return
    HOMING: {ANIMATING, YIELDING, WAITING, IDLE},
}


class BaseStream(MotionStream):
    """The base's rotation commands on the Wheels topic. Only the supervisor thread calls it.

    A step is a turn (one relative command, or a streamed velocity bump) followed by a pause. The
    robot is busy for the step's busy_time; the pause is ours and is cut short on a new enable.

    Another node's Twist on the topic pauses our turns until it has been calm for the quiet time
    (README: "Sharing the robot"), and cancels our return: the planner's heading counts our own turns only,
    so a turn of another node is never undone.

    `turn(angular_z)`: publishes a Twist with that angular z and nothing else (the front-end's publisher, which has
    it on the wire when it returns); `listened()`: whether a node other than this one (the robot's driver, the
    simulator) subscribes to the topic, asked by the controller watcher as it asks the part streams' controllers."""

    def __init__(self, topic: str, turn: Callable[[float], None], listened: Callable[[], bool], log,
                 debug: Callable[..., None] = console.debug, warn: Callable[..., None] = console.warning) -> None:
        super().__init__(WHEELS_KEY, topic, TRANSITIONS, log, debug)
        self.kind = wheels_command_kind(topic)
        self._turn = turn
        self._listened = listened
        self._warn = warn
        self._foreign_count = 0
        self.planner: Optional[BaseRotationPlanner] = None
        self._step = None
        self._step_purpose = ""
        self._step_started = 0.0
        self._step_ends_at = 0.0
        self._next_sample = 0  # index of the next velocity sample to publish
        self.parked = False  # the mode paused the turns: the frame of enable is kept (`park`)

    @property
    def topic(self) -> str:
        return self.controller

    @property
    def action(self) -> str:  # the controller watcher's name, as a part stream's
        return self.controller

    def start(self, config: Configuration, style, rng, now: float) -> None:
        # Keep the frame of a rotation or return still under way, or of a base the mode paused; otherwise start from
        # heading 0.
        keep = self.planner is not None and (self.parked or self.state != IDLE or self._step is not None)
        self.parked = False
        heading = self.planner.heading if keep else 0.0
        self.planner = BaseRotationPlanner(self.kind, config.rot_maximum_range * style.base_speed_share,
                                           config.heading_bound, rng, pause_range=style.base_pauses)
        self.planner.set_heading(heading)
        self.foreign.quiet_time = config.yield_quiet_time
        if self.state == YIELDING:
            return
        if not self.foreign.calm(now):
            self.start_yielding(self.foreign.caller, now, "enabled while another node moves the base")
            return
        if not self.connected:
            self.transition_to(WAITING, "enabled; nothing listens to %s yet" % self.topic)
            return
        self.transition_to(ANIMATING, "enabled")
        if self._step is None:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE)
        else:
            self._drop_pause()

    def park(self, now: float) -> None:
        """The mode pauses the turns (listening, speaking: README "Modes"): the base stops where it is, and keeps its
        heading since enable, so that idle goes on in the same frame and a disable still turns it back."""
        if self.state != IDLE:
            self.stop(False, now)
        self.parked = True

    def stop(self, return_home: bool, now: float) -> None:
        """Stops at once (an explicit zero on a velocity topic); then, if asked, turns back to the
        heading the base had at enable, once a relative turn under way has ended."""
        parked, self.parked = self.parked, False
        if self.state == IDLE:
            if parked and return_home and self.planner is not None:
                self._return(now, "disabled while the mode paused the turns")
            return
        if self.state == YIELDING:  # another node commands the base: no return now
            self.yielding_to = ""
            self.transition_to(IDLE, "disabled while yielding; no return")
            return
        if self.state == WAITING:
            self.transition_to(IDLE, "disabled while nothing listens to %s; no return" % self.topic)
            return
        if self.kind == VELOCITY and self._step is not None:
            self._publish(0.0)
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
            self._step = None
        elif self._step is not None:
            self._drop_pause()
        if return_home and self.planner is not None:
            self._return(now, "disabled")
        else:
            self.transition_to(IDLE, "disabled")

    def _return(self, now: float, why: str) -> None:
        """Back to the heading of enable, once a relative turn under way has ended."""
        self.transition_to(HOMING, why)
        if self._step is None:
            self._begin(self.planner.return_step(), now, PURPOSE_HOME)

    def return_duration(self, now: float) -> float:
        """How long a `stop(True, now)` keeps the base busy until it is back at the heading of enable (s): a relative
        turn under way ends first; a streamed one stops at once and brakes."""
        if not (self.state == ANIMATING or self.parked) or self.planner is None:
            return 0.0
        if self._step is None:
            return self.planner.return_time(self.planner.heading)
        if self.kind == VELOCITY:
            return self.planner.return_time(heading_after_interruption(self._step, self._next_sample))
        busy = max(0.0, self._step_started + self._step.busy_time - now)
        return busy + self.planner.return_time(self._step.target_heading)

    def foreign_twist(self, caller: str, twist, now: float) -> None:
        """Another node's command on the topic (a geometry_msgs/Twist): our turn stops at once (nothing of ours is
        published)."""
        self._foreign_count += 1
        self.foreign.started("twist-%d" % self._foreign_count, caller, TWIST, now,
                             now + base_busy_time(self.kind, twist.linear.x, twist.linear.y, twist.angular.z))
        if self.state == YIELDING:
            self.yielding_to = caller
        elif self.state in (ANIMATING, HOMING):
            self._interrupt()
            if self.state == ANIMATING:
                self.start_yielding(caller, now, "%s commands the base" % caller)
            else:
                self.log_yield(caller, TWIST)
                self.transition_to(IDLE, "%s commands the base; our return is cancelled" % caller)

    def controller_ready(self) -> bool:
        return self._listened()

    def controller_connected(self) -> None:
        if not self._connection_changed(True):
            return
        console.info("%s: the base's %s is listened to.", NODE_NAME, self.topic)
        if self.state == WAITING:  # its first turn at the supervisor's next tick
            self.transition_to(ANIMATING, "%s listened to" % self.topic)

    def controller_lost(self) -> None:
        """Nothing listens to the topic any more: a turn under way counts as far as it was sent; the base waits
        (or, returning, gives up its return)."""
        if not self._connection_changed(False):
            return
        self._warn("%s: nothing listens to %s any more; the base waits.", NODE_NAME, self.topic)
        if self.state == ANIMATING:
            self._interrupt()
            self.transition_to(WAITING, "nothing listens to %s" % self.topic)
        elif self.state == HOMING:
            self._interrupt()
            self.transition_to(IDLE, "nothing listens to %s; our return is cancelled" % self.topic)

    def _interrupt(self) -> None:
        """Our step ends now: a streamed turn counts as far as it went; a relative turn the robot finishes."""
        if self._step is not None and self.kind == VELOCITY:
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
        self._step = None

    def _drop_pause(self) -> None:
        """The step under way ends when the robot is done with it: our pause after it is dropped."""
        self._step_ends_at = min(self._step_ends_at, self._step_started + self._step.busy_time)

    def next_deadline(self, now: float) -> Optional[float]:
        if self.state == YIELDING:
            return self.foreign.next_deadline(now)
        if self._step is None:
            return None
        if self.kind == VELOCITY and self._next_sample < len(self._step.velocities):
            return self._step_started + self._next_sample * self._step.period
        return self._step_ends_at

    def tick(self, now: float) -> None:
        if self._step is not None and self._step_started == 0.0 < now:
            # Begun before a simulated clock ran (it reads 0 until then): the step starts when the clock starts.
            self._step_ends_at += now
            self._step_started = now
        if self.state == YIELDING:
            if self.foreign.calm(now):
                self.transition_to(ANIMATING if self.connected else WAITING, self.stop_yielding(now))
        if self.state == ANIMATING and self._step is None:  # after a yield, or listened to again
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE)
        elif self._step is not None:
            self._publish_due_samples(now)
            if now >= self._step_ends_at:
                self._end_step(now)

    def _publish_due_samples(self, now: float) -> None:
        step = self._step
        if self.kind == VELOCITY:
            while (self._next_sample < len(step.velocities)
                   and now >= self._step_started + self._next_sample * step.period):
                self._publish(step.velocities[self._next_sample])
                self._next_sample += 1

    def _end_step(self, now: float) -> None:
        ended = self._step_purpose
        self._step = None
        if self.state == ANIMATING:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE)
        elif self.state == HOMING and ended != PURPOSE_HOME:
            self._begin(self.planner.return_step(), now, PURPOSE_HOME)
        elif self.state != IDLE:
            self.transition_to(IDLE, "back at the heading of enable")

    def _begin(self, step, now: float, purpose: str) -> None:
        self._step = step
        self._step_purpose = purpose
        self._step_started = now
        self._next_sample = 0
        if step is None:
            if self.state == HOMING:
                self.transition_to(IDLE, "already at the heading of enable")
            return
        self._step_ends_at = now + step.duration
        self._debug("%s: base %s turn of %+.3f rad to heading %+.3f on %s.", NODE_NAME, purpose,
                    step.angle, step.target_heading, self.topic)
        self._log.write(contract.BASE_COMMAND, topic=self.topic, kind=self.kind, purpose=purpose,
                        angle=step.angle, target_heading=step.target_heading, period=step.period,
                        velocities=step.velocities)
        if self.kind == VELOCITY:
            self.tick(now)
        else:
            self._publish(step.angle)

    def _publish(self, angular_z: float) -> None:
        self._turn(float(angular_z))
