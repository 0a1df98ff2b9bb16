"""The gesture race on ROS 1 (doc/soak.md, "The gesture race"; the race itself is cssr_system.soak.gesture_race): a
master of its own, the simulated Pepper and the node animating in the soak's busy configuration, and this process as
the other node, with a gesture client and a status subscription per controller.

python3 -m cssr_system.ros1.gesture_race --gestures 100 --style random --folder DIR --json FILE
"""
import os
import sys
import time

import actionlib
import rosgraph
import rospy
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros1.trajectory_client import goal_state_name
from cssr_system.soak import gesture_race
from cssr_system.soak.gesture_race import PartRace, gesture_points
from cssr_system.soak.processes import PLATFORM, SIMULATOR, Program, free_port, robot_topics, wait_until
from cssr_system.srv import setActivation

START_TIMEOUT = 30.0  # s
RUNNING = (GoalStatus.PENDING, GoalStatus.ACTIVE)


def gesture_goal(part: str) -> FollowJointTrajectoryGoal:
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(PARTS[part].joints)
    zeros = [0.0] * len(PARTS[part].joints)
    goal.trajectory.points = [JointTrajectoryPoint(positions=list(positions), velocities=zeros, accelerations=zeros,
                                                   time_from_start=rospy.Duration.from_sec(at))
                              for at, positions in gesture_points(part)]
    return goal


class Ros1Race:
    def __init__(self, folder: str, parameters: dict) -> None:
        self.simulator = Program(["rosrun", "cssr_system", "simulatedPepper.py"]
                                 + ["_%s:=%s" % item for item in SIMULATOR.items()],
                                 os.path.join(folder, "simulatedPepper.out"))
        self.node = Program(["rosrun", "cssr_system", "animateBehaviour.py", "_platform:=" + PLATFORM,
                             "_logFile:=" + os.path.join(folder, "node.log")]
                            + ["_%s:=%s" % item for item in parameters.items()], os.path.join(folder, "node.out"))
        self.races = {}
        self.clients = {}
        self._own = rospy.get_caller_id() + "-"

    def start(self, parts) -> None:
        self.simulator.start()
        self.node.start()
        rospy.wait_for_service(contract.SERVICE_PATH, START_TIMEOUT)
        topics = robot_topics()
        for part in parts:
            action = "/" + topics[part]
            self.races[part] = PartRace(part)
            self.clients[part] = actionlib.SimpleActionClient(action, FollowJointTrajectoryAction)
            if not self.clients[part].wait_for_server(rospy.Duration(START_TIMEOUT)):
                raise SystemExit("gesture race: no %s within %g s" % (action, START_TIMEOUT))
            rospy.Subscriber(action + "/status", GoalStatusArray, self._status, callback_args=part, queue_size=10)

    def _status(self, message: GoalStatusArray, part: str) -> None:
        now = time.monotonic()
        running = [status.goal_id.id for status in message.status_list if status.status in RUNNING]
        self.races[part].status_list(now, [goal_id for goal_id in running if not goal_id.startswith(self._own)],
                                     any(goal_id.startswith(self._own) for goal_id in running))

    def send(self, part: str) -> None:
        def done(state: int, _result) -> None:
            self.races[part].ended(goal_state_name(state), time.monotonic())
        self.clients[part].send_goal(gesture_goal(part), done_cb=done)

    def activate(self, state: str) -> None:
        rospy.ServiceProxy(contract.SERVICE_PATH, setActivation)(state)

    def stop(self) -> None:
        self.node.stop()
        self.simulator.stop()


def main(argv=None) -> int:
    options = gesture_race.arguments(sys.argv[1:] if argv is None else argv)
    os.makedirs(options.folder, exist_ok=True)
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % free_port()
    os.environ.setdefault("ROS_HOME", options.folder)
    master = Program(["roscore", "-p", os.environ["ROS_MASTER_URI"].rsplit(":", 1)[1]],
                     os.path.join(options.folder, "roscore.out")).start()
    race = None
    try:
        wait_until(rosgraph.is_master_online, START_TIMEOUT)
        rospy.init_node("gesture_race", disable_signals=True)
        race = Ros1Race(options.folder, gesture_race.node_parameters(options.style))
        return gesture_race.run(race, options, "1")
    finally:
        if race is not None:
            race.stop()
        rospy.signal_shutdown("gesture race done")
        master.stop()


if __name__ == "__main__":
    sys.exit(main())
