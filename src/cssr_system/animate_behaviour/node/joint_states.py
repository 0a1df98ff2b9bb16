"""The latest measured joint positions, from /joint_states.
"""
import threading
import time
from typing import Dict, Optional

import numpy
from sensor_msgs.msg import JointState


JOINT_STATE_MAX_AGE = 1.0  # s; older /joint_states are not trusted as the current position


class JointStateCache:
    """The latest measured position of every joint, written by the /joint_states callback."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._positions: Dict[str, float] = {}
        self._received_at = 0.0

    def update(self, message: JointState) -> None:
        with self._lock:
            self._positions.update(zip(message.name, message.position))
            self._received_at = time.monotonic()

    def positions(self, joints) -> Optional[numpy.ndarray]:
        """Current positions of `joints`, or None when they are unknown or stale."""
        with self._lock:
            if time.monotonic() - self._received_at > JOINT_STATE_MAX_AGE:
                return None
            if not all(name in self._positions for name in joints):
                return None
            return numpy.array([self._positions[name] for name in joints], dtype=float)
