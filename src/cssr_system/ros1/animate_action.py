"""The animate action (README: "The animate action"): `/animateBehaviour/animate`, a behaviour tree's way to keep
the robot alive for a while, or until cancelled, with given settings.

`AnimateActionServer` owns the actionlib server: its callbacks validate a goal's settings (a goal that asks for an
unusable configuration is rejected with the reason) and post events to the supervisor, which decides everything
else through `core.session.Session`. Only the supervisor thread ends goals and publishes feedback.
"""
import functools
from typing import Callable

import actionlib
import rospy

from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import ANIMATE_ACTION, NODE_NAME, STATUS_FREQUENCY_PARAMETER
from cssr_system.core.events import AnimateCancel, AnimateGoal
from cssr_system.core.session import GoalRefused, checked_goal, goal_mode
from cssr_system.msg import AnimateAction, AnimateFeedback, AnimateResult
from cssr_system.ros1.rospy_compat import caller_of_goal, quiet_at_shutdown
from cssr_system.ros1.status import part_statuses

STATUS_FREQUENCY = 1.0  # Hz of the action's status between changes


class AnimateActionServer:
    """The actionlib server of the animate action. `configure(overrides)` gives (configuration file, configuration,
    topics) with the goal's settings on top of the node's, or raises ConfigurationError; `post` puts an event on
    the supervisor's queue."""

    def __init__(self, configure: Callable[[dict], tuple], post: Callable[[object], None]) -> None:
        self._configure = configure
        self._post = post
        # The goals' status is published at every change; between changes once a second is enough (actionlib's
        # default, 5 Hz, would cost the node CPU for nothing). actionlib searches the parameter from the node's
        # private namespace up.
        rospy.set_param("~" + STATUS_FREQUENCY_PARAMETER, STATUS_FREQUENCY)
        # Private: under the node's name, in its namespace (README: "Several robots").
        self._server = actionlib.ActionServer(rospy.resolve_name("~" + ANIMATE_ACTION), AnimateAction,
                                              goal_cb=self._on_goal, cancel_cb=self._on_cancel, auto_start=False)

    def start(self) -> None:
        # actionlib's status timer may fire while rospy closes the topics at shutdown: quiet then.
        self._server.publish_status_async = functools.partial(quiet_at_shutdown, self._server.publish_status_async)
        self._server.start()

    def _on_goal(self, handle) -> None:
        try:
            (config_file, config, topics), duration = checked_goal(handle.get_goal(), self._configure)
        except GoalRefused as error:
            console.warning("%s: animate goal rejected: %s", NODE_NAME, error)
            handle.set_rejected(AnimateResult(reason="rejected: %s" % error), str(error))
            return
        by = caller_of_goal(handle.get_goal_id().id)
        self._post(AnimateGoal(handle, config_file, config, topics, duration, by,
                               sets_mode=bool(goal_mode(handle.get_goal()))))

    def _on_cancel(self, handle) -> None:
        self._post(AnimateCancel(handle))

    @staticmethod
    def accept(handle) -> None:
        handle.set_accepted()

    @staticmethod
    def succeed(handle, animated: float, reason: str) -> None:
        handle.set_succeeded(AnimateResult(animated=animated, reason=reason), reason)

    @staticmethod
    def stop(handle, animated: float, reason: str) -> None:
        """A goal that ends before its duration: PREEMPTED (or RECALLED before it started), with the reason."""
        handle.set_canceled(AnimateResult(animated=animated, reason=reason), reason)

    @staticmethod
    def feedback(handle, elapsed: float, rows, motions_completed: int = 0) -> None:
        """`rows`: core.status.part_rows of every stream (the motions completed are not in this action's feedback)."""
        handle.publish_feedback(AnimateFeedback(elapsed=elapsed, parts=part_statuses(rows)))
