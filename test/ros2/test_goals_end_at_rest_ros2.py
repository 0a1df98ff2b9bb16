"""Every goal ends at rest on ROS 2 (README: "Controllers: what each goal carries"): the simulated Pepper judges
goals with joint_trajectory_controller's checks at Jazzy's defaults, which refuse a last point that still moves.
Each style, and a switch of style while enabled, runs with no goal rejected; a node killed mid-breathing leaves
every joint coming to rest without a jump in velocity.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import signal
import time

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")

from builtin_interfaces.msg import Duration  # noqa: E402 (after the skips)
from control_msgs.action import FollowJointTrajectory  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from domains import claim_domain  # noqa: E402
from processes import on_executor  # noqa: E402
from test_animate_behaviour_ros2 import SIMULATOR_PARTS, Run, start, stop, wait_until  # noqa: E402
from trajectory_msgs.msg import JointTrajectoryPoint  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402

DOMAIN = claim_domain()
ARM_ACTION = "/pepper/RightArm_controller/follow_joint_trajectory"
AT_REST = 1e-3  # rad/s: a joint slower than this has come to rest
JUMP = 0.01  # rad/s: the largest change of velocity between two 50 Hz samples that is no jump
SAMPLE_PERIOD = 0.02  # s between /joint_states messages


def breathing_run(tmp_path, breaths_per_minute: int) -> Run:
    """The simulated Pepper (Jazzy's defaults) and the node breathing with arms and leg, enabled."""
    run = Run(tmp_path, ("platform:=simulator",), ("platform:=simulator", "behaviour:=body", "motionStyle:=breathing",
                                                   "breathsPerMinute:=%d" % breaths_per_minute), DOMAIN)
    try:
        assert run.client.activate("enabled") == contract.REPLY_SUCCESS
    except AssertionError:
        run.close()
        raise
    return run


def goal_answer(client, velocities):
    """Whether the simulated Pepper accepts a goal to the right arm's centre whose last point has `velocities`."""
    action = ActionClient(client.node, FollowJointTrajectory, ARM_ACTION)
    try:
        assert action.wait_for_server(timeout_sec=10.0)
        goal = FollowJointTrajectory.Goal()
        goal.trajectory.joint_names = list(PARTS["RArm"].joints)
        goal.trajectory.points = [JointTrajectoryPoint(positions=list(PARTS["RArm"].centre), velocities=velocities,
                                                       time_from_start=Duration(sec=1))]
        future = on_executor(client.node, lambda: action.send_goal_async(goal))
        assert wait_until(future.done, 5.0), "no answer"
        return future.result().accepted
    finally:
        client.node.destroy_client(action)


def test_the_simulated_pepper_refuses_a_moving_last_point_at_jazzys_default_and_takes_it_at_humbles(tmp_path):
    moving = [0.0, 0.0, 0.0, -0.054, 0.0]
    run = Run(tmp_path, ("platform:=simulator",), ("platform:=simulator", "behaviour:=rotation"), DOMAIN)
    try:
        assert not goal_answer(run.client, moving)
        assert goal_answer(run.client, [0.0] * 5)
        stop(run.simulator)
        jazzy_output = run.output(run.simulator)
        run.simulator = start("cssr_system.ros2.simulated_pepper_node", "platform:=simulator",
                              "allow_nonzero_velocity_at_trajectory_end:=true", domain=DOMAIN)
        assert goal_answer(run.client, moving)
    finally:
        run.close()
    assert "Velocity of last trajectory point of joint RElbowYaw is not zero: -0.054000000000000" in jazzy_output


def test_each_style_and_a_switch_of_style_while_enabled_run_with_no_goal_rejected(tmp_path):
    run = breathing_run(tmp_path, 20)
    try:
        client = run.client
        # Breathing until every part's first goal has been replaced by its next (9 s goals at 20 breaths a minute).
        assert wait_until(lambda: {entry.fields["part"] for entry in run.entries(contract.GOAL_FINISHED)
                                   if entry.fields["state"] == "PREEMPTED"} >= SIMULATOR_PARTS, 20.0)
        assert client.set_parameter("motionStyle", "random").successful
        time.sleep(5.0)
        assert client.set_parameter("motionStyle", "breathing").successful
        time.sleep(4.0)
        assert client.activate("disabled") == contract.REPLY_SUCCESS
        time.sleep(2.5)  # the return home ends
    finally:
        run.close()
    finished = run.entries(contract.GOAL_FINISHED)
    assert len(finished) >= 3 * len(SIMULATOR_PARTS)
    assert [entry.fields for entry in finished if entry.fields["state"] not in ("SUCCEEDED", "PREEMPTED")] == []
    styles = [entry.fields["new"] for entry in run.entries(contract.SETTING_CHANGED)]
    assert styles == ["random", "breathing"]


def test_a_node_killed_mid_breathing_leaves_every_joint_coming_to_rest_smoothly(tmp_path):
    run = breathing_run(tmp_path, 15)
    try:
        client = run.client
        assert wait_until(lambda: all(client.part_state(part) == "animating" for part in SIMULATOR_PARTS), 3.0)
        time.sleep(4.0)
        killed = len(client.joint_states)
        run.node.send_signal(signal.SIGKILL)
        run.node.wait(10.0)
        joints = [joint for part in SIMULATOR_PARTS for joint in PARTS[part].joints]

        def at_rest():
            last = client.joint_states[-1]
            speeds = dict(zip(last.name, last.velocity))
            return all(abs(speeds[joint]) < AT_REST for joint in joints)
        assert not at_rest(), "killed while moving"
        assert wait_until(at_rest, 30.0), "every joint comes to rest"
        time.sleep(0.5)
        samples = list(client.joint_states[killed:])
    finally:
        client.close()
        stop(run.simulator)
    for joint in joints:
        index = samples[0].name.index(joint)
        for before, after in zip(samples, samples[1:]):
            gap = (after.header.stamp.sec - before.header.stamp.sec) + (
                after.header.stamp.nanosec - before.header.stamp.nanosec) * 1e-9
            change = abs(after.velocity[index] - before.velocity[index])
            assert change <= JUMP * max(1.0, gap / SAMPLE_PERIOD), (joint, change, gap)
        assert abs(samples[-1].velocity[index]) < AT_REST, joint
