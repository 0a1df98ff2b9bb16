"""animateBehaviourDemoGesture: plays a gesture on an arm as another node would, with its own actionlib client.

rosrun cssr_system animateBehaviourDemoGesture.py [_node:=/animateBehaviour]
then: rostopic pub -1 /animateBehaviourDemoGesture/play std_msgs/Empty

On each message on /animateBehaviourDemoGesture/play it sends the demo's gesture (`gesture`: a 4 s
wave of the right arm, ending at its rest posture) as a FollowJointTrajectory goal to the right arm's
action namespace, which it reads from the topic file of the node's configuration (``~node``, default
/animateBehaviour, as the node resolves it). It prints one line when it sends the goal and one when
the goal ends, with its final state (SUCCEEDED, PREEMPTED, ABORTED, ...): the demo shows whether
animateBehaviour lets the gesture run.
"""
import functools
import os
import threading
import time

import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from std_msgs.msg import Empty
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour import console
from cssr_system.demo.gesture import (GESTURE_DURATION, GESTURE_PART, NODE_NAME, PLAY_TOPIC,
                                      gesture_points)
from cssr_system.pepper.joint_table import PARTS
from cssr_system.recording.recording import run_setting
from cssr_system.ros1.trajectory_client import goal_state_name

say = functools.partial(console.say, NODE_NAME)

SERVER_TIMEOUT = 5.0  # s to wait for the action server when playing


class GesturePlayer:
    def __init__(self, action: str) -> None:
        self.action = action
        self.label = PARTS[GESTURE_PART].label
        self.client = actionlib.SimpleActionClient(action, FollowJointTrajectoryAction)
        self._lock = threading.Lock()

    def goal(self) -> FollowJointTrajectoryGoal:
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(PARTS[GESTURE_PART].joints)
        goal.trajectory.header.stamp = rospy.Time(0)  # start now
        for point in gesture_points(GESTURE_PART, GESTURE_DURATION):
            goal.trajectory.points.append(JointTrajectoryPoint(
                positions=list(point.positions), velocities=list(point.velocities),
                accelerations=list(point.accelerations), time_from_start=rospy.Duration.from_sec(point.time)))
        return goal

    def play(self, message: Empty) -> None:
        with self._lock:  # one play at a time
            if not self.client.wait_for_server(rospy.Duration(SERVER_TIMEOUT)):
                say("error: no action server on %s within %.0f s: no gesture" % (self.action, SERVER_TIMEOUT))
                return
            sent = time.monotonic()

            def done(state: int, result) -> None:
                detail = " (%s)" % result.error_string if result is not None and result.error_string else ""
                elapsed, state_name = time.monotonic() - sent, goal_state_name(state)
                say("gesture on the %s ended after %.1f s: %s%s" % (self.label, elapsed, state_name, detail))

            self.client.send_goal(self.goal(), done_cb=done)
            say("gesture on the %s started (%g s, goal to %s)" % (self.label, GESTURE_DURATION, self.action))


def main() -> int:
    rospy.init_node(NODE_NAME)
    node = rospy.resolve_name(str(rospy.get_param("~node", contract.NODE_NAME)))  # relative: in our namespace
    try:
        topics = run_setting(rospy.get_param(node, {}), os.environ.get("ROS_HOME"), node).topics
    except ValueError as error:
        say("error: the configuration of %s cannot be read: %s" % (node, error))
        return 1
    if GESTURE_PART not in topics:
        say("error: the topic file of %s names no %s action: no gesture" % (node, GESTURE_PART))
        return 1
    player = GesturePlayer(topics[GESTURE_PART])
    rospy.Subscriber(PLAY_TOPIC, Empty, player.play, queue_size=1)
    rospy.spin()
    return 0
