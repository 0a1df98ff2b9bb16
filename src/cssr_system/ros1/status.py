"""The node's status on ROS 1 (README: "Status"): the latched status topic, published at every change, and the same
as ROS diagnostics: one DiagnosticStatus named after the node (core/status.py says what they hold)."""
from typing import List, Optional

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.contract import DIAGNOSTICS_TOPIC, NODE_NAME, STATUS_TOPIC
from cssr_system.animate_behaviour.live_settings import moving_parts
from cssr_system.core.status import StatusChanges, diagnostic_summary, part_rows
from cssr_system.msg import AnimateBehaviourStatus, PartStatus


def part_statuses(rows) -> List[PartStatus]:
    """The `part_rows` as messages (the status topic's and the animate action's feedback's `parts`)."""
    return [PartStatus(part=part, controller=controller, state=state, yielding_to=caller)
            for part, controller, state, caller in rows]


class StatusPublisher:
    def __init__(self) -> None:
        self._status = rospy.Publisher(STATUS_TOPIC, AnimateBehaviourStatus, queue_size=1, latch=True)
        self._diagnostics = rospy.Publisher(DIAGNOSTICS_TOPIC, DiagnosticArray, queue_size=1)
        self._changes = StatusChanges()

    def publish(self, enabled: bool, part_streams, base_streams, settings: Optional[Configuration] = None,
                by: str = "") -> None:
        """Publishes when anything changed since the last time. `settings`: the configuration in force."""
        rows = part_rows(part_streams, base_streams)
        if not self._changes.changed(enabled, rows, settings, by):
            return
        message = AnimateBehaviourStatus(enabled=enabled, settings_by=by, parts=part_statuses(rows))
        if settings is not None:
            message.intensity, message.tempo = settings.intensity, settings.breaths_per_minute
            message.motion_style, message.moving_parts = settings.motion_style, moving_parts(settings)
        message.header.stamp = rospy.Time.now()
        self._status.publish(message)
        self._diagnostics.publish(status_diagnostics(enabled, rows, message.header))


def status_diagnostics(enabled: bool, rows, header) -> DiagnosticArray:
    waiting, summary, values = diagnostic_summary(enabled, rows)
    array = DiagnosticArray(header=header)
    array.status = [DiagnosticStatus(level=DiagnosticStatus.WARN if waiting else DiagnosticStatus.OK, name=NODE_NAME,
                                     message=summary, hardware_id="pepper",
                                     values=[KeyValue(key=key, value=value) for key, value in values])]
    return array
