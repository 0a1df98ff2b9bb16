"""What a test or a tool sees of one robot from outside, whatever the ROS: the joints its /joint_states reports and
the status messages its animateBehaviour node publishes (README: "Status"), fed from the client library's callback
threads. Pure Python."""
import threading
import time
from typing import List, Sequence, Tuple

from cssr_system.pepper.joint_table import PARTS


class RobotWatch:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.samples: List[Tuple[float, dict]] = []  # (monotonic time, {joint: position})
        self.statuses: list = []  # the node's status messages, in order

    def joint_states(self, names: Sequence[str], positions: Sequence[float]) -> None:
        """One /joint_states message's joints and positions, as it comes."""
        with self.lock:
            self.samples.append((time.monotonic(), dict(zip(names, positions))))

    def status(self, message) -> None:
        with self.lock:
            self.statuses.append(message)

    def travel(self, since: float) -> float:
        """The largest travel (rad) of an arm, hand or leg joint since `since` (monotonic time)."""
        with self.lock:
            samples = [positions for stamp, positions in self.samples if stamp >= since]
        joints = [joint for part in PARTS.values() for joint in part.joints]
        return max((max(s[joint] for s in samples) - min(s[joint] for s in samples) for joint in joints
                    if samples and all(joint in s for s in samples)), default=0.0)

    def yielding_since(self, count: int) -> List[Tuple[str, str]]:
        """(part, the node it yields to) of each yielding part row in the status messages after the first `count`."""
        with self.lock:
            return [(part.part, part.yielding_to) for status in self.statuses[count:] for part in status.parts
                    if part.state == "yielding"]
