"""Unit tests of how the node tells other nodes' goals and Twists from its own (ros1/foreign_watch.py), no master."""
import numpy
import pytest
from actionlib_msgs.msg import GoalID, GoalStatus, GoalStatusArray
from geometry_msgs.msg import Twist, Vector3
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed

from cssr_system.core.events import ForeignGoal, ForeignJointAngles, ForeignResult, ForeignTwist
from cssr_system.pepper.joint_table import JOINTS, centre_of
from cssr_system.ros1.foreign_watch import ForeignCommandWatch
from cssr_system.ros1.rospy_compat import caller_of_goal

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"


def status_array(*goals):
    return GoalStatusArray(status_list=[GoalStatus(goal_id=GoalID(id=goal_id), status=state)
                                        for goal_id, state in goals])


def make_watch():
    posted = []
    return ForeignCommandWatch("/animateBehaviour", posted.append, lambda: 100.0), posted


def test_caller_of_goal_reads_actionlibs_goal_id():
    assert caller_of_goal("/gestureExecution-3-1795412345.678") == "/gestureExecution"
    assert caller_of_goal("/robot1/teleop-12-17.5") == "/robot1/teleop"
    assert caller_of_goal("odd") == "odd"


def test_another_clients_goal_is_posted_once_when_running_and_once_when_it_ends():
    watch, posted = make_watch()
    gesture = "/gestureExecution-1-17.25"
    watch._on_status(status_array(("/animateBehaviour-4-16.0", GoalStatus.PREEMPTED), (gesture, GoalStatus.ACTIVE)),
                     ACTION)
    watch._on_status(status_array((gesture, GoalStatus.ACTIVE)), ACTION)  # the server repeats its status
    assert posted == [ForeignGoal(ACTION, gesture, "/gestureExecution", None)]
    watch._on_status(status_array((gesture, GoalStatus.SUCCEEDED)), ACTION)
    watch._on_status(status_array((gesture, GoalStatus.SUCCEEDED)), ACTION)
    assert posted[1:] == [ForeignResult(ACTION, gesture)]


def test_our_own_goals_are_never_foreign():
    watch, posted = make_watch()
    watch._on_status(status_array(("/animateBehaviour-1-1.0", GoalStatus.ACTIVE)), ACTION)
    assert posted == []


def test_a_goal_that_leaves_the_status_list_has_ended():
    watch, posted = make_watch()
    watch._on_status(status_array(("/teleop-1-2.0", GoalStatus.PENDING)), ACTION)
    watch._on_status(status_array(), ACTION)
    assert posted == [ForeignGoal(ACTION, "/teleop-1-2.0", "/teleop", None), ForeignResult(ACTION, "/teleop-1-2.0")]


def test_another_clients_goal_is_posted_from_the_goal_topic_before_the_server_lists_it_and_ours_never():
    from control_msgs.msg import FollowJointTrajectoryActionGoal
    watch, posted = make_watch()
    gesture, ours = FollowJointTrajectoryActionGoal(), FollowJointTrajectoryActionGoal()
    gesture.goal_id.id, ours.goal_id.id = "/gestureExecution-3-5.0", "/animateBehaviour-7-5.0"
    watch._on_goal(ours, ACTION)
    watch._on_goal(gesture, ACTION)
    assert posted == [ForeignGoal(ACTION, gesture.goal_id.id, "/gestureExecution", None)]
    watch._on_status(status_array((gesture.goal_id.id, GoalStatus.ACTIVE)), ACTION)
    watch._on_status(status_array((gesture.goal_id.id, GoalStatus.SUCCEEDED)), ACTION)
    assert posted[1:] == [ForeignResult(ACTION, gesture.goal_id.id)]


def test_a_goal_first_seen_ended_is_not_a_motion():
    watch, posted = make_watch()
    watch._on_status(status_array(("/teleop-1-2.0", GoalStatus.SUCCEEDED)), ACTION)
    assert posted == []


def test_twists_are_foreign_by_caller_id():
    watch, posted = make_watch()
    ours, theirs = Twist(angular=Vector3(z=0.1)), Twist(angular=Vector3(z=0.2))
    ours._connection_header = {"callerid": "/animateBehaviour"}
    theirs._connection_header = {"callerid": "/overtAttention"}
    watch._on_twist(ours, "/pepper_dcm/cmd_moveto")
    watch._on_twist(theirs, "/pepper_dcm/cmd_moveto")
    assert posted == [ForeignTwist("/pepper_dcm/cmd_moveto", "/overtAttention", theirs)]


def test_every_status_message_is_told_to_the_controller_watcher_by_action():
    seen = []
    watch = ForeignCommandWatch("/animateBehaviour", [].append, lambda: 100.0, status_seen=seen.append)
    watch._on_status(status_array(), ACTION)
    watch._on_status(status_array(("/animateBehaviour-1-16.0", GoalStatus.ACTIVE)), ACTION)
    assert seen == [ACTION, ACTION]


def joint_angles(caller, names, angles, speed=0.1, relative=0):
    message = JointAnglesWithSpeed(joint_names=list(names), joint_angles=list(angles), speed=speed, relative=relative)
    message._connection_header = {"callerid": caller}
    return message


def test_another_nodes_joint_angles_are_posted_with_our_joints_and_when_they_arrive():
    watch, posted = make_watch()
    watch._positions = lambda joints: numpy.array([1.5, 0.0][:len(joints)])
    vmax = JOINTS["RShoulderPitch"].max_velocity
    watch._on_joint_angles(joint_angles("/gesture", ["RShoulderPitch", "HeadYaw"], [1.0, 0.3], 0.1), "/joint_angles")
    assert posted == [ForeignJointAngles("/joint_angles", "/gesture", ("RShoulderPitch",),
                                         pytest.approx(100.0 + 0.5 / (0.1 * vmax)))]


def test_our_own_and_head_only_joint_angles_are_never_foreign():
    watch, posted = make_watch()
    watch._on_joint_angles(joint_angles("/animateBehaviour", ["RShoulderPitch"], [1.0]), "/joint_angles")
    watch._on_joint_angles(joint_angles("/gesture", ["HeadYaw"], [0.3]), "/joint_angles")
    assert posted == []


def test_unmeasured_joints_are_taken_at_their_centre():
    watch, posted = make_watch()
    watch._on_joint_angles(joint_angles("/gesture", ["HipPitch"], [centre_of("HipPitch")]), "/joint_angles")
    assert posted[0].last_point_at == 100.0
