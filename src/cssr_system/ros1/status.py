"""The node's status on ROS 1 (README: "Status"): the latched status topic, published at every change, and the same
as ROS diagnostics: one DiagnosticStatus named after the node's resolved name, whose hardware id is the robot's
namespace (core/status.py says what they hold)."""
from typing import List, Optional

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.contract import DIAGNOSTICS_TOPIC, STATUS, robot_of
from cssr_system.animate_behaviour.live_settings import moving_parts
from cssr_system.core.status import StatusChanges, diagnostic_summary, part_rows
from cssr_system.msg import AnimateBehaviourStatus, PartStatus


def part_statuses(rows) -> List[PartStatus]:
    """The `part_rows` as messages (the status topic's and the animate action's feedback's `parts`)."""
    return [PartStatus(part=part, controller=controller, state=state, yielding_to=caller)
            for part, controller, state, caller in rows]


class StatusPublisher:
    def __init__(self) -> None:
        self._status = rospy.Publisher("~" + STATUS, AnimateBehaviourStatus, queue_size=1, latch=True)
        self._diagnostics = rospy.Publisher(DIAGNOSTICS_TOPIC, DiagnosticArray, queue_size=1)
        self._changes = StatusChanges()

    def publish(self, enabled: bool, part_streams, base_streams, settings: Optional[Configuration] = None,
                by: str = "", mode: str = "", mode_by: str = "") -> None:
        """Publishes when anything changed since the last time. `settings`: the configuration in force; `mode`: the
        mode in force, set by `mode_by`."""
        rows = part_rows(part_streams, base_streams)
        if not self._changes.changed(enabled, rows, settings, by, mode, mode_by):
            return
        message = AnimateBehaviourStatus(enabled=enabled, settings_by=by, parts=part_statuses(rows), mode=mode,
                                         mode_by=mode_by)
        if settings is not None:
            message.intensity, message.tempo = settings.intensity, settings.breaths_per_minute
            message.motion_style, message.moving_parts = settings.motion_style, moving_parts(settings)
        message.header.stamp = rospy.Time.now()
        self._status.publish(message)
        self._diagnostics.publish(status_diagnostics(enabled, rows, message.header, rospy.get_name(),
                                                     rospy.get_namespace()))


def status_diagnostics(enabled: bool, rows, header, node: str, namespace: str) -> DiagnosticArray:
    """The status as diagnostics of the node whose resolved name is `node`, in `namespace` (at the root with the
    default name: named ``animateBehaviour``, hardware id ``pepper``)."""
    waiting, summary, values = diagnostic_summary(enabled, rows)
    array = DiagnosticArray(header=header)
    array.status = [DiagnosticStatus(level=DiagnosticStatus.WARN if waiting else DiagnosticStatus.OK,
                                     name=node.lstrip("/"), message=summary, hardware_id=robot_of(namespace),
                                     values=[KeyValue(key=key, value=value) for key, value in values])]
    return array
