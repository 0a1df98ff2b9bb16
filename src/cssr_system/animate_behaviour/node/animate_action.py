"""The animate action (README: "The animate action"): `/animateBehaviour/animate`, a behaviour tree's way to keep
the robot alive for a while, or until cancelled, with given settings.

`AnimateActionServer` owns the actionlib server: its callbacks validate a goal's settings (a goal that asks for an
unusable configuration is rejected with the reason) and post events to the supervisor, which decides everything
else through `Session`. Only the supervisor thread ends goals and publishes feedback.
"""
from typing import Callable, Optional

import actionlib
import rospy

from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.contract import ANIMATE_ACTION_NAME, NODE_NAME
from cssr_system.animate_behaviour.live_settings import goal_overrides
from cssr_system.animate_behaviour.motion.planners import HOME_GESTURE_DURATION, SETTLE_TIME
from cssr_system.animate_behaviour.node.events import AnimateCancel, AnimateGoal
from cssr_system.animate_behaviour.rospy_compat import caller_of_goal
from cssr_system.msg import AnimateAction, AnimateFeedback, AnimateResult

FEEDBACK_PERIOD = 1.0  # s between feedback messages
STATUS_FREQUENCY = 1.0  # Hz of the action's status between changes
# The parts start home this long before a goal's duration ends, so that they are at their centres when it does:
# the shortest return to the centre and its hold.
HOME_LEAD = HOME_GESTURE_DURATION + SETTLE_TIME
LONGEST_HOMING = 3.0  # s after the duration: the goal succeeds even if a part is not back (a lost result, say)
DURATION_ELAPSED, CANCELLED, REPLACED, DISABLED = "duration elapsed", "cancelled", "replaced", "disabled"


class Session:
    """One goal of the action while it runs: when it started, how long it lasts, and whether it is ending."""

    def __init__(self, handle, started: float, duration: float) -> None:
        self.handle = handle
        self.started = started
        self.duration = duration  # 0: until cancelled
        self.homing = False  # the duration is over: the parts return to their centres
        self.next_feedback = started + FEEDBACK_PERIOD

    def home_due(self, now: float) -> bool:
        return self.duration > 0.0 and not self.homing and now >= self.started + self.duration - HOME_LEAD

    def succeeds(self, now: float, parts_active: bool) -> bool:
        """Homing is done (or has taken too long)."""
        return self.homing and (not parts_active or now >= self.started + self.duration + LONGEST_HOMING)

    def feedback_due(self, now: float) -> bool:
        if now < self.next_feedback:
            return False
        self.next_feedback = now + FEEDBACK_PERIOD
        return True

    def next_deadline(self) -> Optional[float]:
        deadlines = [self.next_feedback]
        if self.duration > 0.0 and not self.homing:
            deadlines.append(self.started + self.duration - HOME_LEAD)
        return min(deadlines)


class AnimateActionServer:
    """The actionlib server of the animate action. `configure(overrides)` gives (configuration file, configuration,
    topics) with the goal's settings on top of the node's, or raises ConfigurationError; `post` puts an event on
    the supervisor's queue."""

    def __init__(self, configure: Callable[[dict], tuple], post: Callable[[object], None]) -> None:
        self._configure = configure
        self._post = post
        # The goals' status is published at every change; between changes once a second is enough (actionlib's
        # default, 5 Hz, would cost the node CPU for nothing).
        rospy.set_param(rospy.resolve_name(ANIMATE_ACTION_NAME) + "/status_frequency", STATUS_FREQUENCY)
        self._server = actionlib.ActionServer(ANIMATE_ACTION_NAME, AnimateAction, goal_cb=self._on_goal,
                                              cancel_cb=self._on_cancel, auto_start=False)

    def start(self) -> None:
        self._server.start()

    def _on_goal(self, handle) -> None:
        goal = handle.get_goal()
        try:
            overrides = goal_overrides(goal.parts, goal.base_rotation, goal.style, goal.intensity, goal.tempo)
            if not goal.duration >= 0.0:
                raise ValueError("duration %r: expected a number of seconds >= 0" % goal.duration)
            config_file, config, topics = self._configure(overrides)
        except (ValueError, ConfigurationError) as error:
            rospy.logwarn("%s: animate goal rejected: %s", NODE_NAME, error)
            handle.set_rejected(AnimateResult(reason="rejected: %s" % error), str(error))
            return
        by = caller_of_goal(handle.get_goal_id().id)
        self._post(AnimateGoal(handle, config_file, config, topics, float(goal.duration), by))

    def _on_cancel(self, handle) -> None:
        self._post(AnimateCancel(handle))

    @staticmethod
    def accept(handle) -> None:
        handle.set_accepted()

    @staticmethod
    def succeed(handle, animated: float, reason: str) -> None:
        handle.set_succeeded(AnimateResult(animated=animated, reason=reason), reason)

    @staticmethod
    def stop(handle, animated: float, reason: str) -> None:
        """A goal that ends before its duration: PREEMPTED (or RECALLED before it started), with the reason."""
        handle.set_canceled(AnimateResult(animated=animated, reason=reason), reason)

    @staticmethod
    def feedback(handle, elapsed: float, parts) -> None:
        handle.publish_feedback(AnimateFeedback(elapsed=elapsed, parts=parts))
