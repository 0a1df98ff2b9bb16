"""The ROS 2 client of a controller's FollowJointTrajectory action (ros2_control's joint_trajectory_controller), as
the part streams use it (core/goals.py says what they ask of it)."""
import collections
import threading
import uuid
from typing import Callable, Deque, Optional, Set

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from trajectory_msgs.msg import JointTrajectoryPoint
from unique_identifier_msgs.msg import UUID

from cssr_system.core.goals import ABORTED, LOST, PREEMPTED, REJECTED, SUCCEEDED, WITHHELD
from cssr_system.motion.planners import GOAL_TIME_TOLERANCE
from cssr_system.motion.trajectory_timing import TimedTrajectory, to_points

REMEMBERED_GOALS = 64  # a client's latest goals whose ids it keeps in own_goals (TrajectoryClient._remember)
# ROS 2's goal states, by the names the log uses. A canceled goal is what ROS 1 calls preempted.
STATE_NAMES = {GoalStatus.STATUS_SUCCEEDED: SUCCEEDED, GoalStatus.STATUS_ABORTED: ABORTED,
               GoalStatus.STATUS_CANCELED: PREEMPTED}


def duration(seconds: float) -> Duration:
    nanoseconds = int(round(seconds * 1e9))
    return Duration(sec=nanoseconds // 1000000000, nanosec=nanoseconds % 1000000000)


def goal_message(joints, timed: TimedTrajectory) -> FollowJointTrajectory.Goal:
    """The goal of a planned trajectory (with its hold, `planners.settled`), to start as soon as it arrives
    (a zero stamp), with positions, velocities and accelerations and GOAL_TIME_TOLERANCE."""
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = list(joints)
    goal.goal_time_tolerance = duration(GOAL_TIME_TOLERANCE)
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=[float(value) for value in point.positions],
                             velocities=[float(value) for value in point.velocities],
                             accelerations=[float(value) for value in point.accelerations],
                             time_from_start=duration(time))
        for point, time in zip(to_points(timed), timed.times)]
    return goal


class SentGoal:
    """A goal sent: its id, and its cancel, which waits for the server's acceptance if that has not come yet.
    `on_executor(work)` runs `work` on the executor's thread (TrajectoryClient says why)."""

    def __init__(self, goal: FollowJointTrajectory.Goal, on_executor: Callable[[Callable[[], None]], None],
                 told: Optional[int] = None) -> None:
        self.goal = goal
        self.told = told  # other clients' goals told when the send was decided (ForeignGoals.started)
        self.uuid = UUID(uuid=list(uuid.uuid4().bytes))
        self.replaced = False  # no longer runs for us
        self._on_executor = on_executor
        self._lock = threading.Lock()
        self._sent = False  # the message has gone (rclpy has serialised it)
        self._handle = None  # rclpy's ClientGoalHandle, once the server has answered
        self._cancel_wanted = False

    def went_out(self) -> None:
        with self._lock:
            self._sent = True
            if self.replaced:
                self.goal.trajectory.points = []

    def accepted(self, handle) -> None:
        with self._lock:
            self._handle = handle
            cancel = self._cancel_wanted
        if cancel:
            handle.cancel_goal_async()

    def cancel(self) -> None:
        with self._lock:
            self._cancel_wanted = True
            handle = self._handle
        if handle is not None:
            self._on_executor(handle.cancel_goal_async)

    def release(self) -> None:
        """Its points go once the message has gone (a goal still queued for the executor is sent whole)."""
        with self._lock:
            self.replaced = True
            if self._sent:
                self.goal.trajectory.points = []


class TrajectoryClient:
    """One controller's FollowJointTrajectory client. `own_goals`: the ids of the goals this node has sent lately (the
    foreign watch tells other clients' goals apart by them); this client keeps its REMEMBERED_GOALS latest there.

    Goals and cancels are sent on the executor's thread (`on_executor`): rclpy's ActionClient registers a request's
    future only after the request has gone, so an answer that the executor's thread takes first is lost or fails
    (ros2/rclpy#1123, #878). That thread also takes the controllers' status lists, so the last look before a goal
    leaves (`last_look`, core/foreign_goals.py) sees every list taken before it: a goal is withheld when another
    client's goal runs on the controller, or came after the supervisor decided to send (README: "Sharing the
    robot")."""

    def __init__(self, node, action: str, own_goals: Set[bytes], on_executor: Callable[[Callable[[], None]], None],
                 callback_group=None, last_look=None) -> None:
        self.client = ActionClient(node, FollowJointTrajectory, action, callback_group=callback_group)
        self.action = action
        self._last_look = last_look
        self._on_executor = on_executor
        self._own_goals = own_goals
        self._sent_ids: Deque[bytes] = collections.deque()  # ours in own_goals, the oldest first

    def ready(self) -> bool:
        return self.client.server_is_ready()

    @staticmethod
    def goal(joints, timed: TimedTrajectory) -> FollowJointTrajectory.Goal:
        return goal_message(joints, timed)

    def send(self, goal: FollowJointTrajectory.Goal,
             done: Callable[[str, Optional[int], str], None]) -> SentGoal:
        told = None if self._last_look is None else self._last_look.started(self.action)
        sent = SentGoal(goal, self._on_executor, told)
        self._remember(bytes(sent.uuid.uuid))
        self._on_executor(lambda: self._send_now(sent, done))
        return sent

    def _send_now(self, sent: SentGoal, done) -> None:
        futures = []

        def send() -> None:
            futures.append(self.client.send_goal_async(sent.goal, goal_uuid=sent.uuid))
        try:
            foreign = send() if self._last_look is None else \
                self._last_look.send_unless_foreign(self.action, send, sent.told)
        except Exception as error:  # raised on the executor's thread, it would end the executor
            done(LOST, None, "not sent: %s: %s" % (type(error).__name__, error))
            return
        if foreign is not None:
            done(WITHHELD, None, "not sent: another client's goal %s is on the controller" % foreign)
            return
        sent.went_out()
        futures[0].add_done_callback(lambda answered: self._answered(sent, answered, done))

    def _remember(self, goal_id: bytes) -> None:
        """`goal_id` joins own_goals and this client's oldest leaves it, so that the set does not grow with every goal
        sent (about 100 bytes each). The controller runs one goal at a time: ours of REMEMBERED_GOALS goals ago has
        ended, and the watch pays no heed to an ended goal, ours or not. Only the supervisor thread sends."""
        self._own_goals.add(goal_id)
        self._sent_ids.append(goal_id)
        if len(self._sent_ids) > REMEMBERED_GOALS:
            self._own_goals.discard(self._sent_ids.popleft())

    def _answered(self, sent: SentGoal, future, done) -> None:
        handle = future.result()
        if handle is None or not handle.accepted:
            done(REJECTED, None, "")
            return
        sent.accepted(handle)
        handle.get_result_async().add_done_callback(lambda finished: self._finished(sent, finished, done))

    @staticmethod
    def _finished(sent: SentGoal, future, done) -> None:
        response = future.result()
        if response is None:
            done(LOST, None, "")
            return
        state = STATE_NAMES.get(response.status, LOST)
        if sent.replaced and state == ABORTED:  # joint_trajectory_controller aborts the goal a new one replaces
            state = PREEMPTED
        done(state, response.result.error_code, response.result.error_string)
