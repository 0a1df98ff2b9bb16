"""The node's status (README: "Status"): the latched status topic, published at every change, and the same as ROS
diagnostics: one DiagnosticStatus named after the node, OK while every part is where it should be, WARN while a
part waits (a missing controller, a retry)."""
from typing import List, Optional

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.contract import DIAGNOSTICS_TOPIC, NODE_NAME, STATUS_TOPIC
from cssr_system.animate_behaviour.core.motion_stream import part_rows
from cssr_system.animate_behaviour.live_settings import moving_parts
from cssr_system.msg import AnimateBehaviourStatus, PartStatus


def part_statuses(rows) -> List[PartStatus]:
    """The `part_rows` as messages (the status topic's and the animate action's feedback's `parts`)."""
    return [PartStatus(part=part, controller=controller, state=state, yielding_to=caller)
            for part, controller, state, caller in rows]


class StatusPublisher:
    def __init__(self) -> None:
        self._status = rospy.Publisher(STATUS_TOPIC, AnimateBehaviourStatus, queue_size=1, latch=True)
        self._diagnostics = rospy.Publisher(DIAGNOSTICS_TOPIC, DiagnosticArray, queue_size=1)
        self._published = None

    def publish(self, enabled: bool, part_streams, base_streams, settings: Optional[Configuration] = None,
                by: str = "") -> None:
        """Publishes when anything changed since the last time. `settings`: the configuration in force."""
        rows = part_rows(part_streams, base_streams)
        if (enabled, rows, settings, by) == self._published:
            return
        self._published = (enabled, rows, settings, by)
        message = AnimateBehaviourStatus(enabled=enabled, settings_by=by, parts=part_statuses(rows))
        if settings is not None:
            message.intensity, message.tempo = settings.intensity, settings.breaths_per_minute
            message.motion_style, message.moving_parts = settings.motion_style, moving_parts(settings)
        message.header.stamp = rospy.Time.now()
        self._status.publish(message)
        self._diagnostics.publish(status_diagnostics(message))


def part_summary(part) -> str:
    """``RArm animating`` or ``RArm yielding to /gestureExecution``."""
    text = "%s %s" % (part.part, part.state)
    return text + (" to " + part.yielding_to if part.yielding_to else "")


def status_diagnostics(status) -> DiagnosticArray:
    """A DiagnosticArray from an AnimateBehaviourStatus message."""
    waiting = [part.part for part in status.parts if part.state == "waiting"]
    level = DiagnosticStatus.WARN if waiting else DiagnosticStatus.OK
    summary = "%s: %s" % ("enabled" if status.enabled else "disabled",
                          ", ".join(part_summary(part) for part in status.parts) or "no parts")
    values = [KeyValue(key="enabled", value=str(status.enabled).lower())]
    values += [KeyValue(key=part.part, value=part_summary(part)[len(part.part) + 1:]) for part in status.parts]
    array = DiagnosticArray()
    array.header = status.header
    array.status = [DiagnosticStatus(level=level, name=NODE_NAME, message=summary, hardware_id="pepper",
                                     values=values)]
    return array
