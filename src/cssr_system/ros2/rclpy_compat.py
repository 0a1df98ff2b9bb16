"""Who is at the other end of a topic, where ROS 2 says less than ROS 1: the one module of the ROS 2 front-end that
makes up for it (its ROS 1 twin, cssr_system.ros1.rospy_compat, reads the sender of each message and goal).

The graph names a topic's publishers and subscribers (`endpoint_names`), not who sent a message. The node watches the
topics it also publishes on (the base's Twist topic, naoqi_driver2's JointAngles topic) to notice other nodes'
commands; ROS 1 names each message's publisher, a Humble subscription does not. So each message the node publishes
is remembered by its content until it comes back (`OwnMessages`: a topic delivers one publisher's messages in
order); a message that matches none of ours is another node's."""
import collections
import threading
from typing import Deque, Hashable

REMEMBERED = 64  # messages not seen again yet: more than the node sends in the time a message takes to arrive
ACTION_STATUS = "/_action/status"  # an action's topics, after its name: its server publishes its goals' states,
ACTION_FEEDBACK = "/_action/feedback"  # and each of its clients subscribes to its feedback


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


def endpoint_names(infos) -> set:
    """Fully qualified node names of a topic's publishers or subscribers (rclpy's endpoint infos)."""
    return {"%s/%s" % (info.node_namespace.rstrip("/"), info.node_name) for info in infos}


def subscribed_by_another_node(node, topic: str) -> bool:
    """Whether a node other than `node` subscribes to `topic`: the robot's driver or a simulator. The node's own
    subscription (its watch of the topic for other nodes' commands) does not count."""
    return bool(endpoint_names(node.get_subscriptions_info_by_topic(topic)) - {node.get_fully_qualified_name()})


def other_action_client(node, action: str) -> str:
    """Who else is a client of `action` (a fully qualified name): the node, where the graph shows exactly one besides
    `node`, else "another client of <action>". A goal's id does not name its sender on ROS 2, as on ROS 1.

    An action's clients are the subscribers of its feedback topic, as rcl_action finds them. The topic is asked, not
    each node with rclpy.action's get_action_client_names_and_types_by_node: rclpy never frees the names that one
    returns (hundreds of bytes a call, a call per node in the graph)."""
    clients = endpoint_names(node.get_subscriptions_info_by_topic(action + ACTION_FEEDBACK))
    clients.discard(node.get_fully_qualified_name())
    return clients.pop() if len(clients) == 1 else "another client of %s" % action
