"""One goal of the animate action while it runs (README: "The animate action"): when it started, how long it lasts,
and whether it is ending. The supervisor (core/supervisor.py) decides with it; the front-end's action server ends
the goals and publishes their feedback.

A goal with a duration ends on time, every part back at its centre: in its last seconds the supervisor plans each
part's return from where the part is then, and starts it as late as that return allows (`starts_return`), so a part
far from its centre, or moving fast, starts earlier than one near it. The goal succeeds at its duration once every
part is back."""
from typing import Callable, Optional, Tuple

from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.live_settings import goal_overrides

FEEDBACK_PERIOD = 1.0  # s between feedback messages
# The last seconds of a goal in which the parts' returns are planned, every RETURN_POLL s: longer than the longest
# return the speed cap allows from anywhere in the bands (about 2.5 s), so that none starts late.
RETURN_WINDOW = 4.0  # s
RETURN_POLL = 0.05  # s
# A return's result comes this long after its last point at the latest: a control period at 12 Hz and the messages.
RESULT_MARGIN = 0.1  # s
LONGEST_HOMING = 3.0  # s after the duration: the goal succeeds even if a part is not back (a lost result, say)
DURATION_ELAPSED, CANCELLED, REPLACED, DISABLED, STOPPED, HOMED = (
    "duration elapsed", "cancelled", "replaced", "disabled", "stopped", "at the centre")
GoalRefused = (ValueError, ConfigurationError)  # what `checked_goal` raises for a goal to reject


def checked_goal(goal, configure: Callable[[dict], tuple]) -> Tuple[tuple, float]:
    """An animate goal (either front-end's message: the same fields) checked before it is accepted:
    (`configure(overrides)`'s (configuration file, configuration, topics) with the goal's settings over the node's,
    its duration). Raises one of `GoalRefused`, naming what is wrong."""
    overrides = goal_overrides(list(goal.parts), goal.style, goal.intensity, goal.tempo, goal_mode(goal))
    if not goal.duration >= 0.0:
        raise ValueError("duration %r: expected a number of seconds >= 0" % goal.duration)
    return configure(overrides), float(goal.duration)


def goal_mode(goal) -> str:
    """The mode an animate goal sets by hand ("" : it keeps the mode in force). The successor's goals have none."""
    return str(getattr(goal, "mode", "") or "").strip().lower()


def starts_return(now: float, return_duration: float, ends_at: float) -> bool:
    """Whether a return of `return_duration` s must start now to be over, its result in, when the goal ends at
    `ends_at`: the next look, RETURN_POLL s later, would be too late."""
    return now + RETURN_POLL + return_duration + RESULT_MARGIN >= ends_at


class Session:
    """One goal of the action while it runs: when it started, how long it lasts, and whether it is ending.

    `server`: the action server the goal came from (its `succeed`, `stop` and `feedback` end it and report on it);
    `by`: who sent it; `home`: a goal that only brings every part back to its centre."""

    def __init__(self, handle, started: float, duration: float, server=None, by: str = "",
                 home: bool = False, motions_before: int = 0) -> None:
        self.handle = handle
        self.started = started
        self.duration = duration  # 0: until cancelled (a home goal: until every part is back)
        self.server = server
        self.by = by
        self.home = home
        self.homing = home  # every part returns to its centre: the goal succeeds once they are back
        self.motions_before = motions_before  # the motions the streams had completed before the goal started
        self.next_feedback = started + FEEDBACK_PERIOD

    @property
    def ends_at(self) -> Optional[float]:
        """When the goal ends (None: until cancelled)."""
        return self.started + self.duration if self.duration > 0.0 or self.home else None

    def returns_due(self, now: float) -> bool:
        """In the goal's last seconds, before every part has started back: the returns are planned now."""
        return self.ends_at is not None and not self.homing and now >= self.ends_at - RETURN_WINDOW

    def succeeds(self, now: float, parts_active: bool) -> bool:
        """Every part is back and the duration is over (or the parts have taken too long)."""
        return self.homing and (not parts_active and now >= self.ends_at or now >= self.ends_at + LONGEST_HOMING)

    def feedback_due(self, now: float) -> bool:
        if now < self.next_feedback:
            return False
        self.next_feedback = now + FEEDBACK_PERIOD
        return True

    def next_deadline(self, now: float) -> Optional[float]:
        return min([self.next_feedback] + ([] if self.ends_at is None else [self._end_deadline(now)]))

    def _end_deadline(self, now: float) -> float:
        if self.returns_due(now):
            return now + RETURN_POLL
        if not self.homing:
            return self.ends_at - RETURN_WINDOW
        return self.ends_at if now < self.ends_at else self.ends_at + LONGEST_HOMING
