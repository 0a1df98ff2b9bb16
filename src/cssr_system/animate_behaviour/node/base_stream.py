"""The base's rotation commands on the Wheels topic, as a small state machine driven by the supervisor.
"""
import enum
from typing import Optional

import rospy
from geometry_msgs.msg import Twist

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.contract import PURPOSE_ANIMATE, PURPOSE_RETURN, NODE_NAME
from cssr_system.animate_behaviour.event_log import EventLog
from cssr_system.animate_behaviour.motion.base_rotation import BaseRotationPlanner, heading_after_interruption
from cssr_system.animate_behaviour.node.foreign_motion import TWIST, ForeignMotionTracker
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.pepper.joint_table import VELOCITY, base_busy_time, wheels_command_kind


class BaseState(enum.Enum):
    IDLE = "idle"
    ROTATING = "rotating"
    YIELDING = "yielding"  # another node commands the base: no turn of ours, no return
    RETURNING = "returning"


TRANSITIONS = {
    BaseState.IDLE: {BaseState.ROTATING, BaseState.YIELDING, BaseState.RETURNING},
    BaseState.ROTATING: {BaseState.ROTATING, BaseState.YIELDING, BaseState.RETURNING, BaseState.IDLE},
    BaseState.YIELDING: {BaseState.ROTATING, BaseState.IDLE},
    BaseState.RETURNING: {BaseState.ROTATING, BaseState.YIELDING, BaseState.IDLE},
}
STATUS_OF = {BaseState.IDLE: "idle", BaseState.ROTATING: "animating", BaseState.YIELDING: "yielding",
             BaseState.RETURNING: "homing"}  # the part states of the status topic (README: "Status")


