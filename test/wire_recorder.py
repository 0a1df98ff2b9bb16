"""Records what goes over the wire to a robot's controllers, for tests and benchmarks (rospy).

Subscribes to every action namespace's goal, cancel and result topics and to the Wheels topic of a
topic map, and keeps each message with its arrival time on the monotonic clock."""
import threading
import time

import rospy
from actionlib_msgs.msg import GoalID, GoalStatus
from control_msgs.msg import FollowJointTrajectoryActionGoal, FollowJointTrajectoryActionResult
from geometry_msgs.msg import Twist

from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.pepper.joint_table import PARTS


class WireRecorder:
    """goals, cancels, results, twists: lists of (arrival time, topic-map key, message)."""

    def __init__(self, topics):
        self.lock = threading.Lock()
        self.goals, self.cancels, self.results, self.twists = [], [], [], []
        self._needed = []  # subscribers that must be connected before measuring
        self._subscribers = []
        self._names = dict(topics)
        for key, name in topics.items():
            if key not in PARTS and key != WHEELS_KEY:  # JointAngles: no goals there
                continue
            if key == WHEELS_KEY:
                subscriber = rospy.Subscriber(name, Twist, self._record, (self.twists, key))
                self._needed.append(subscriber)
                self._subscribers.append(subscriber)
                continue
            goal = rospy.Subscriber(name + "/goal", FollowJointTrajectoryActionGoal, self._record,
                                    (self.goals, key))
            self._needed.append(goal)
            self._subscribers += [goal,
                                  rospy.Subscriber(name + "/cancel", GoalID, self._record,
                                                   (self.cancels, key)),
                                  rospy.Subscriber(name + "/result", FollowJointTrajectoryActionResult,
                                                   self._record, (self.results, key))]

    def _record(self, message, args):
        store, key = args
        with self.lock:
            store.append((time.monotonic(), key, message))

    def clear(self):
        with self.lock:
            for store in (self.goals, self.cancels, self.results, self.twists):
                del store[:]

    def snapshot(self, store):
        with self.lock:
            return list(store)

    def connected(self):
        """True once every goal and Wheels subscription has a publisher connected."""
        return all(subscriber.get_num_connections() > 0 for subscriber in self._needed)

    def connected_to(self, caller_id, keys=None):
        """True once every goal and cancel subscription (of `keys`, or all) has an open connection from the node
        `caller_id`. A node started just before sends its first goals at once: wait for this before enabling it."""
        actions = [subscriber for subscriber in self._subscribers
                   if subscriber.name.endswith(("/goal", "/cancel"))
                   and (keys is None or any(subscriber.name.startswith(self._names[key] + "/") for key in keys))]
        return all(any(connection.callerid_pub == caller_id and not connection.done
                       for connection in subscriber.impl.connections)
                   for subscriber in actions)

    def unregister(self):
        for subscriber in self._subscribers:
            subscriber.unregister()


def wait_until(condition, timeout, period=0.01):
    """Polls `condition` until it is true or `timeout` seconds have passed; returns its last value."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return condition()


def next_goal_gaps(goals, results, goal_ids=None):
    """(part key, seconds) from each succeeded goal's result to the goal that followed it.

    Pairs by sequence, not by arrival time: the result and the next goal travel on different
    connections, so under load the next goal may reach the observer first (a gap of 0 then).
    `goal_ids` limits the succeeded goals considered."""
    goal_order = {}  # part key -> goal ids in the order they were sent
    goal_arrival = {}
    for at, key, message in goals:
        goal_order.setdefault(key, []).append(message.goal_id.id)
        goal_arrival[message.goal_id.id] = at
    gaps = []
    for at, key, message in results:
        goal_id = message.status.goal_id.id
        if message.status.status != GoalStatus.SUCCEEDED or goal_id not in goal_arrival:
            continue
        if goal_ids is not None and goal_id not in goal_ids:
            continue
        order = goal_order[key]
        position = order.index(goal_id)
        if position + 1 < len(order):
            gaps.append((key, max(0.0, goal_arrival[order[position + 1]] - at)))
    return gaps
