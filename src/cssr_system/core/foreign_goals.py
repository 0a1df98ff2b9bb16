"""Other action clients' goals on our controllers, from each controller's status list (README: "Sharing the robot").

An action server publishes the states of every client's goals, at each change and a few times a second (ROS 1:
``<action>/status``; ROS 2: ``<action>/_action/status``). Each front-end's watch hands every list here as (goal id,
running) pairs of the goals that are not ours; the supervisor is told when one is first seen running and when it
ends (a terminal state, or gone from the list). A goal that began and ended between two lists is told as both.

The same lock guards the last look before each of our goals leaves (`send_unless_foreign`): a list handed over
while a goal of ours is being sent waits until it has left, and one handed over before is in the look.
"""
import threading
from collections import defaultdict
from typing import Callable, Dict, Iterable, Optional, Set, Tuple

from cssr_system.core.events import ForeignGoal, ForeignResult


class ForeignGoals:
    """`post`: the supervisor's queue. Safe from any thread."""

    def __init__(self, post: Callable[[object], None]) -> None:
        self._post = post
        self._running: Dict[str, Set[str]] = defaultdict(set)  # per action: other clients' goals seen running
        self._listed: Dict[str, Set[str]] = {}  # per action: other clients' goals in its latest list
        self._started: Dict[str, int] = defaultdict(int)  # per action: other clients' goals told so far
        self._latest: Dict[str, str] = {}  # per action: the latest of them
        self._lock = threading.Lock()

    def status_list(self, action: str, goals: Iterable[Tuple[str, bool]], caller_of: Callable[[str], str]) -> None:
        """One status list of `action`'s server: (goal id, running) of each goal not ours; `caller_of(goal id)`
        names the client of a goal first seen running."""
        listed = set()
        with self._lock:
            running = self._running[action]
            before = self._listed.get(action)  # None: the first list, whose ended goals are old news
            for goal_id, is_running in goals:
                listed.add(goal_id)
                if is_running and goal_id not in running:
                    running.add(goal_id)
                    self._tell_started(action, goal_id, caller_of)
                elif not is_running and goal_id in running:
                    running.discard(goal_id)
                    self._post(ForeignResult(action, goal_id))
                elif not is_running and before is not None and goal_id not in before:
                    self._tell_started(action, goal_id, caller_of)  # it moved the part all the same
                    self._post(ForeignResult(action, goal_id))
            for goal_id in running - listed:
                running.discard(goal_id)
                self._post(ForeignResult(action, goal_id))
            self._listed[action] = listed

    def _tell_started(self, action: str, goal_id: str, caller_of: Callable[[str], str]) -> None:
        self._started[action] += 1
        self._latest[action] = goal_id
        self._post(ForeignGoal(action, goal_id, caller_of(goal_id), None))

    def started(self, action: str) -> int:
        """How many other clients' goals on `action` have been told so far: a send handed over to another thread
        notes it, and its last look withholds the goal if one came since."""
        with self._lock:
            return self._started[action]

    def send_unless_foreign(self, action: str, send: Callable[[], None], since: Optional[int] = None
                            ) -> Optional[str]:
        """The last look before a goal of ours leaves for `action`: calls `send` unless, in the latest status list,
        another client's goal runs there, or one was told after `since` (`started` when the send was decided);
        then returns that goal's id and sends nothing (its ForeignGoal is on the supervisor's queue already, and
        makes the part yield). None: sent."""
        with self._lock:
            running = sorted(self._running[action])
            if running:
                return running[0]
            if since is not None and self._started[action] > since:
                return self._latest[action]
            send()
            return None
