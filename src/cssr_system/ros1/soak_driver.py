"""`make soak ROS=1` (doc/soak.md): the ROS 1 driver of a soak. A master of its own, the simulated Pepper and the
node as processes of the run, and this process's clients: setActivation, dynamic_reconfigure, the animate action,
another node's gesture on the right arm and the base's listener. From half-way through the warm-up a second robot
(in namespace robot2: its simulated Pepper and node) runs on a simulated clock that this process publishes, under the
same churn, and is judged on its own. The run itself (schedule, sampling, figures) is cssr_system.soak's.

python3 -m cssr_system.ros1.soak_driver --minutes 60 --warm-up 10 --folder DIR --json FILE
"""
import os
import sys
import threading
import time
import xmlrpc.client
from typing import Optional

import actionlib
import dynamic_reconfigure.client
import rosgraph
import rospy
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.demo.gesture import GESTURE_PART
from cssr_system.msg import AnimateAction, AnimateGoal
from cssr_system.ros1.gesture_player import GesturePlayer
from cssr_system.ros1.trajectory_client import goal_state_name
from cssr_system.soak.processes import (BUSY, PLATFORM, SIMULATOR, Program, arguments, base_remapping, free_port,
                                        heap_file, node_environment, robot_topics, soak, wait_until)
from cssr_system.srv import setActivation

START_TIMEOUT = 30.0  # s
USE_SIM_TIME = "/use_sim_time"
SIM_CLOCK_NAMESPACE = "robot2"
CLOCK_FACTOR = 0.8  # the simulated clock's speed against the wall clock's, as a simulation a little slower than real
CLOCK_START = 1000.0  # s: far from the wall clock, so that a time taken from the wrong clock shows
CLOCK_PERIOD = 0.01  # s of wall time between /clock messages
# One process starts at a time: a ROS 1 node reads /use_sim_time once, as it starts, and the parameter is set only
# while the simulated clock's robot starts.
STARTING = threading.Lock()


def graph() -> list:
    """The master's [publishers, subscribers, services] ([] when it does not answer)."""
    try:
        return rosgraph.Master("/soak").getSystemState()
    except Exception:  # noqa: BLE001 - the master is asked again
        return []


def services() -> set:
    state = graph()
    return {name for name, _ in state[2]} if state else set()


def registered(node: str) -> bool:
    """Whether `node` has registered a topic other than /rosout: rospy's init_node has returned, after reading
    /use_sim_time (a node on a simulated clock subscribes to /clock as it reads it)."""
    state = graph()
    return any(node in nodes for topics in state[:2] for topic, nodes in topics if topic != "/rosout")


class Ros1Driver:
    """One robot's processes and this process's clients of them; `namespace`: the robot's ("" for the root),
    `sim_time`: its processes start with /use_sim_time."""

    def __init__(self, folder: str, namespace: str = "", sim_time: bool = False) -> None:
        os.makedirs(folder, exist_ok=True)
        self.folder, self.sim_time = folder, sim_time
        self.prefix = "/" + namespace if namespace else ""
        self.log_file = os.path.join(folder, "node.log")
        self.output_file = os.path.join(folder, "node.out")
        self.heap_file = heap_file(folder)
        where = ["__ns:=" + namespace] if namespace else []
        self.simulator = Program(["rosrun", "cssr_system", "simulatedPepper.py", base_remapping()] + where
                                 + ["_%s:=%s" % item for item in SIMULATOR.items()],
                                 os.path.join(folder, "simulatedPepper.out"))
        self.node = Program(["rosrun", "cssr_system", "animateBehaviour.py", "_platform:=" + PLATFORM,
                             "_logFile:=" + self.log_file] + where + ["_%s:=%s" % item for item in BUSY.items()],
                            self.output_file, node_environment(folder))
        self._ended = None
        self._goals = {}  # name -> actionlib goal handle
        self._lock = threading.Lock()
        self._pid = None
        self._listener: Optional[rospy.Subscriber] = None

    def attach(self, ended) -> None:
        self._ended = ended

    def _start(self, program: Program, node: str) -> None:
        """Starts `program` (ROS node `node`) and waits until it has read /use_sim_time, set for it alone."""
        with STARTING:
            if self.sim_time:
                rospy.set_param(USE_SIM_TIME, True)
            try:
                program.start()
                if not wait_until(lambda: registered(node), START_TIMEOUT):
                    raise SystemExit("soak: %s did not start within %g s (see %s)"
                                     % (node, START_TIMEOUT, program.output_file))
            finally:
                if self.sim_time:
                    rospy.delete_param(USE_SIM_TIME)

    def start(self) -> None:
        name = self.prefix + "/" + contract.NODE_NAME
        self._start(self.simulator, self.prefix + "/simulatedPepper")
        self._start(self.node, name)
        if not wait_until(lambda: self.prefix + contract.SERVICE_PATH in services(), START_TIMEOUT):
            raise SystemExit("soak: the node did not offer %s within %g s (see %s)"
                             % (self.prefix + contract.SERVICE_PATH, START_TIMEOUT, self.output_file))
        self._pid = xmlrpc.client.ServerProxy(rosgraph.Master("/soak").lookupNode(name)).getPid("/soak")[2]
        self._activation = rospy.ServiceProxy(self.prefix + contract.SERVICE_PATH, setActivation, persistent=True)
        self._settings = dynamic_reconfigure.client.Client(name, timeout=START_TIMEOUT)
        self._animate = actionlib.ActionClient(name + "/" + contract.ANIMATE_ACTION, AnimateAction)
        self._animate.wait_for_server(rospy.Duration(START_TIMEOUT))
        topics = robot_topics()
        self._gesture = GesturePlayer(self.prefix + "/" + topics[GESTURE_PART])
        self._gesture.client.wait_for_server(rospy.Duration(START_TIMEOUT))
        self._base = self.prefix + "/" + topics[WHEELS_KEY]
        self.base_listener(True)

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
        self._start(self.simulator, self.prefix + "/simulatedPepper")

    def base_listener(self, present: bool) -> None:
        """A subscriber of the base's topic, as a base driver's, comes or goes."""
        if present and self._listener is None:
            self._listener = rospy.Subscriber(self._base, Twist, lambda message: None, queue_size=1)
        elif not present and self._listener is not None:
            self._listener.unregister()
            self._listener = None

    def stop(self) -> None:
        """The node disabled and stopped, then the simulated Pepper, also after a failure of the run."""
        if self.node.running():
            try:
                self.activate(contract.DISABLED)
            except Exception as error:  # noqa: BLE001 - the processes are stopped all the same
                print("soak: the last disable failed: %s" % error)
        self.node.stop()
        self.simulator.stop()


