"""`make soak ROS=1` (doc/soak.md): the ROS 1 driver of a soak. A master of its own, the simulated Pepper and the
node as processes of the run, and this process's clients: setActivation, dynamic_reconfigure, the animate action and
another node's gesture on the right arm. The run itself (schedule, sampling, figures) is cssr_system.soak's.

python3 -m cssr_system.ros1.soak_driver --minutes 60 --warm-up 10 --folder DIR --json FILE
"""
import os
import sys
import threading
import xmlrpc.client

import actionlib
import dynamic_reconfigure.client
import rosgraph
import rospy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import load_configuration, shipped_configuration_path
from cssr_system.animate_behaviour.configuration import topic_file_path
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.demo.gesture import GESTURE_PART
from cssr_system.msg import AnimateAction, AnimateGoal
from cssr_system.ros1.gesture_player import GesturePlayer
from cssr_system.ros1.trajectory_client import goal_state_name
from cssr_system.soak.processes import (BUSY, PLATFORM, SIMULATOR, Program, arguments, free_port, node_environment,
                                        soak, wait_until)
from cssr_system.srv import setActivation

NODE = "/" + contract.NODE_NAME
CALL_TIMEOUT = 5.0  # s


class Ros1Driver:
    def __init__(self, folder: str) -> None:
        self.folder = folder
        self.log_file = os.path.join(folder, "node.log")
        self.output_file = os.path.join(folder, "node.out")
        self.simulator = Program(["rosrun", "cssr_system", "simulatedPepper.py"]
                                 + ["_%s:=%s" % item for item in SIMULATOR.items()],
                                 os.path.join(folder, "simulatedPepper.out"))
        self.node = Program(["rosrun", "cssr_system", "animateBehaviour.py", "_platform:=" + PLATFORM,
                             "_logFile:=" + self.log_file] + ["_%s:=%s" % item for item in BUSY.items()],
                            self.output_file, node_environment(folder))
        self._ended = None
        self._goals = {}  # name -> actionlib goal handle
        self._lock = threading.Lock()
        self._pid = None

    def attach(self, ended) -> None:
        self._ended = ended

    def start(self) -> None:
        self.simulator.start()
        self.node.start()
        if not wait_until(lambda: contract.SERVICE_PATH in services(), 30):
            raise SystemExit("soak: the node did not offer %s within 30 s (see %s)"
                             % (contract.SERVICE_PATH, self.output_file))
        self._pid = xmlrpc.client.ServerProxy(rosgraph.Master("/soak").lookupNode(NODE)).getPid("/soak")[2]
        self._activation = rospy.ServiceProxy(contract.SERVICE_PATH, setActivation, persistent=True)
        self._settings = dynamic_reconfigure.client.Client(NODE, timeout=30)
        self._animate = actionlib.ActionClient(NODE + "/" + contract.ANIMATE_ACTION, AnimateAction)
        self._animate.wait_for_server(rospy.Duration(30))
        configuration = load_configuration(shipped_configuration_path(), {"platform": PLATFORM})
        action = dict(load_topic_map(topic_file_path(configuration)).topics)[GESTURE_PART]
        self._gesture = GesturePlayer(rospy.resolve_name(action))
        self._gesture.client.wait_for_server(rospy.Duration(30))

    def node_pid(self) -> int:
        return self._pid

    def activate(self, state: str) -> bool:
        return self._activation(state).success == contract.REPLY_SUCCESS

    def set_setting(self, name: str, value) -> bool:
        return self._settings.update_configuration({name: value}) is not None

    def send_animate(self, goal: str, detail: dict) -> None:
        message = AnimateGoal(parts=list(detail["parts"]), intensity=detail["intensity"],
                              duration=detail["duration"])

        def transition(handle) -> None:
            if handle.get_comm_state() == actionlib.CommState.DONE:
                result = handle.get_result()
                with self._lock:
                    self._goals.pop(goal, None)
                self._ended(goal, goal_state_name(handle.get_goal_status()),
                            result.reason if result is not None else "")
        with self._lock:
            self._goals[goal] = self._animate.send_goal(message, transition_cb=transition)

    def cancel_animate(self, goal: str) -> None:
        with self._lock:
            handle = self._goals.get(goal)
        if handle is not None:
            handle.cancel()

    def play_gesture(self, goal: str) -> None:
        def done(state: int, _result) -> None:
            self._ended(goal, goal_state_name(state), "")
        self._gesture.client.send_goal(self._gesture.goal(), done_cb=done)

    def restart_controllers(self) -> None:
        self.simulator.stop()
        self.simulator.start()

    def stop(self) -> None:
        """The node disabled and stopped, then the simulated Pepper, also after a failure of the run."""
        try:
            self.activate(contract.DISABLED)
        except Exception as error:  # noqa: BLE001 - the processes are stopped all the same
            print("soak: the last disable failed: %s" % error)
        self.node.stop()
        self.simulator.stop()


def services() -> set:
    try:
        return {name for name, _ in rosgraph.Master("/soak").getSystemState()[2]}
    except Exception:  # noqa: BLE001 - the master is asked again
        return set()


def main(argv=None) -> int:
    options = arguments(sys.argv[1:] if argv is None else argv)
    os.makedirs(options.folder, exist_ok=True)
    port = free_port()
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % port
    os.environ.setdefault("ROS_HOME", options.folder)
    master = Program(["roscore", "-p", str(port)], os.path.join(options.folder, "roscore.out")).start()
    driver = Ros1Driver(options.folder)
    try:
        wait_until(rosgraph.is_master_online, 30)
        rospy.init_node("soak", disable_signals=True)
        driver.start()
        return soak(driver, options, "1")
    finally:
        driver.stop()
        rospy.signal_shutdown("soak done")
        master.stop()


if __name__ == "__main__":
    sys.exit(main())
