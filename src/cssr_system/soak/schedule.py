"""The churn of a soak (doc/soak.md): what a day on the robot does to the node, compressed. `churn_schedule` gives
every step at its time from the start, drawn from a seeded random generator, so a run can be repeated:
- enabled and disabled spells of 15 to 30 s each, through setActivation;
- a live setting every 10 s, in turn intensity, tempo, style and the parts switches;
- in every disabled spell an animate goal: with a duration (it succeeds), until cancelled (cancelled after 4 s) or
  replaced after 3 s by one with a duration (the first ends "replaced", the second succeeds);
- another node's gesture on the right arm every minute, at a random moment of that minute that ignores the node's
  goals and the live settings (it succeeds: the node yields, and withholds a goal it would send meanwhile);
- the simulated Pepper restarted every 10 minutes (its controllers leave and come back), with no animate goal or
  gesture within 15 s of it, so that every one of them has one expected end;
- the base's listener gone for 30 s every 10 minutes, on its own, half-way between two restarts.
Pure Python: no ROS.
"""
import random
from typing import Dict, List, NamedTuple, Tuple

ENABLE, DISABLE, SETTING, ANIMATE, CANCEL, GESTURE, RESTART, LISTENER = (
    "enable", "disable", "setting", "animate", "cancel", "gesture", "restart", "listener")
SUCCEEDED_REASON, CANCELLED_REASON, REPLACED_REASON = "duration elapsed", "cancelled", "replaced"
SPELL = (15.0, 30.0)  # s of each enabled or disabled spell
SETTING_PERIOD = 10.0  # s between live settings
GESTURE_PERIOD = 60.0  # s: one gesture of another node at a random moment of each such period
RESTART_PERIOD = 600.0  # s between restarts of the simulated Pepper; the first at half of it
CLEARANCE = 15.0  # s kept between a restart and any animate goal or gesture
LISTENER_AWAY = 30.0  # s the base's listener stays away
ANIMATE_SPAN = 12.0  # s from an animate goal's start to the end of its last goal, at most
ANIMATE_DURATION = 4.0  # s of an animate goal with a duration
# The live settings in turn, by dynamic_reconfigure's names (animate_behaviour.live_settings.SETTING_KEYS).
SETTINGS: Tuple[Tuple[str, object], ...] = (
    ("intensity", 0.4), ("tempo", 16.0), ("style", "breathing"), ("base", False), ("intensity", 1.0),
    ("hands", False), ("tempo", 10.0), ("style", "random"), ("hands", True), ("leg", False), ("intensity", 0.7),
    ("base", True), ("leg", True), ("tempo", 12.0))
ANIMATE_KINDS = ("duration", "cancelled", "replaced")


class Step(NamedTuple):
    at: float  # s from the start of the run
    action: str
    detail: Dict[str, object]


def _spells(seconds: float, rng: random.Random) -> List[Tuple[float, float, bool]]:
    """(start, end, enabled) of each spell, from 2 s on, alternating and beginning with an enabled one."""
    spells, at, enabled = [], 2.0, True
    while at < seconds:
        length = rng.uniform(*SPELL)
        spells.append((at, min(at + length, seconds), enabled))
        at, enabled = at + length, not enabled
    return spells


def restart_times(seconds: float, period: float = RESTART_PERIOD) -> List[float]:
    times, at = [], period / 2.0
    while at < seconds:
        times.append(at)
        at += period
    return times


def _clear_of(start: float, end: float, restarts: List[float]) -> bool:
    return all(end + CLEARANCE <= restart or start >= restart + CLEARANCE for restart in restarts)


def _animate_steps(start: float, number: int, kind: str) -> List[Step]:
    """The steps of one animate goal (two for `replaced`) beginning at `start`; each goal's detail names its
    expected end (`expect`: the result's reason)."""
    name = "animate-%d" % number
    if kind == "duration":
        return [Step(start, ANIMATE, {"goal": name, "duration": ANIMATE_DURATION, "intensity": 0.8, "parts": [],
                                      "expect": SUCCEEDED_REASON})]
    if kind == "cancelled":
        return [Step(start, ANIMATE, {"goal": name, "duration": 0.0, "intensity": 0.6, "parts": ["arms", "leg"],
                                      "expect": CANCELLED_REASON}),
                Step(start + 4.0, CANCEL, {"goal": name})]
    return [Step(start, ANIMATE, {"goal": name, "duration": 0.0, "intensity": 1.0, "parts": [],
                                  "expect": REPLACED_REASON}),
            Step(start + 3.0, ANIMATE, {"goal": name + "b", "duration": ANIMATE_DURATION, "intensity": 0.5,
                                        "parts": ["arms"], "expect": SUCCEEDED_REASON})]


def _listener_steps(seconds: float, restart_period: float) -> List[Step]:
    """The base's listener leaving and coming back on its own, every `restart_period` s from the first, half-way
    between two restarts of the simulated Pepper (whose own listener the drivers keep off the base's topic)."""
    steps, at = [], restart_period
    while at + LISTENER_AWAY < seconds:
        steps += [Step(at, LISTENER, {"present": False}), Step(at + LISTENER_AWAY, LISTENER, {"present": True})]
        at += restart_period
    return steps


def churn_schedule(seconds: float, seed: int = 1, restart_period: float = RESTART_PERIOD) -> List[Step]:
    """Every step of a run of `seconds`, in time order (the simulated Pepper restarted every `restart_period` s)."""
    rng = random.Random(seed)
    restarts = restart_times(seconds, restart_period)
    steps = [Step(at, RESTART, {}) for at in restarts]
    animated = 0
    for start, end, enabled in _spells(seconds, rng):
        steps.append(Step(start, ENABLE if enabled else DISABLE, {}))
        goal_start = start + 2.0
        if not enabled and goal_start + ANIMATE_SPAN <= end and _clear_of(goal_start, goal_start + ANIMATE_SPAN,
                                                                          restarts):
            steps += _animate_steps(goal_start, animated, ANIMATE_KINDS[animated % len(ANIMATE_KINDS)])
            animated += 1
    at, index = SETTING_PERIOD, 0
    while at < seconds:
        name, value = SETTINGS[index % len(SETTINGS)]
        steps.append(Step(at, SETTING, {"name": name, "value": value}))
        at, index = at + SETTING_PERIOD, index + 1
    steps += _listener_steps(seconds, restart_period)
    minute = 0.0
    while minute < seconds:
        at = minute + rng.uniform(0.0, GESTURE_PERIOD)
        if at < seconds and _clear_of(at, at + ANIMATE_SPAN, restarts):
            steps.append(Step(at, GESTURE, {"goal": "gesture-%d" % sum(step.action == GESTURE for step in steps)}))
        minute += GESTURE_PERIOD
    return sorted(steps, key=lambda step: step.at)
