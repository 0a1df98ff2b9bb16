"""animateBehaviourDemoGesture on ROS 2: plays the demo's gesture on an arm as another node would, with its own
rclpy action client (the twin of cssr_system.ros1.gesture_player).

  python3 -m cssr_system.ros2.gesture_player --ros-args -p platform:=simulator
  then: ros2 topic pub --once animateBehaviourDemoGesture/play std_msgs/msg/Empty

On each message on its play topic it sends the demo's gesture (`gesture`: a 4 s wave of the right arm, ending at
its rest posture) as a FollowJointTrajectory goal to the right arm's action of the platform's shipped topic file,
resolved in its own namespace. It prints one line when it sends the goal and one when the goal ends, with its final
state: the demo shows whether animateBehaviour lets the gesture run.
"""
import functools
import sys
import threading
import time
from typing import List, Optional

from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import Empty
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import console
from cssr_system.demo.gesture import GESTURE_DURATION, GESTURE_PART, NODE_NAME, PLAY_TOPIC, gesture_points
from cssr_system.pepper.joint_table import PARTS
from cssr_system.recording.recording import run_setting
from cssr_system.ros2.program import on_signals, run_node
from cssr_system.ros2.trajectory_client import STATE_NAMES, duration

say = functools.partial(console.say, NODE_NAME)
SERVER_TIMEOUT = 5.0  # s to wait for the action server when playing


def gesture_goal() -> FollowJointTrajectory.Goal:
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = list(PARTS[GESTURE_PART].joints)
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=list(point.positions), velocities=list(point.velocities),
                             accelerations=list(point.accelerations), time_from_start=duration(point.time))
        for point in gesture_points(GESTURE_PART, GESTURE_DURATION)]
    return goal


class GesturePlayer:
    """Plays on each message of the play topic, one gesture at a time; every callback runs on the executor's
    thread, so waiting for the server happens on a thread of its own."""

    def __init__(self, node: Node, action: str) -> None:
        self.node, self.action = node, node.resolve_topic_name(action)
        self.label = PARTS[GESTURE_PART].label
        self.client = ActionClient(node, FollowJointTrajectory, self.action)
        self._playing = threading.Lock()
        node.create_subscription(Empty, PLAY_TOPIC, self.play, 1)

    def play(self, _message: Empty) -> None:
        if self._playing.acquire(blocking=False):
            threading.Thread(target=self._send, name="gesture", daemon=True).start()

    def _send(self) -> None:
        if not self.client.wait_for_server(timeout_sec=SERVER_TIMEOUT):
            say("error: no action server on %s within %.0f s: no gesture" % (self.action, SERVER_TIMEOUT))
            self._playing.release()
            return
        # rclpy's ActionClient registers a goal's future only after sending the goal: sent from this thread, an
        # answer the executor's thread took first would be lost (ros2/rclpy#1123). The executor's thread sends it.
        self.node.executor.create_task(self._send_goal)

    def _send_goal(self) -> None:
        sent = time.monotonic()
        self.client.send_goal_async(gesture_goal()).add_done_callback(lambda future: self._accepted(future, sent))
        say("gesture on the %s started (%g s, goal to %s)" % (self.label, GESTURE_DURATION, self.action))

    def _accepted(self, future, sent: float) -> None:
        handle = future.result()
        if not handle.accepted:
            say("gesture on the %s ended after %.1f s: REJECTED" % (self.label, time.monotonic() - sent))
            self._playing.release()
            return
        handle.get_result_async().add_done_callback(lambda result: self._ended(result.result(), sent))

    def _ended(self, response, sent: float) -> None:
        state = STATE_NAMES.get(response.status, str(response.status))
        detail = " (%s)" % response.result.error_string if response.result.error_string else ""
        say("gesture on the %s ended after %.1f s: %s%s" % (self.label, time.monotonic() - sent, state, detail))
        self._playing.release()


def play(node: Node, stop: threading.Event) -> int:
    platform = str(node.declare_parameter("platform", "robot").value)
    try:
        topics = run_setting({"platform": platform}, None).topics
    except ValueError as error:
        say("error: the topic file of platform %s cannot be read: %s" % (platform, error))
        return 1
    if GESTURE_PART not in topics:
        say("error: the topic file of platform %s names no %s action: no gesture" % (platform, GESTURE_PART))
        return 1
    GesturePlayer(node, topics[GESTURE_PART])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    threading.Thread(target=executor.spin, name="executor", daemon=True).start()
    while not stop.wait(0.2):  # a signal sets it
        pass
    executor.shutdown()
    return 0


def main(args: Optional[List[str]] = None) -> int:
    stop = threading.Event()
    on_signals(lambda _name: stop.set())
    return run_node(NODE_NAME, args, lambda node: play(node, stop))


if __name__ == "__main__":
    sys.exit(main())
