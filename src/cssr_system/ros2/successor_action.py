"""The ROS 2 successor system's interface to its animate behaviour (README: "With the successor's behaviour tree"),
served beside the node's own: the action `animate_behavior` (dec_interfaces/action/AnimateBehavior) and its stop
service `animate_behavior/stop` (std_srvs/srv/Trigger, ros2/services.py), in the node's namespace
(`/animate_behavior` at the root), so that the successor's behaviour tree drives this node unchanged. What a goal
asks and what its result says: core/successor.py; the goals run as the node's own animate action's do
(ros2/animate_action.py's GoalServer).

A goal that the stop service ends SUCCEEDS, as on the successor's own node; one ended by a cancel is CANCELED, by a
newer goal or a disable ABORTED, both with `success` false."""
from typing import Callable

from dec_interfaces.action import AnimateBehavior

from cssr_system.core.events import AnimateGoal
from cssr_system.core.session import STOPPED
from cssr_system.core.successor import checked_successor_goal, moving_parts, result_of
from cssr_system.ros2.animate_action import GoalServer

SUCCESSOR_ACTION = "animate_behavior"  # relative: in the node's namespace (its stop service: ros2/services.py)


class SuccessorActionServer(GoalServer):
    action_type = AnimateBehavior

    def __init__(self, node, configure: Callable[[dict], tuple], post: Callable[[object], None],
                 report_error: Callable[[str, Exception], None]) -> None:
        super().__init__(node, node.resolve_topic_name(SUCCESSOR_ACTION), configure, post, report_error)

    def goal_event(self, request, by: str, handle=None) -> AnimateGoal:
        (config_file, config, topics), duration, home = checked_successor_goal(request, self._configure)
        return AnimateGoal(handle, config_file, config, topics, duration, by, self, home)

    def result(self, animated: float, reason: str):
        success, message = result_of(reason)
        return AnimateBehavior.Result(success=success, message=message, total_duration=float(animated))

    def stop(self, handle, animated: float, reason: str) -> None:
        """A goal the stop service ends succeeds; otherwise as the node's own action's goals end."""
        if reason == STOPPED and not handle.is_cancel_requested:
            self.succeed(handle, animated, reason)
        else:
            super().stop(handle, animated, reason)

    def feedback_message(self, elapsed: float, rows, motions_completed: int):
        return AnimateBehavior.Feedback(current_limb=moving_parts(rows), gestures_completed=int(motions_completed),
                                        elapsed_time=float(elapsed), is_running=True)
