"""The ROS 2 successor system's animate behaviour action, `/animate_behavior` (dec_interfaces/action/AnimateBehavior),
and its stop service (README: "With the successor's behaviour tree"): what its goals ask of the node, and what its
feedback and results say. Pure Python: ros2/successor_action.py serves them.

A goal's `behavior_type` chooses what moves, as the `behaviour` key and the part switches do; its `selected_range`
is the `selectedRange` key for that goal; "home" brings every part back to its centre, then succeeds."""
import math
from typing import Callable, Dict, Iterable, NamedTuple, Tuple

from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.core.session import CANCELLED, DISABLED, DURATION_ELAPSED, HOMED, REPLACED, STOPPED

HOME = "home"
# Each behavior_type (in any letter case) as configuration overrides: the behaviour, and the part switches that the
# status's moving_parts shows; "home" has none of its own.
BEHAVIOUR_TYPES: Dict[str, Dict[str, object]] = {
    "all": {"behaviour": "all", "moveArms": True, "moveHands": True, "moveLeg": True, "turnBase": True},
    "body": {"behaviour": "body", "moveArms": True, "moveHands": True, "moveLeg": True, "turnBase": False},
    "hands": {"behaviour": "hands", "moveArms": True, "moveHands": True, "moveLeg": False, "turnBase": False},
    "arms": {"behaviour": "body", "moveArms": True, "moveHands": False, "moveLeg": False, "turnBase": False},
    "rotation": {"behaviour": "rotation", "moveArms": False, "moveHands": False, "moveLeg": False, "turnBase": True},
    HOME: {},
}
ACCEPTED_TYPES = ("All", "body", "hands", "arms", "rotation", HOME)
# The feedback's names of the parts (`current_limb`), in the order it lists them.
PART_NAMES = (("RArm", "right arm"), ("LArm", "left arm"), ("RHand", "right hand"), ("LHand", "left hand"),
              ("Leg", "leg"), (WHEELS_KEY, "base"))
MOVING_STATES = ("animating", "homing")


class SuccessorGoal(NamedTuple):
    """A goal checked and made into the node's terms."""
    configured: tuple  # `configure(overrides)`'s (configuration file, configuration, topics)
    duration: float  # s; 0: until cancelled or stopped (a home goal: until every part is back)
    home: bool


def successor_overrides(behavior_type: str, selected_range: float) -> Dict[str, object]:
    """The configuration overrides of a goal's two settings. Raises ValueError naming what is wrong."""
    overrides = BEHAVIOUR_TYPES.get(behavior_type.strip().lower())
    if overrides is None:
        raise ValueError("behavior_type %r: expected one of %s" % (behavior_type, ", ".join(ACCEPTED_TYPES)))
    if not (math.isfinite(selected_range) and 0.0 <= selected_range <= 1.0):
        raise ValueError("selected_range %r: expected a number in [0, 1]" % selected_range)
    return dict(overrides, selectedRange=float(selected_range))


def checked_successor_goal(goal, configure: Callable[[dict], tuple]) -> SuccessorGoal:
    """A goal (`behavior_type`, `selected_range`, `duration_seconds`) checked before it is accepted. Raises
    ValueError or ConfigurationError (core/session.py's GoalRefused), naming what is wrong."""
    overrides = successor_overrides(goal.behavior_type, goal.selected_range)
    if goal.duration_seconds < 0:
        raise ValueError("duration_seconds %d: expected 0 (until cancelled) or more" % goal.duration_seconds)
    return SuccessorGoal(configure(overrides), float(goal.duration_seconds), goal.behavior_type.strip().lower() == HOME)


def moving_parts(rows: Iterable[tuple]) -> str:
    """The feedback's `current_limb`: the parts moving now (animating or returning), as "right arm, leg, base";
    `rows`: core.status.part_rows."""
    moving = {part for part, _, state, _ in rows if state in MOVING_STATES}
    return ", ".join(name for part, name in PART_NAMES if part in moving)


# How each end reads in the result: (success, message). A goal the stop service ends succeeds, as the successor's
# own node has it, so that a tree step running it in parallel does not fail; a cancel, a newer goal and a disable
# end it with success false.
RESULTS: Dict[str, Tuple[bool, str]] = {
    DURATION_ELAPSED: (True, "completed: the duration elapsed, every part back at its centre"),
    HOMED: (True, "completed: every part back at its centre"),
    STOPPED: (True, "stopped by the stop service"),
    CANCELLED: (False, "cancelled"),
    REPLACED: (False, "replaced by a newer goal or an enable"),
    DISABLED: (False, "disabled"),
}


def result_of(reason: str) -> Tuple[bool, str]:
    return RESULTS.get(reason, (False, reason))
