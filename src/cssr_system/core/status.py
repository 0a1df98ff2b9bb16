"""The node's status (README: "Status") as plain values, for either front-end's status topic and diagnostics: a row
per part and for the base, and the one-line summary that diagnostics show (OK while every part is where it should
be, WARN while a part waits: a missing controller, a retry)."""
from typing import List, Tuple

from cssr_system.animate_behaviour.topics import WHEELS_KEY

WAITING = "waiting"


def part_rows(part_streams, base_streams) -> tuple:
    """(part, controller, state, yielding_to) of each part and of the base."""
    # The controller that executes: a goal stream's action, a joint-angle stream's topic.
    parts = tuple((stream.part, stream.controller, stream.state.value, stream.yielding_to) for stream in part_streams)
    return parts + tuple((WHEELS_KEY, base.topic, base.state.value, base.yielding_to) for base in base_streams)


def part_summary(part: str, state: str, yielding_to: str) -> str:
    """``RArm animating`` or ``RArm yielding to /gestureExecution``."""
    return "%s %s" % (part, state) + (" to " + yielding_to if yielding_to else "")


def diagnostic_summary(enabled: bool, rows) -> Tuple[bool, str, List[Tuple[str, str]]]:
    """(whether a part waits, the summary line, the key-value pairs) of the node's diagnostic status."""
    waiting = any(state == WAITING for _, _, state, _ in rows)
    summary = "%s: %s" % ("enabled" if enabled else "disabled",
                          ", ".join(part_summary(part, state, caller) for part, _, state, caller in rows) or "no parts")
    values = [("enabled", str(enabled).lower())]
    values += [(part, part_summary(part, state, caller)[len(part) + 1:]) for part, _, state, caller in rows]
    return waiting, summary, values


class StatusChanges:
    """Whether the status differs from the one published last (the status topic is published at every change)."""

    def __init__(self) -> None:
        self._published = None

    def changed(self, *status) -> bool:
        if status == self._published:
            return False
        self._published = status
        return True