class SimulatedClock:
    """/clock from this process: CLOCK_START, then CLOCK_FACTOR seconds for each second of wall time."""

    def __init__(self) -> None:
        self._publisher = rospy.Publisher("/clock", Clock, queue_size=1)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._run, name="clock", daemon=True)

    def _run(self) -> None:
        started = time.monotonic()
        while not self._stop.wait(CLOCK_PERIOD):
            self._publisher.publish(Clock(clock=rospy.Time.from_sec(
                CLOCK_START + CLOCK_FACTOR * (time.monotonic() - started))))

    def stop(self) -> None:
        self._stop.set()


class SimulatedClockRobot:
    """The second robot, on the simulated clock from half-way through the warm-up to the end of the run, judged apart
    with a warm-up of its own (its result beside the run's: <json>-sim-clock.json)."""

    def __init__(self, options) -> None:
        self.options = options
        self.driver = Ros1Driver(os.path.join(options.folder, "sim-clock"), SIM_CLOCK_NAMESPACE, sim_time=True)
        self.clock: Optional[SimulatedClock] = None
        self.status: Optional[int] = None
        self._cancelled = threading.Event()
        self.thread = threading.Thread(target=self._run, name="simulated-clock robot", daemon=True)

    def _run(self) -> None:
        # Half-way through the first robot's warm-up: its restarts then fall half-way between the first robot's (one
        # process starts at a time, so two restarts at once would keep a simulated Pepper away longer).
        start = 30.0 * self.options.warm_up
        if self._cancelled.wait(start):
            return
        try:
            self.clock = SimulatedClock()
            self.clock.thread.start()
            self.driver.start()
            self.status = soak(self.driver, self.options, "1, simulated clock", start,
                               self.options.json[:-len(".json")] + "-sim-clock.json",
                               ", namespace %s, simulated clock at %g of real time" % (SIM_CLOCK_NAMESPACE,
                                                                                       CLOCK_FACTOR))
        except BaseException as error:  # noqa: BLE001 - said in one line; the run's status says it failed
            print("soak: the simulated clock's robot failed: %s" % error, flush=True)
            self.status = 1

    def stop(self) -> None:
        self._cancelled.set()
        self.driver.stop()
        if self.clock is not None:
            self.clock.stop()


def main(argv=None) -> int:
    options = arguments(sys.argv[1:] if argv is None else argv)
    os.makedirs(options.folder, exist_ok=True)
    port = free_port()
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % port
    os.environ.setdefault("ROS_HOME", options.folder)
    master = Program(["roscore", "-p", str(port)], os.path.join(options.folder, "roscore.out")).start()
    driver = Ros1Driver(options.folder)
    beside = SimulatedClockRobot(options) if options.sim_clock else None
    try:
        wait_until(rosgraph.is_master_online, START_TIMEOUT)
        rospy.init_node("soak", disable_signals=True)
        driver.start()
        if beside is not None:
            beside.thread.start()
        status = soak(driver, options, "1")
        if beside is not None:
            beside.thread.join()
            status = status or beside.status or 0
        return status
    finally:
        if beside is not None:
            beside.stop()
        driver.stop()
        rospy.signal_shutdown("soak done")
        master.stop()


if __name__ == "__main__":
    sys.exit(main())
