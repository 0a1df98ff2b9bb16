"""The animate action on ROS 2 (README: "The animate action"): `/animateBehaviour/animate`
(`cssr_system_interfaces/action/Animate`), with the ROS 1 action's semantics (ros1/animate_action.py).

A goal whose settings make an unusable configuration is rejected, the reason on the console (a ROS 2 rejection carries
no result). An accepted goal's execute callback posts it to the supervisor, which decides
everything else through `core.session.Session`, and waits for its end. The supervisor's calls (`succeed`, `stop`,
`feedback`) run on the executor's thread, woken by a guard condition: rclpy's goal handles and futures belong to it.
A goal that ends before its duration is CANCELED when its client asked for that, else ABORTED (a new goal, a
disable): ROS 2 lets a goal be canceled only after a cancel request. The result's `reason` says which.

`GoalServer` is what this action and the successor system's (ros2/successor_action.py) share.
"""
import queue
from typing import Callable, Dict

from cssr_system_interfaces.action import Animate
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.task import Future

from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import ANIMATE_ACTION, NODE_NAME
from cssr_system.core.events import AnimateCancel, AnimateGoal
from cssr_system.core.session import GoalRefused, checked_goal, goal_mode
from cssr_system.ros2.rclpy_compat import other_action_client
from cssr_system.ros2.status import part_statuses

# How long an ended goal stays on the action's status and its result can be asked for: rcl's default since Iron,
# which Jazzy's controllers keep. rclpy's own default (900 s, Humble to Kilted) keeps every goal of a quarter of an
# hour listed in each status message the server publishes, and in its clients' memory.
RESULT_TIMEOUT = 10.0


def goal_id(handle) -> bytes:
    """A goal's key (rclpy's goal handles are not hashable in every release)."""
    return bytes(handle.goal_id.uuid)


class GoalServer:
    """An rclpy action server whose goals the supervisor runs. `configure(overrides)` gives (configuration file,
    configuration, topics) with a goal's settings on top of the node's, or raises ConfigurationError; `post` puts an
    event on the supervisor's queue; `report_error(where, error)`: an unexpected error, in one line.

    A subclass names its type (`action_type`) and full name (`name`), and says what a goal asks (`goal_event`), what
    its result and feedback say (`result`, `feedback_message`) and how a goal that ends early ends (`stop`)."""

    action_type = None

    def __init__(self, node, name: str, configure: Callable[[dict], tuple], post: Callable[[object], None],
                 report_error: Callable[[str, Exception], None]) -> None:
        self._node = node
        self._configure = configure
        self._post = post
        self._report_error = report_error
        self._results: Dict[bytes, Future] = {}  # by goal id: its execute callback awaits it
        self._calls: "queue.Queue" = queue.Queue()  # the supervisor's calls, for the executor's thread
        self._wake = node.create_guard_condition(self._run_calls)
        self._server = None
        self.name = name  # as the graph lists its clients

    def start(self) -> None:
        self._server = ActionServer(self._node, self.action_type, self.name, self._execute,
                                    goal_callback=self._on_goal, cancel_callback=self._on_cancel,
                                    result_timeout=RESULT_TIMEOUT)

    def goal_event(self, request, by: str, handle=None) -> AnimateGoal:
        """The supervisor's event for a goal `request` from `by`; raises one of GoalRefused, naming what is wrong."""
        raise NotImplementedError

    def result(self, animated: float, reason: str):
        raise NotImplementedError

    def feedback_message(self, elapsed: float, rows, motions_completed: int):
        raise NotImplementedError

    # -- rclpy's callbacks, on the executor's thread -------------------------------------------------
    def _on_goal(self, request) -> GoalResponse:
        try:
            self.goal_event(request, "")
        except GoalRefused as error:
            console.warning("%s: %s goal rejected: %s", NODE_NAME, self.name, error)
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def _on_cancel(self, handle) -> CancelResponse:
        self._post(AnimateCancel(handle))
        return CancelResponse.ACCEPT

    async def _execute(self, handle):
        """Runs until the supervisor ends the goal (`succeed` or `stop`), and returns its result."""
        try:  # checked again: the configuration file may have changed since the goal callback
            event = self.goal_event(handle.request, other_action_client(self._node, self.name), handle)
        except GoalRefused as error:
            handle.abort()
            return self.result(0.0, "rejected: %s" % error)
        result = self._results[goal_id(handle)] = Future()
        self._post(event)
        if handle.is_cancel_requested:  # the cancel came before the goal reached the supervisor
            self._post(AnimateCancel(handle))
        return await result

    def _run_calls(self) -> None:
        while not self._calls.empty():
            try:
                self._calls.get_nowait()()
            except Exception as error:  # a goal that ended meanwhile, say: one line, the next calls still run
                self._report_error(self.name, error)

    def _call(self, function: Callable[[], None]) -> None:
        self._calls.put(function)
        self._wake.trigger()

    # -- the supervisor's calls ----------------------------------------------------------------------
    @staticmethod
    def accept(handle) -> None:
        """rclpy accepted the goal and runs it already (its execute callback posted it)."""

    def succeed(self, handle, animated: float, reason: str) -> None:
        self._call(lambda: self._end(handle, handle.succeed, animated, reason))

    def stop(self, handle, animated: float, reason: str) -> None:
        """A goal that ends before its duration: CANCELED after its client's cancel request, else ABORTED."""
        self._call(lambda: self._end(handle, handle.canceled if handle.is_cancel_requested else handle.abort,
                                     animated, reason))

    def feedback(self, handle, elapsed: float, rows, motions_completed: int = 0) -> None:
        """`rows`: core.status.part_rows of every stream."""
        message = self.feedback_message(elapsed, rows, motions_completed)
        self._call(lambda: handle.publish_feedback(message) if handle.is_active else None)

    def _end(self, handle, set_state: Callable[[], None], animated: float, reason: str) -> None:
        result = self._results.pop(goal_id(handle), None)
        if result is None:
            return  # ended already
        set_state()
        result.set_result(self.result(animated, reason))


class AnimateActionServer(GoalServer):
    """The rclpy server of the animate action: private, under the node's name in its namespace (README: "Several
    robots")."""

    action_type = Animate

    def __init__(self, node, configure: Callable[[dict], tuple], post: Callable[[object], None],
                 report_error: Callable[[str, Exception], None]) -> None:
        super().__init__(node, node.resolve_topic_name("~/" + ANIMATE_ACTION), configure, post, report_error)

    def goal_event(self, request, by: str, handle=None) -> AnimateGoal:
        (config_file, config, topics), duration = checked_goal(request, self._configure)
        return AnimateGoal(handle, config_file, config, topics, duration, by, sets_mode=bool(goal_mode(request)))

    def result(self, animated: float, reason: str):
        return Animate.Result(animated=float(animated), reason=reason)

    def feedback_message(self, elapsed: float, rows, motions_completed: int):
        """The motions completed are not in this action's feedback."""
        return Animate.Feedback(elapsed=float(elapsed), parts=part_statuses(rows))
