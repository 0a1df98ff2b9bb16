"""The ROS 2 successor system's behaviour tree drives the node (README: "With the successor's behaviour tree"): a
client written from the action's field table (dec_interfaces/action/AnimateBehavior: goal `behavior_type` string,
`selected_range` float32, `duration_seconds` int32; result `success`, `message`, `total_duration`; feedback
`current_limb`, `gestures_completed`, `elapsed_time`, `is_running`) and the stop service (std_srvs/srv/Trigger) does
what the tree does, against the node beside the ROS 2 simulated Pepper on the robot platform (hands and base too).
Every goal with a duration, of this action and of the node's own, ends within 0.3 s of it, every part at its centre.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2/test_successor_ros2.py -q
"""
import threading
import time

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("dec_interfaces.action")

from action_msgs.msg import GoalStatus  # noqa: E402 (after the skips)
from cssr_system_interfaces.action import Animate  # noqa: E402
from cssr_system_interfaces.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system_interfaces.srv import SetActivation  # noqa: E402
from dec_interfaces.action import AnimateBehavior  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.event_log import read_log  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402

from domains import claim_domain  # noqa: E402
from processes import on_executor, start_program, stop_program, wait_until  # noqa: E402

DOMAIN = claim_domain()
START_TIMEOUT = 20.0  # s
ON_TIME = 0.3  # s: a goal with a duration ends this close to it
ROBOT_PARTS = ("RArm", "LArm", "RHand", "LHand", "Leg")
WHEELS = "Wheels"
# What each behavior_type moves (the node's status rows), as the successor's own node does, the base with "rotation".
MOVES = {"All": set(ROBOT_PARTS) | {WHEELS}, "body": set(ROBOT_PARTS), "hands": {"RArm", "LArm", "RHand", "LHand"},
         "arms": {"RArm", "LArm"}, "rotation": {WHEELS}}
CENTRE_TOLERANCE = 0.02  # rad (a hand: its unit)


def successor_goal(behavior_type: str, selected_range: float, duration_seconds: int) -> AnimateBehavior.Goal:
    """The tree's goal, field by field (its `AnimateBehavior` node's ports)."""
    goal = AnimateBehavior.Goal()
    goal.behavior_type = behavior_type
    goal.selected_range = selected_range
    goal.duration_seconds = duration_seconds
    return goal


