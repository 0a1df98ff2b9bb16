"""Events posted to the supervisor's queue by the service, actionlib's callbacks, the watcher and signals.
"""
import threading
from typing import Dict, FrozenSet, NamedTuple, Optional, Tuple

from cssr_system.animate_behaviour.configuration import Configuration


class Enable(NamedTuple):
    config_file: str
    config: Configuration
    topics: Dict[str, str]
    done: threading.Event


class Disable(NamedTuple):
    reason: str  # core/session.py's DISABLED, or STOPPED (the successor's stop service)
    done: threading.Event
    by: str = "setActivation"  # who asked


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


class ControllerLost(NamedTuple):
    part: str
    action: str


class Shutdown(NamedTuple):
    reason: str
    done: threading.Event


class ForeignGoal(NamedTuple):
    """Another node's goal on a controller's action, first seen running on <action>/status."""
    action: str
    goal_id: str
    caller: str
    last_point_at: Optional[float]  # when its last point passes, if known; else its end is its result


class ForeignResult(NamedTuple):
    """Another node's goal ended (a terminal state on <action>/status, or gone from it)."""
    action: str
    goal_id: str


class ForeignCommand(NamedTuple):
    """Another node's trajectory on a controller's command topic."""
    action: str
    caller: str
    last_point_at: float


class ForeignJointAngles(NamedTuple):
    """Another node's setAngles call on naoqi_driver's JointAngles topic, naming joints of our parts."""
    topic: str
    caller: str
    joints: Tuple[str, ...]  # the joints of our parts it names
    last_point_at: float  # when its slowest joint arrives


class ForeignTwist(NamedTuple):
    """Another node's Twist on the Wheels topic."""
    topic: str
    caller: str
    twist: object  # geometry_msgs/Twist


class Reconfigure(NamedTuple):
    """Live settings changed (README: "Live settings"): the configuration they make, validated."""
    config_file: str
    config: Configuration
    topics: Dict[str, str]
    by: str  # who asked: "dynamic_reconfigure", ...
    changed: Optional[FrozenSet[str]] = None  # the keys the change sets (None: every live key that differs)


class AnimateGoal(NamedTuple):
    """A goal of the animate action, accepted by the action server's callback once its settings are valid."""
    handle: object  # actionlib ServerGoalHandle
    config_file: str
    config: Configuration
    topics: Dict[str, str]
    duration: float  # s; 0: until cancelled
    by: str  # the caller id of the client
    server: object = None  # the action server it came from (None: the node's own animate action)
    home: bool = False  # every part back to its centre, then the goal succeeds
    sets_mode: bool = False  # the goal names a mode (else the mode setting in force stays)


class ConversationHeard(NamedTuple):
    """A message of a source of the conversation (README: "Modes"): whether the robot speaks (or listens), as it
    says (a Bool topic's data; an action's status: a goal running)."""
    source: str  # its configuration key: speakingTopic, listeningTopic, speakingAction or listeningAction
    active: bool


class ConversationPresent(NamedTuple):
    """A source of the conversation still has a publisher: a sign of life."""
    source: str


class AnimateCancel(NamedTuple):
    """A client asked to cancel a goal of the animate action."""
    handle: object
