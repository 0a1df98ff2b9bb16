"""When the soak's gesture leaves (doc/soak.md, "What the soak found"). A goal that reaches a controller within a few
milliseconds of the node's next goal on the same part can be replaced by it: no client sees a goal before it arrives.
The node sends a part's next goal about a second after its last one started, so a gesture sent just after one of the
node's goals has started on the arm tests the node's yield, not that race. The drivers hand the arm controller's
status lists here; a gesture that is due waits for the next goal to start there, GESTURE_WAIT s at most (when the
node is disabled no goal starts). Pure Python: no ROS.
"""
import threading
from typing import Callable, Iterable, Set

GESTURE_WAIT = 2.0  # s a due gesture waits at most for a goal to start on the arm


class GoalStarts:
    """The goals running on one action, from its server's status lists. Safe from any thread."""

    def __init__(self) -> None:
        self._running: Set[str] = set()
        self._starts = 0  # goals seen starting so far
        self._changed = threading.Condition()

    def status_list(self, running: Iterable[str]) -> None:
        """The ids of the goals that one status list shows running."""
        now_running = set(running)
        with self._changed:
            if now_running - self._running:
                self._starts += 1
                self._changed.notify_all()
            self._running = now_running

    def wait_for_start(self, timeout: float) -> bool:
        """Whether a goal not running before the call started within `timeout` s."""
        with self._changed:
            before = self._starts
            return self._changed.wait_for(lambda: self._starts > before, timeout)

    def after_next_start(self, send: Callable[[], None], timeout: float = GESTURE_WAIT) -> threading.Thread:
        """Calls `send` on a thread of its own once a goal starts, or after `timeout` s; returns at once."""
        def wait_and_send() -> None:
            self.wait_for_start(timeout)
            send()
        thread = threading.Thread(target=wait_and_send, name="gesture", daemon=True)
        thread.start()
        return thread
