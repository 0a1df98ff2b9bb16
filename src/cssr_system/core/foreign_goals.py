"""Other action clients' goals on our controllers, from each controller's status list (README: "Sharing the robot").

An action server publishes the states of every client's goals, at each change and a few times a second (ROS 1:
``<action>/status``; ROS 2: ``<action>/_action/status``). Each front-end's watch hands every list here as (goal id,
running) pairs of the goals that are not ours; the supervisor is told when one is first seen running and when it
ends (a terminal state, or gone from the list)."""
import threading
from collections import defaultdict
from typing import Callable, Dict, Iterable, Set, Tuple

from cssr_system.core.events import ForeignGoal, ForeignResult


class ForeignGoals:
    """`post`: the supervisor's queue. Safe from any thread."""

    def __init__(self, post: Callable[[object], None]) -> None:
        self._post = post
        self._running: Dict[str, Set[str]] = defaultdict(set)  # per action: other clients' goals seen running
        self._lock = threading.Lock()

    def status_list(self, action: str, goals: Iterable[Tuple[str, bool]], caller_of: Callable[[str], str]) -> None:
        """One status list of `action`'s server: (goal id, running) of each goal not ours; `caller_of(goal id)`
        names the client of a goal first seen running."""
        listed = set()
        with self._lock:
            running = self._running[action]
            for goal_id, is_running in goals:
                listed.add(goal_id)
                if is_running and goal_id not in running:
                    running.add(goal_id)
                    self._post(ForeignGoal(action, goal_id, caller_of(goal_id), None))
                elif not is_running and goal_id in running:
                    running.discard(goal_id)
                    self._post(ForeignResult(action, goal_id))
            for goal_id in running - listed:
                running.discard(goal_id)
                self._post(ForeignResult(action, goal_id))