class Tree:
    """What the successor's behaviour tree holds of the node: the action and the stop service; and what the test
    watches: the node's status and /joint_states. A node of its own context, spun on a thread."""

    def __init__(self, domain: int) -> None:
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node("behavior_controller", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.status = None
        self.positions = {}
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.node.create_subscription(AnimateBehaviourStatus, "/animateBehaviour/status", self._on_status, latched)
        self.node.create_subscription(JointState, "/joint_states", self._on_joint_states, 10)
        self.action = ActionClient(self.node, AnimateBehavior, "/animate_behavior")
        self.own_action = ActionClient(self.node, Animate, "/animateBehaviour/animate")
        self.stop_service = self.node.create_client(Trigger, "/animate_behavior/stop")
        self.set_activation = self.node.create_client(SetActivation, "/animateBehaviour/setActivation")
        self.feedback = []
        threading.Thread(target=self.executor.spin, daemon=True).start()

    def _on_status(self, message) -> None:
        self.status = message

    def _on_joint_states(self, message) -> None:
        self.positions = dict(zip(message.name, message.position))

    def part_states(self) -> dict:
        rows = self.status.parts if self.status is not None else []
        return {row.part: row.state for row in rows}

    def moving(self) -> set:
        return {part for part, state in self.part_states().items() if state == "animating"}

    def send(self, goal, action=None):
        """The goal handle once the node has answered; the time it was accepted."""
        action = action or self.action
        future = on_executor(self.node, lambda: action.send_goal_async(goal, feedback_callback=self.feedback.append))
        assert wait_until(future.done, 5.0), "no answer to the goal"
        return future.result(), time.monotonic()

    def result(self, handle, timeout: float = 15.0):
        """The result, and when it came."""
        future = on_executor(self.node, handle.get_result_async)
        assert wait_until(future.done, timeout), "no result"
        return future.result(), time.monotonic()

    def cancel(self, handle) -> None:
        on_executor(self.node, handle.cancel_goal_async)

    def stop(self):
        future = self.stop_service.call_async(Trigger.Request())
        assert wait_until(future.done, 5.0), "no answer from the stop service"
        return future.result()

    def parts_at_their_centres(self) -> bool:
        joints = [pair for part in ROBOT_PARTS for pair in zip(PARTS[part].joints, PARTS[part].centre)]
        return all(abs(self.positions[joint] - centre) <= CENTRE_TOLERANCE for joint, centre in joints)

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


class Run:
    def __init__(self, tmp) -> None:
        self.log_file = tmp / "animateBehaviour.log"
        self.simulator = start_program("cssr_system.ros2.simulated_pepper_node", DOMAIN, ["-p", "platform:=robot"])
        self.node = start_program("cssr_system.ros2.animate_behaviour_main", DOMAIN,
                                  ["-p", "platform:=robot", "-p", "logFile:=%s" % self.log_file,
                                   "-p", "randomSeed:=11"])
        self.tree = Tree(DOMAIN)
        assert self.tree.action.wait_for_server(timeout_sec=START_TIMEOUT), self.output()
        assert self.tree.stop_service.wait_for_service(timeout_sec=START_TIMEOUT), self.output()
        assert wait_until(lambda: {entry.fields["part"] for entry in self.entries(contract.CONTROLLER_CONNECTED)}
                          >= set(ROBOT_PARTS), START_TIMEOUT), self.output()
        assert wait_until(lambda: self.tree.positions, START_TIMEOUT), self.output(self.simulator)

    def entries(self, event: str, since: float = 0.0):
        if not self.log_file.exists():
            return []
        return [entry for entry in read_log(str(self.log_file))
                if entry.event == event and entry.timestamp.timestamp() >= since]

    def output(self, process=None) -> str:
        process = process or self.node
        return "still running" if process.poll() is None else process.communicate()[1]

    def close(self) -> int:
        self.tree.close()
        status = stop_program(self.node)
        stop_program(self.simulator)
        return status


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    run = Run(tmp_path_factory.mktemp("successor"))
    yield run
    assert run.close() == 0, "SIGINT: the node stops the robot and exits 0"


def settle_home(tree: Tree) -> None:
    """Between tests: nothing runs and every part is back at its centre."""
    assert tree.stop().success
    assert wait_until(lambda: tree.status is not None and not tree.status.enabled and
                      not set(tree.part_states().values()) - {"idle"}, 5.0)


def test_the_trees_goal_runs_beside_its_other_steps_then_its_stop_brings_every_part_home(run):
    tree, since = run.tree, time.time()
    handle, _ = tree.send(successor_goal("All", 0.5, 0))
    assert handle.accepted
    assert wait_until(lambda: tree.moving() == MOVES["All"], 3.0), tree.part_states()
    # The tree's other steps go on meanwhile: here, the same node's own service answers at once.
    future = tree.set_activation.call_async(SetActivation.Request(state="unknown"))
    assert wait_until(future.done, 2.0) and future.result().success == contract.REPLY_FAILURE
    assert wait_until(lambda: len(tree.feedback) >= 3, 4.0), "feedback at least once a second"
    feedback = [message.feedback for message in tree.feedback]
    assert all(message.is_running for message in feedback)
    assert [round(message.elapsed_time) for message in feedback[:3]] == [1, 2, 3]
    assert feedback[-1].current_limb == "right arm, left arm, right hand, left hand, leg, base"
    response = tree.stop()
    assert response.success
    result, _ = tree.result(handle)
    assert (result.status, result.result.success) == (GoalStatus.STATUS_SUCCEEDED, True), result.result.message
    assert result.result.total_duration >= 3.0
    assert not tree.status.enabled
    assert wait_until(lambda: not set(tree.part_states().values()) - {"idle"}, 3.0), "every part back home"
    assert wait_until(tree.parts_at_their_centres, 2.0), tree.positions
    ends = [entry.fields for entry in run.entries(contract.ANIMATE_GOAL, since)
            if entry.fields["outcome"] != "accepted"]
    assert [(fields["reason"], fields["by"]) for fields in ends] == [("stopped", "/animate_behavior/stop")]


@pytest.mark.parametrize("behavior_type", ["body", "hands", "arms", "rotation", "All"])
def test_each_behavior_type_moves_only_its_parts(run, behavior_type):
    tree = run.tree
    handle, _ = tree.send(successor_goal(behavior_type, 0.5, 0))
    assert handle.accepted
    assert wait_until(lambda: tree.moving() == MOVES[behavior_type], 3.0), tree.part_states()
    time.sleep(0.5)
    assert tree.moving() == MOVES[behavior_type], tree.part_states()
    settle_home(tree)
    assert tree.result(handle)[0].result.success, "ended by the stop service"


@pytest.mark.parametrize("behavior_type, selected_range", [("dance", 0.5), ("All", 1.5), ("All", -0.1)])
def test_a_bad_goal_is_rejected_and_nothing_moves(run, behavior_type, selected_range):
    tree = run.tree
    handle, _ = tree.send(successor_goal(behavior_type, selected_range, 0))
    assert not handle.accepted
    time.sleep(0.3)
    assert not tree.status.enabled and not tree.moving()


def test_a_cancel_ends_the_goal_with_success_false_and_the_robot_stopped(run):
    tree = run.tree
    handle, _ = tree.send(successor_goal("All", 0.5, 0))
    assert wait_until(lambda: tree.moving() == MOVES["All"], 3.0)
    tree.cancel(handle)
    result, _ = tree.result(handle)
    assert (result.status, result.result.success) == (GoalStatus.STATUS_CANCELED, False)
    assert wait_until(lambda: not tree.status.enabled, 1.0)
    assert wait_until(lambda: not set(tree.part_states().values()) - {"idle"}, 3.0)


def test_a_newer_goal_replaces_the_older_without_a_stop(run):
    tree = run.tree
    first, _ = tree.send(successor_goal("All", 0.5, 0))
    assert wait_until(lambda: tree.moving() == MOVES["All"], 3.0)
    second, _ = tree.send(successor_goal("arms", 0.8, 0))
    replaced, _ = tree.result(first)
    assert (replaced.status, replaced.result.success) == (GoalStatus.STATUS_ABORTED, False)
    assert wait_until(lambda: tree.moving() == MOVES["arms"], 3.0), tree.part_states()
    assert sorted(tree.status.moving_parts) == ["arms"] and tree.status.settings_by == "/behavior_controller"
    settle_home(tree)


def test_a_home_goal_brings_every_part_to_its_centre_then_succeeds(run):
    tree = run.tree
    animating, _ = tree.send(successor_goal("All", 1.0, 0))
    assert wait_until(lambda: tree.moving() == MOVES["All"], 3.0)
    time.sleep(1.5)
    home, _ = tree.send(successor_goal("home", 0.5, 0))
    result, _ = tree.result(home)
    assert (result.status, result.result.success) == (GoalStatus.STATUS_SUCCEEDED, True), result.result.message
    assert not set(tree.part_states().values()) - {"idle"}
    assert wait_until(tree.parts_at_their_centres, 1.0), tree.positions
    assert tree.result(animating)[0].result.success is False, "the home goal replaced it"


def own_goal(style: str, duration: float) -> Animate.Goal:
    goal = Animate.Goal()
    goal.style, goal.intensity, goal.duration = style, 1.0, duration
    return goal


@pytest.mark.parametrize("action, style", [("successor", "random"), ("own", "random"), ("own", "breathing")])
def test_a_goal_with_a_duration_ends_on_time_every_part_at_its_centre_also_when_it_replaced_another(
        run, action, style):
    """At intensity 1 and the widest range the parts are far from their centres and moving when the duration ends;
    the goal that is timed replaced another one a moment before."""
    tree = run.tree
    send = {"successor": lambda seconds: tree.send(successor_goal("All", 1.0, seconds)),
            "own": lambda seconds: tree.send(own_goal(style, float(seconds)), tree.own_action)}[action]
    first, _ = send(0)
    assert wait_until(lambda: tree.moving() == MOVES["All"], 3.0)
    time.sleep(1.0)
    handle, accepted = send(4)
    assert handle.accepted
    result, ended = tree.result(handle)
    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert ended - accepted == pytest.approx(4.0, abs=ON_TIME), "the client's time from acceptance to result"
    ran = result.result.total_duration if action == "successor" else result.result.animated
    assert ran == pytest.approx(4.0, abs=ON_TIME)
    assert not set(tree.part_states().values()) - {"idle"}, "every part back"
    assert tree.parts_at_their_centres(), tree.positions
    assert tree.result(first)[0].status == GoalStatus.STATUS_ABORTED
