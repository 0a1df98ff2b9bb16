"""The conversation's sources on ROS 1 (README: "Modes"): std_msgs/Bool topics and actions' ``<action>/status``,
each posted to the supervisor as it speaks (core/conversation.py decides the mode). Names resolve in the node's
namespace, remapped where asked (README: "Several robots"). A Bool topic's publisher still there is a sign of life
(a latched or changes-only topic says nothing more while the robot speaks); an action's server repeats its status
list (5 Hz by default), so only its messages are."""
from typing import Callable, List, Tuple

import rospy
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from std_msgs.msg import Bool

from cssr_system.core.conversation import PRESENCE_PERIOD, HeardMessages
from cssr_system.core.events import ConversationPresent

ACTIVE_STATES = (GoalStatus.ACTIVE, GoalStatus.PREEMPTING)  # a goal the server runs: the robot speaks (or listens)


class ConversationWatch:
    """`post`: the supervisor's queue; `report_error(where, error)`: an unexpected error, in one line."""

    def __init__(self, post: Callable[[object], None], report_error: Callable[[str, Exception], None]) -> None:
        self._post = post
        self._report_error = report_error
        self._heard = HeardMessages(post, ACTIVE_STATES)
        self._topics: List[Tuple[str, rospy.Subscriber]] = []  # (key, subscription) of the Bool topics
        self._subscribers = []  # kept for the node's life
        self._timer = None

    def watch(self, sources) -> List[Tuple[str, str, str]]:
        """Subscribes to each of `sources` ((key, name, means, kind): conversation.configured_sources); (key, resolved
        name, means) of each, for the supervisor."""
        watched = []
        for key, name, means, kind in sources:
            resolved = rospy.resolve_name(name)
            if kind == "topic":
                subscriber = rospy.Subscriber(resolved, Bool, self._guarded(self._heard.bool_message),
                                              callback_args=key, queue_size=10)
                self._topics.append((key, subscriber))
            else:
                subscriber = rospy.Subscriber(resolved + "/status", GoalStatusArray,
                                              self._guarded(self._heard.status_message), callback_args=key,
                                              queue_size=1)
            self._subscribers.append(subscriber)
            watched.append((key, resolved, means))
        if self._topics:
            self._timer = rospy.Timer(rospy.Duration(PRESENCE_PERIOD), self._guarded(self._look_for_publishers))
        return watched

    def _guarded(self, callback):
        def guarded(message, argument=None):
            try:
                callback(message, argument)
            except Exception as error:  # one line, not rospy's traceback
                self._report_error("watching the conversation", error)
        return guarded

    def _look_for_publishers(self, event, argument=None) -> None:
        for key, subscriber in self._topics:
            if subscriber.get_num_connections() > 0:
                self._post(ConversationPresent(key))
