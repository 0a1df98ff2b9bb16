"""The node's status as ROS diagnostics (README: "Status"): one DiagnosticStatus named after the node, OK
while every part is where it should be, WARN while a part waits (a missing controller, a retry)."""
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from cssr_system.animate_behaviour.contract import NODE_NAME


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
