"""The gesture race on ROS 2 (doc/soak.md, "The gesture race"; the race itself is cssr_system.soak.gesture_race), the
twin of cssr_system.ros1.gesture_race: the simulated Pepper and the node on this process's ROS 2 domain
(ROS_DOMAIN_ID), and this process as the other node, with a gesture client and a status subscription per
controller.

python3 -m cssr_system.ros2.gesture_race --gestures 100 --style random --folder DIR --json FILE
"""
import os
import sys
import threading
import time
import uuid

import rclpy
from action_msgs.msg import GoalStatus, GoalStatusArray
from control_msgs.action import FollowJointTrajectory
from cssr_system_interfaces.srv import SetActivation
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_action_status_default
from rclpy.signals import SignalHandlerOptions
from trajectory_msgs.msg import JointTrajectoryPoint
from unique_identifier_msgs.msg import UUID

from cssr_system.animate_behaviour import contract
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros2.program import call
from cssr_system.ros2.rclpy_compat import ACTION_STATUS
from cssr_system.ros2.soak_driver import ros_arguments
from cssr_system.ros2.trajectory_client import STATE_NAMES, duration
from cssr_system.soak import gesture_race
from cssr_system.soak.gesture_race import PartRace, gesture_points
from cssr_system.soak.processes import PLATFORM, SIMULATOR, Program, robot_topics

START_TIMEOUT = 30.0  # s
RUNNING = (GoalStatus.STATUS_ACCEPTED, GoalStatus.STATUS_EXECUTING)


def gesture_goal(part: str) -> FollowJointTrajectory.Goal:
    goal = FollowJointTrajectory.Goal()
    goal.trajectory.joint_names = list(PARTS[part].joints)
    zeros = [0.0] * len(PARTS[part].joints)
    goal.trajectory.points = [JointTrajectoryPoint(positions=list(positions), velocities=zeros, accelerations=zeros,
                                                   time_from_start=duration(at))
                              for at, positions in gesture_points(part)]
    return goal


class Ros2Race:
    def __init__(self, node: Node, folder: str, parameters: dict) -> None:
        self.ros = node
        self.simulator = Program([sys.executable, "-m", "cssr_system.ros2.simulated_pepper_node"]
                                 + ros_arguments(SIMULATOR), os.path.join(folder, "simulatedPepper.out"))
        self.node = Program([sys.executable, "-m", "cssr_system.ros2.animate_behaviour_main"]
                            + ros_arguments(dict(parameters, platform=PLATFORM,
                                                 logFile=os.path.join(folder, "node.log"))),
                            os.path.join(folder, "node.out"))
        self._activation = node.create_client(SetActivation, "/" + contract.NODE_NAME + "/" + contract.SET_ACTIVATION)
        self.races = {}
        self.clients = {}
        self._gestures = set()  # the ids of this process's goals
        self._lock = threading.Lock()

    def start(self, parts) -> None:
        self.simulator.start()
        self.node.start()
        if not self._activation.wait_for_service(timeout_sec=START_TIMEOUT):
            raise SystemExit("gesture race: the node's service did not come within %g s" % START_TIMEOUT)
        topics = robot_topics()
        for part in parts:
            action = self.ros.resolve_topic_name(topics[part])
            self.races[part] = PartRace(part)
            self.clients[part] = ActionClient(self.ros, FollowJointTrajectory, action)
            if not self.clients[part].wait_for_server(timeout_sec=START_TIMEOUT):
                raise SystemExit("gesture race: no %s within %g s" % (action, START_TIMEOUT))
            self.ros.create_subscription(GoalStatusArray, action + ACTION_STATUS,
                                         lambda message, part=part: self._status(message, part),
                                         qos_profile_action_status_default)

    def _status(self, message: GoalStatusArray, part: str) -> None:
        now = time.monotonic()
        running = [bytes(status.goal_info.goal_id.uuid) for status in message.status_list if status.status in RUNNING]
        with self._lock:
            ours = [goal_id in self._gestures for goal_id in running]
        self.races[part].status_list(now, [goal_id.hex() for goal_id, mine in zip(running, ours) if not mine],
                                     any(ours))

    def send(self, part: str) -> None:
        goal_id = uuid.uuid4().bytes
        with self._lock:
            self._gestures.add(goal_id)

        def ended(future) -> None:
            self.races[part].ended(STATE_NAMES.get(future.result().status, "?"), time.monotonic())

        def accepted(future) -> None:
            handle = future.result()
            if not handle.accepted:
                self.races[part].ended("REJECTED", time.monotonic())
                return
            handle.get_result_async().add_done_callback(ended)

        def send() -> None:  # on the executor's thread: rclpy's action client registers a request after sending it
            self.clients[part].send_goal_async(gesture_goal(part), goal_uuid=UUID(uuid=list(goal_id))) \
                .add_done_callback(accepted)
        self.ros.executor.create_task(send)

    def activate(self, state: str) -> None:
        call(self._activation, SetActivation.Request(state=state), START_TIMEOUT)

    def stop(self) -> None:
        self.node.stop()
        self.simulator.stop()


def main(argv=None) -> int:
    options = gesture_race.arguments(sys.argv[1:] if argv is None else argv)
    os.makedirs(options.folder, exist_ok=True)
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node("gesture_race")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    race = Ros2Race(node, options.folder, gesture_race.node_parameters(options.style))
    try:
        return gesture_race.run(race, options, "2")
    finally:
        race.stop()
        executor.shutdown()
        spinner.join(5.0)
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
