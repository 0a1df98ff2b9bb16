"""One goal of the animate action while it runs (README: "The animate action"): when it started, how long it lasts,
and whether it is ending. The supervisor (core/supervisor.py) decides with it; the front-end's action server ends
the goals and publishes their feedback."""
from typing import Callable, Optional, Tuple

from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.live_settings import goal_overrides
from cssr_system.motion.planners import HOME_GESTURE_DURATION, SETTLE_TIME

FEEDBACK_PERIOD = 1.0  # s between feedback messages
# The parts start home this long before a goal's duration ends, so that they are at their centres when it does:
# the shortest return to the centre and its hold.
HOME_LEAD = HOME_GESTURE_DURATION + SETTLE_TIME
LONGEST_HOMING = 3.0  # s after the duration: the goal succeeds even if a part is not back (a lost result, say)
DURATION_ELAPSED, CANCELLED, REPLACED, DISABLED = "duration elapsed", "cancelled", "replaced", "disabled"
GoalRefused = (ValueError, ConfigurationError)  # what `checked_goal` raises for a goal to reject


def checked_goal(goal, configure: Callable[[dict], tuple]) -> Tuple[tuple, float]:
    """An animate goal (either front-end's message: the same fields) checked before it is accepted:
    (`configure(overrides)`'s (configuration file, configuration, topics) with the goal's settings over the node's,
    its duration). Raises one of `GoalRefused`, naming what is wrong."""
    overrides = goal_overrides(list(goal.parts), goal.style, goal.intensity, goal.tempo)
    if not goal.duration >= 0.0:
        raise ValueError("duration %r: expected a number of seconds >= 0" % goal.duration)
    return configure(overrides), float(goal.duration)


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
