"""Our own messages, as they come back to this node's subscriptions on ROS 2.

The node watches the topics it also publishes on (the base's Twist topic, naoqi_driver2's JointAngles topic) to
notice other nodes' commands. ROS 1 names each message's publisher; a Humble subscription does not. So each
message the node publishes is remembered by its content until it comes back (a topic delivers one publisher's
messages in order); a message that matches none of ours is another node's."""
import collections
import threading
from typing import Deque, Hashable

REMEMBERED = 64  # messages not seen again yet: more than the node sends in the time a message takes to arrive


class OwnMessages:
    def __init__(self) -> None:
        self._sent: Deque[Hashable] = collections.deque(maxlen=REMEMBERED)
        self._lock = threading.Lock()

    def sent(self, key: Hashable) -> None:
        with self._lock:
            self._sent.append(key)

    def is_own(self, key: Hashable) -> bool:
        """True (and forgotten) when `key` is one of ours not seen again yet."""
        with self._lock:
            try:
                self._sent.remove(key)
                return True
            except ValueError:
                return False