class BaseStream:
    """The base's rotation commands on the Wheels topic. Only the supervisor thread calls it.

    A step is a turn (one relative command, or a streamed velocity bump) followed by a pause. The
    robot is busy for the step's busy_time; the pause is ours and is cut short on a new enable.

    Another node's Twist on the topic pauses our turns until it has been calm for the quiet time
    (README: "Sharing the robot"), and cancels our return: the planner's heading counts our own turns only,
    so a turn of another node is never undone."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.kind = wheels_command_kind(topic)
        self.publisher = rospy.Publisher(topic, Twist, queue_size=10)
        # Written by the sending thread (as the goals are, part_stream.action_client): the zero Twist of a stop is
        # on the wire when publish returns.
        self.publisher.impl.set_queue_size(None)
        self.state = BaseState.IDLE
        self.foreign = ForeignMotionTracker()
        self.yielding_to = ""
        self._yield_started = 0.0
        self._foreign_count = 0
        self.planner: Optional[BaseRotationPlanner] = None
        self._step = None
        self._step_purpose = ""
        self._step_started = 0.0
        self._step_ends_at = 0.0
        self._next_sample = 0  # index of the next velocity sample to publish

    def start(self, config: Configuration, style, rng, now: float, log: EventLog) -> None:
        # Keep the frame of a rotation or return still under way; otherwise start from heading 0.
        keep = self.planner is not None and (self.state != BaseState.IDLE or self._step is not None)
        heading = self.planner.heading if keep else 0.0
        self.planner = BaseRotationPlanner(self.kind, config.rot_maximum_range * style.base_speed_share,
                                           config.heading_bound, rng, pause_range=style.base_pauses)
        self.planner.set_heading(heading)
        self.foreign.quiet_time = config.yield_quiet_time
        if self.state == BaseState.YIELDING:
            return
        if not self.foreign.calm(now):
            self._yield(self.foreign.caller, now, log, "enabled while another node moves the base")
            return
        self._transition_to(BaseState.ROTATING, "enabled")
        if self._step is None:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
        else:
            self._drop_pause()

    def stop(self, return_home: bool, now: float, log: EventLog) -> None:
        """Stops at once (an explicit zero on a velocity topic); then, if asked, turns back to the
        heading the base had at enable, once a relative turn under way has ended."""
        if self.state == BaseState.IDLE:
            return
        if self.state == BaseState.YIELDING:  # another node commands the base: no return now
            self.yielding_to = ""
            self._transition_to(BaseState.IDLE, "disabled while yielding; no return")
            return
        if self.kind == VELOCITY and self._step is not None:
            self._publish(0.0)
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
            self._step = None
        elif self._step is not None:
            self._drop_pause()
        if return_home and self.planner is not None:
            self._transition_to(BaseState.RETURNING, "disabled")
            if self._step is None:
                self._begin(self.planner.return_step(), now, PURPOSE_RETURN, log)
        else:
            self._transition_to(BaseState.IDLE, "disabled")

    def foreign_twist(self, caller: str, twist: Twist, now: float, log: EventLog) -> None:
        """Another node's command on the topic: our turn stops at once (nothing of ours is published)."""
        self._foreign_count += 1
        self.foreign.started("twist-%d" % self._foreign_count, caller, TWIST, now,
                             now + base_busy_time(self.kind, twist.linear.x, twist.linear.y, twist.angular.z))
        if self.state == BaseState.YIELDING:
            self.yielding_to = caller
        elif self.state in (BaseState.ROTATING, BaseState.RETURNING):
            self._interrupt()
            if self.state == BaseState.ROTATING:
                self._yield(caller, now, log, "%s commands the base" % caller)
            else:
                log.write(contract.PART_YIELDED, part=WHEELS_KEY, controller=self.topic, caller=caller, kind=TWIST)
                self._transition_to(BaseState.IDLE, "%s commands the base; our return is cancelled" % caller)

    def _interrupt(self) -> None:
        """Our step ends now: a streamed turn counts as far as it went; a relative turn the robot finishes."""
        if self._step is not None and self.kind == VELOCITY:
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
        self._step = None

    def _yield(self, caller: str, now: float, log: EventLog, why: str) -> None:
        self.yielding_to = caller
        self._yield_started = now
        log.write(contract.PART_YIELDED, part=WHEELS_KEY, controller=self.topic, caller=caller, kind=TWIST)
        self._transition_to(BaseState.YIELDING, why)

    def _transition_to(self, new_state: BaseState, why: str) -> None:
        if new_state not in TRANSITIONS[self.state]:
            raise RuntimeError("base: no transition %s -> %s (%s)" % (self.state.value, new_state.value, why))
        rospy.logdebug("%s: base: %s -> %s (%s).", NODE_NAME, self.state.value, new_state.value, why)
        self.state = new_state

    @property
    def status(self) -> str:
        return STATUS_OF[self.state]

    def _drop_pause(self) -> None:
        """The step under way ends when the robot is done with it: our pause after it is dropped."""
        self._step_ends_at = min(self._step_ends_at, self._step_started + self._step.busy_time)

    def next_deadline(self, now: float) -> Optional[float]:
        if self.state == BaseState.YIELDING:
            return self.foreign.next_deadline(now)
        if self._step is None:
            return None
        if self.kind == VELOCITY and self._next_sample < len(self._step.velocities):
            return self._step_started + self._next_sample * self._step.period
        return self._step_ends_at

    def tick(self, now: float, log: EventLog) -> None:
        if self.state == BaseState.YIELDING:
            if self.foreign.calm(now):
                log.write(contract.PART_RESUMED, part=WHEELS_KEY, controller=self.topic, caller=self.yielding_to,
                          seconds=round(now - self._yield_started, 3))
                self._transition_to(BaseState.ROTATING, "%s done, calm for %.1f s" % (self.yielding_to,
                                                                                      self.foreign.quiet_time))
                self.yielding_to = ""
                self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
            return
        step = self._step
        if step is None:
            return
        if self.kind == VELOCITY:
            while (self._next_sample < len(step.velocities)
                   and now >= self._step_started + self._next_sample * step.period):
                self._publish(step.velocities[self._next_sample])
                self._next_sample += 1
        if now < self._step_ends_at:
            return
        ended = self._step_purpose
        self._step = None
        if self.state == BaseState.ROTATING:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
        elif self.state == BaseState.RETURNING and ended != PURPOSE_RETURN:
            self._begin(self.planner.return_step(), now, PURPOSE_RETURN, log)
        elif self.state != BaseState.IDLE:
            self._transition_to(BaseState.IDLE, "back at the heading of enable")

    def _begin(self, step, now: float, purpose: str, log: EventLog) -> None:
        self._step = step
        self._step_purpose = purpose
        self._step_started = now
        self._next_sample = 0
        if step is None:
            if self.state == BaseState.RETURNING:
                self._transition_to(BaseState.IDLE, "already at the heading of enable")
            return
        self._step_ends_at = now + step.duration
        rospy.logdebug("%s: base %s turn of %+.3f rad to heading %+.3f on %s.", NODE_NAME, purpose,
                       step.angle, step.target_heading, self.topic)
        log.write(contract.BASE_COMMAND, topic=self.topic, kind=self.kind, purpose=purpose,
                  angle=step.angle, target_heading=step.target_heading, period=step.period,
                  velocities=step.velocities)
        if self.kind == VELOCITY:
            self.tick(now, log)
        else:
            self._publish(step.angle)

    def _publish(self, angular_z: float) -> None:
        twist = Twist()
        twist.angular.z = float(angular_z)
        self.publisher.publish(twist)
