"""Events posted to the supervisor's queue by the service, actionlib's callbacks, the watcher and signals.
"""
import threading
from typing import Dict, NamedTuple, Optional

from cssr_system.animate_behaviour.configuration import Configuration


class Enable(NamedTuple):
    config_file: str
    config: Configuration
    topics: Dict[str, str]
    done: threading.Event


class Disable(NamedTuple):
    reason: str
    done: threading.Event


class GoalDone(NamedTuple):
    part: str
    action: str
    goal_number: int
    state: int
    error_code: Optional[int]
    error_string: str


class ControllerConnected(NamedTuple):
    part: str
    action: str


class Shutdown(NamedTuple):
    reason: str
    done: threading.Event
