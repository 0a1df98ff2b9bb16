"""The FollowJointTrajectory goal of a planned trajectory (ros1/trajectory_client.py goal_message): every point's
positions, velocities, accelerations and time, to the nanosecond, as planned."""
import io

import numpy
from control_msgs.msg import FollowJointTrajectoryActionGoal

from cssr_system.motion.planners import GOAL_TIME_TOLERANCE, settled
from cssr_system.motion.trajectory_timing import time_trajectory
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros1.trajectory_client import goal_message


def planned(part: str, seed: int):
    joints, centre = PARTS[part].joints, numpy.array(PARTS[part].centre)
    rng = numpy.random.default_rng(seed)
    waypoints = centre + rng.uniform(-0.05, 0.05, (12, len(joints)))
    zeros = numpy.zeros(len(joints))
    return joints, settled(time_trajectory(waypoints, joints, centre, zeros, 0.7))


def test_the_goal_carries_every_point_as_planned_and_serializes():
    for seed, part in enumerate(PARTS):
        joints, timed = planned(part, seed)
        goal = goal_message(joints, timed)
        assert goal.trajectory.joint_names == list(joints)
        assert goal.trajectory.header.stamp.is_zero()  # start as soon as it arrives
        assert goal.goal_time_tolerance.to_sec() == GOAL_TIME_TOLERANCE
        assert len(goal.trajectory.points) == len(timed.times)
        for point, time, positions, velocities, accelerations in zip(goal.trajectory.points, timed.times,
                                                                     timed.positions, timed.velocities,
                                                                     timed.accelerations):
            assert point.positions == list(positions) and point.velocities == list(velocities)
            assert point.accelerations == list(accelerations) and point.effort == []
            assert all(isinstance(value, float) for value in point.positions + point.velocities)
            assert point.time_from_start.to_nsec() == int(round(time * 1e9))
        FollowJointTrajectoryActionGoal(goal=goal).serialize(io.BytesIO())


def test_the_hold_of_a_goal_that_ends_at_rest_is_its_last_point_again():
    joints, timed = planned("RArm", 7)
    points = goal_message(joints, timed).trajectory.points
    assert points[-1].positions == points[-2].positions
    assert points[-1].velocities == [0.0] * len(joints)


class FakeActionClient:
    def __init__(self):
        self.sent = []

    def send_goal(self, goal, transition):
        self.sent.append(goal)
        return "handle %d" % len(self.sent)


def test_a_goal_leaves_under_the_last_look_and_is_withheld_while_another_clients_goal_runs():
    from cssr_system.core.foreign_goals import ForeignGoals
    from cssr_system.ros1.trajectory_client import TrajectoryClient
    action = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"
    actionlib_client, posted, ends = FakeActionClient(), [], []
    goals = ForeignGoals(posted.append)
    client = TrajectoryClient(action, actionlib_client, last_look=goals)
    joints, timed = planned("RArm", 3)
    done = lambda *end: ends.append(end)  # noqa: E731
    assert client.send(client.goal(joints, timed), done).handle == "handle 1" and ends == []
    goals.status_list(action, [("gesture", True)], lambda goal_id: "/gestureExecution")
    withheld = client.send(client.goal(joints, timed), done)
    withheld.cancel()  # nothing left: nothing to cancel
    assert len(actionlib_client.sent) == 1 and ends[0][:2] == ("WITHHELD", None) and "gesture" in ends[0][2]
