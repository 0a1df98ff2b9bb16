"""Something done every so often by a loop that wakes more often anyway (a program's main loop): no timer thread."""
from typing import Callable


class Periodic:
    """`tick()` from the loop does `action()` once `period` s have passed since the last time (once, however long the
    loop's wait was). `clock`: seconds, monotonic; the first time is a period after the start."""

    def __init__(self, clock: Callable[[], float], period: float, action: Callable[[], None]) -> None:
        self._clock = clock
        self._period = period
        self._action = action
        self._due = clock() + period

    def tick(self) -> None:
        now = self._clock()
        if now >= self._due:
            self._due = now + self._period
            self._action()
