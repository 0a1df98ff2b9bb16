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
from cssr_system.pepper.joint_table import VELOCITY, wheels_command_kind


class BaseState(enum.Enum):
    IDLE = "idle"
    ROTATING = "rotating"
    RETURNING = "returning"


class BaseStream:
    """The base's rotation commands on the Wheels topic. Only the supervisor thread calls it.

    A step is a turn (one relative command, or a streamed velocity bump) followed by a pause. The
    robot is busy for the step's busy_time; the pause is ours and is cut short on a new enable."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.kind = wheels_command_kind(topic)
        self.publisher = rospy.Publisher(topic, Twist, queue_size=10)
        self.state = BaseState.IDLE
        self.planner: Optional[BaseRotationPlanner] = None
        self._step = None
        self._step_purpose = ""
        self._step_started = 0.0
        self._step_ends_at = 0.0
        self._next_sample = 0  # index of the next velocity sample to publish

    def start(self, config: Configuration, rng, now: float, log: EventLog) -> None:
        # Keep the frame of a rotation or return still under way; otherwise start from heading 0.
        keep = self.planner is not None and (self.state != BaseState.IDLE or self._step is not None)
        heading = self.planner.heading if keep else 0.0
        self.planner = BaseRotationPlanner(self.kind, config.rot_maximum_range, config.heading_bound, rng)
        self.planner.set_heading(heading)
        self.state = BaseState.ROTATING
        if self._step is None:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
        else:
            self._drop_pause()

    def stop(self, return_home: bool, now: float, log: EventLog) -> None:
        """Stops at once (an explicit zero on a velocity topic); then, if asked, turns back to the
        heading the base had at enable, once a relative turn under way has ended."""
        if self.state == BaseState.IDLE:
            return
        if self.kind == VELOCITY and self._step is not None:
            self._publish(0.0)
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
            self._step = None
        elif self._step is not None:
            self._drop_pause()
        self.state = BaseState.IDLE
        if return_home and self.planner is not None:
            self.state = BaseState.RETURNING
            if self._step is None:
                self._begin(self.planner.return_step(), now, PURPOSE_RETURN, log)

    def _drop_pause(self) -> None:
        """The step under way ends when the robot is done with it: our pause after it is dropped."""
        self._step_ends_at = min(self._step_ends_at, self._step_started + self._step.busy_time)

    def next_deadline(self) -> Optional[float]:
        if self._step is None:
            return None
        if self.kind == VELOCITY and self._next_sample < len(self._step.velocities):
            return self._step_started + self._next_sample * self._step.period
        return self._step_ends_at

    def tick(self, now: float, log: EventLog) -> None:
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
        else:
            self.state = BaseState.IDLE

    def _begin(self, step, now: float, purpose: str, log: EventLog) -> None:
        self._step = step
        self._step_purpose = purpose
        self._step_started = now
        self._next_sample = 0
        if step is None:
            if self.state == BaseState.RETURNING:
                self.state = BaseState.IDLE
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
