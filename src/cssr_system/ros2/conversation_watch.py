"""The conversation's sources on ROS 2 (README: "Modes"): std_msgs/Bool topics and actions' ``<action>/_action/status``
(e.g. the successor's ``/tts`` and ``/speech_recognition``), each posted to the supervisor as it speaks
(core/conversation.py decides the mode); ROS 1's twin: ros1/conversation_watch.py. Names resolve in the node's
namespace, remapped where asked. An action's status comes at each change only (transient local), and a Bool topic
may be published at changes only too: a publisher still on the topic is a sign of life of either."""
from typing import Callable, List, Tuple

from action_msgs.msg import GoalStatus, GoalStatusArray
from rclpy.qos import qos_profile_action_status_default
from std_msgs.msg import Bool

from cssr_system.core.conversation import PRESENCE_PERIOD, HeardMessages
from cssr_system.core.events import ConversationPresent
from cssr_system.ros2.rclpy_compat import ACTION_STATUS

ACTIVE_STATES = (GoalStatus.STATUS_EXECUTING, GoalStatus.STATUS_CANCELING)  # the robot speaks (or listens)
QUEUE_DEPTH = 10


class ConversationWatch:
    """`node`: the rclpy node; `post`: the supervisor's queue; `report_error(where, error)`: one line."""

    def __init__(self, node, post: Callable[[object], None], report_error: Callable[[str, Exception], None]) -> None:
        self._node = node
        self._post = post
        self._report_error = report_error
        self._heard = HeardMessages(post, ACTIVE_STATES)
        self._topics: List[Tuple[str, str]] = []  # (key, topic) of every source: their publishers are looked for
        self._subscriptions = []  # kept for the node's life

    def watch(self, sources) -> List[Tuple[str, str, str]]:
        """Subscribes to each of `sources` ((key, name, means, kind): conversation.configured_sources); (key, resolved
        name, means) of each, for the supervisor."""
        watched = []
        for key, name, means, kind in sources:
            resolved = self._node.resolve_topic_name(name)
            if kind == "topic":
                topic, subscription = resolved, self._node.create_subscription(
                    Bool, resolved, self._guarded(self._heard.bool_message, key), QUEUE_DEPTH)
            else:
                topic = resolved + ACTION_STATUS
                subscription = self._node.create_subscription(GoalStatusArray, topic,
                                                              self._guarded(self._heard.status_message, key),
                                                              qos_profile_action_status_default)
            self._subscriptions.append(subscription)
            self._topics.append((key, topic))
            watched.append((key, resolved, means))
        if self._topics:
            self._node.create_timer(PRESENCE_PERIOD, self._guarded(self._look_for_publishers, None))
        return watched

    def _guarded(self, callback, key):
        def guarded(message=None) -> None:
            try:
                callback(message, key)
            except Exception as error:  # one line, not rclpy's traceback
                self._report_error("watching the conversation", error)
        return guarded

    def _look_for_publishers(self, message, key) -> None:
        for source, topic in self._topics:
            if self._node.count_publishers(topic) > 0:
                self._post(ConversationPresent(source))
