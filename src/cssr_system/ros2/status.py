"""The node's status on ROS 2 (README: "Status"): the status topic with a transient-local QoS (ROS 2's latching),
published at every change, and the same as diagnostics, named after the node's resolved name with the robot's
namespace as hardware id (core/status.py says what they hold)."""
from typing import List, Optional

from cssr_system_interfaces.msg import AnimateBehaviourStatus, PartStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rclpy.qos import DurabilityPolicy, QoSProfile

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.contract import DIAGNOSTICS_TOPIC, STATUS, robot_of
from cssr_system.animate_behaviour.live_settings import moving_parts
from cssr_system.core.status import StatusChanges, diagnostic_summary, part_rows

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def part_statuses(rows) -> List[PartStatus]:
    """The `part_rows` as messages (the status topic's and the animate action's feedback's `parts`)."""
    return [PartStatus(part=part, controller=controller, state=state, yielding_to=caller)
            for part, controller, state, caller in rows]


class StatusPublisher:
    def __init__(self, node) -> None:
        self._node = node
        self._status = node.create_publisher(AnimateBehaviourStatus, "~/" + STATUS, LATCHED)
        self._diagnostics = node.create_publisher(DiagnosticArray, DIAGNOSTICS_TOPIC, 1)
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
            message.intensity, message.tempo = float(settings.intensity), float(settings.breaths_per_minute)
            message.motion_style, message.moving_parts = settings.motion_style, moving_parts(settings)
        message.header.stamp = self._node.get_clock().now().to_msg()
        self._status.publish(message)
        waiting, summary, values = diagnostic_summary(enabled, rows)
        array = DiagnosticArray(header=message.header)
        array.status = [DiagnosticStatus(level=DiagnosticStatus.WARN if waiting else DiagnosticStatus.OK,
                                         name=self._node.get_fully_qualified_name().lstrip("/"), message=summary,
                                         hardware_id=robot_of(self._node.get_namespace()),
                                         values=[KeyValue(key=key, value=value) for key, value in values])]
        self._diagnostics.publish(array)
