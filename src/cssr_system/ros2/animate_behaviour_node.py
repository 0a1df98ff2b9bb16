"""The animateBehaviour node's ROS 2 side (README: "ROS 2"): it makes the event log, the parameters, the status
publisher, the services, the action clients or the JointAngles publisher, the base publisher and the
subscriptions, and hands them to the supervisor (core/supervisor.py), which owns the motion state, as the ROS 1
node (ros1/animate_behaviour_node.py) does."""
import collections
import os
import threading
from typing import Callable, Deque, Dict, Optional, Set

from geometry_msgs.msg import Twist
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import JOINT_ANGLES_ACTUATION, Configuration, configuration_items
from cssr_system.animate_behaviour.console import HEARTBEAT_PERIOD, console
from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC, NODE_NAME
from cssr_system.animate_behaviour.event_log import (BackgroundLog, EventLog, claim_log_file, default_log_path,
                                                     node_log_file_name)
from cssr_system.animate_behaviour.topics import joint_angles_topic
from cssr_system.core.activation import Activation
from cssr_system.core.base_stream import BaseStream
from cssr_system.core.controller_watcher import ControllerWatcher
from cssr_system.core.conversation import configured_sources
from cssr_system.core.events import Shutdown
from cssr_system.core.joint_angle_stream import JointAngleStream
from cssr_system.core.joint_states import JointStateCache, JointStateFeed, SubscriptionSwitch
from cssr_system.core.part_stream import PartStream
from cssr_system.core.problems import Problems
from cssr_system.core.supervisor import Supervisor
from cssr_system.package_files import package_dir, package_version
from cssr_system.ros2.animate_action import AnimateActionServer
from cssr_system.ros2.conversation_watch import ConversationWatch
from cssr_system.ros2.foreign_watch import ForeignCommandWatch, twist_key
from cssr_system.ros2.joint_angles_topic import JointAnglesTopic
from cssr_system.ros2.parameters import NodeParameters
from cssr_system.ros2.rclpy_compat import subscribed_by_another_node
from cssr_system.ros2.services import ActivationServices
from cssr_system.ros2.status import StatusPublisher
from cssr_system.ros2.successor_action import SuccessorActionServer
from cssr_system.ros2.time_conversion import clock_seconds, seconds_of
from cssr_system.ros2.trajectory_client import TrajectoryClient

JOINT_STATES_QUEUE = 1  # only the latest /joint_states message matters
BASE_QUEUE = 10


class Subscription:
    """A subscription the joint-state switch can end (`unregister`, as on ROS 1). It has a callback group of its own:
    a callback group keeps a reference to every subscription ever added to it (ros2/rclpy#1356), so the node's
    default group would grow with each subscription made and ended."""

    def __init__(self, node, message_type, topic: str, callback, queue: int, on_executor) -> None:
        self._node = node
        self._subscription = node.create_subscription(message_type, topic, callback, queue,
                                                      callback_group=MutuallyExclusiveCallbackGroup())
        self._on_executor = on_executor

    def unregister(self) -> None:
        """Ends the subscription on the executor's thread: rclpy's executor fails (InvalidHandle) when another
        thread destroys a subscription while it builds its wait set."""
        self._on_executor(lambda: self._node.destroy_subscription(self._subscription))


class ExecutorThread:
    """The thread that spins the node's executor (given the node before the node's clients are made), and the work
    that must run on it, in the order it was handed over (rclpy runs its own tasks newest first).

    The work runs as the callback of a guard condition, not as an executor task: rclpy runs its tasks before it
    waits for new messages, a guard condition's callback after the subscriptions ready with it. So a goal's last look
    (ros2/trajectory_client.py) sees the controllers' status lists that came while the goal was handed over."""

    def __init__(self, node, report_error: Callable[[str, Exception], None]) -> None:
        self._node = node
        self._report_error = report_error
        self._waiting: Deque[Callable[[], None]] = collections.deque()
        self._wake = node.create_guard_condition(self._run_waiting)
        self.thread: Optional[threading.Thread] = None

    def spin(self, executor) -> None:
        self.thread = threading.Thread(target=executor.spin, name="executor", daemon=True)
        self.thread.start()

    def ended(self) -> bool:
        return self.thread is not None and not self.thread.is_alive()

    def run(self, work: Callable[[], None]) -> None:
        """Runs `work` on the executor's thread, queued until it spins; at once on this thread if the executor has
        ended, so that a stop still goes out."""
        executor = self._node.executor
        if executor is None or self.ended():
            work()
            return
        self._waiting.append(work)
        self._wake.trigger()

    def run_pending(self) -> None:
        """Runs the work handed over so far now, when called on the executor's thread (by one of its callbacks);
        elsewhere the executor runs it, as handed over."""
        if threading.current_thread() is self.thread:
            self._run_waiting()

    def _run_waiting(self) -> None:
        while self._waiting:
            work = self._waiting.popleft()
            try:
                work()
            except Exception as error:  # raised here, it would end the executor
                self._report_error("executor", error)


class AnimateBehaviourNode:
    """The node on ROS 2: its interfaces (on the rclpy `node`), and the supervisor that drives the streams."""

    def __init__(self, node) -> None:
        self.node = node
        self.version = package_version()
        self.parameters = NodeParameters(node, self._post)
        # Named after the node's resolved name, and never shared with another running instance (README: "Several
        # robots").
        name = node.get_fully_qualified_name()
        default_log_file = default_log_path(package_dir(), os.environ.get("ROS_HOME"), node_log_file_name(name))
        log_file, clash = claim_log_file(self.parameters.log_file or default_log_file, name)
        if clash:
            console.warning(clash)
        self.log = BackgroundLog(EventLog(log_file))
        problems = Problems(self.log)  # one console line and one log line each
        self.report_error, self.report_problem = problems.error, problems.bad_input
        # ROS time (simulated with use_sim_time, as ros2_control's controllers): the streams' deadlines.
        self.clock = lambda: clock_seconds(node)
        self.own_goals: Set[bytes] = set()  # each client's latest goal ids (REMEMBERED_GOALS)
        joint_states = node.resolve_topic_name(JOINT_STATES_TOPIC)  # in the node's namespace, remapped where asked
        self.joint_states = JointStateCache(self.clock, lambda text: self.report_problem("joint_states", text),
                                            joint_states)
        self._switch = SubscriptionSwitch(self._subscribe_joint_states, None, self.report_error, joint_states)
        self.feed = JointStateFeed(self.joint_states, self._switch, console.debug)
        self.status = StatusPublisher(node)
        self.action = AnimateActionServer(node, self.parameters.load, self._post, self.report_error)
        self.successor_action = SuccessorActionServer(node, self.parameters.load, self._post, self.report_error)
        # Goals leave from the executor's thread (TrajectoryClient): at an enable each goes as soon as it is planned.
        self.supervisor = Supervisor(self.clock, self.log, self._make_part, self._make_base, self.status.publish,
                                     self.feed, self.report_error, self.action, sends_on_another_thread=True)
        self._watcher = ControllerWatcher(self.supervisor.controlled_streams, self._post, self.log,
                                          self.supervisor.stopped, self.report_error)
        self.watch = ForeignCommandWatch(node, self.own_goals, self._post, self.clock, self.report_error,
                                         self._watcher.status_seen)
        self.conversation = ConversationWatch(node, self._post, self.report_error)  # README: "Modes"
        self.joint_angles: Optional[JointAnglesTopic] = None
        self.services: Optional[ActivationServices] = None
        self.executor_thread = ExecutorThread(node, self.report_error)

    def start(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        self.log.write(contract.CONFIGURATION_LOADED, file=config_file, items=configuration_items(config))
        self._choose_actuation(config, topics)
        self.supervisor.set_up(config, topics, self.conversation.watch(configured_sources(config)))
        self._switch.start()
        self.supervisor.start()
        self._watcher.thread.start()
        activation = Activation(self._post, self.log, self.parameters.load, lambda: self.parameters.config_file)
        self.services = ActivationServices(self.node, activation, self.log, self.executor_thread.run_pending)
        self.action.start()
        self.successor_action.start()
        console.info("%s: services %s and %s ready; the successor's action %s and %s too.", NODE_NAME,
                     self.node.resolve_service_name("~/" + contract.SET_ACTIVATION),
                     self.node.resolve_service_name("~/" + contract.SET_ENABLED), self.successor_action.name,
                     self.services.stop_service)
        self.node.create_timer(HEARTBEAT_PERIOD, lambda: console.info("%s: running.", NODE_NAME))

    def _post(self, event) -> None:
        self.supervisor.events.put(event)

    def _choose_actuation(self, config: Configuration, topics: Dict[str, str]) -> None:
        """The actuation of this run: the JointAngles topic is published on with joint_angles, and watched for
        other nodes' calls either way."""
        topic = joint_angles_topic(topics)
        self.supervisor.actuation = config.actuation
        if config.actuation == JOINT_ANGLES_ACTUATION:
            self.joint_angles = JointAnglesTopic(self.node, topic, self.watch.own_calls)
        self.watch.watch_joint_angles(topic, self.joint_states.positions)

    def _make_part(self, part: str, action: str):
        self.watch.watch_controller(action)
        if self.joint_angles is not None:
            return JointAngleStream(part, action, self.joint_angles, self.clock, self.joint_states, self.log)
        client = TrajectoryClient(self.node, action, self.own_goals, self.executor_thread.run,
                                  last_look=self.watch.goals)
        return PartStream(part, action, client, self.clock, self.joint_states, self._post, self.log)

    def _make_base(self, topic: str) -> BaseStream:
        self.watch.watch_base(topic)
        publisher = self.node.create_publisher(Twist, topic, BASE_QUEUE)

        def turn(angular_z: float) -> None:
            twist = Twist()
            twist.angular.z = angular_z
            self.watch.own_twists.sent(twist_key(twist))
            publisher.publish(twist)
        return BaseStream(topic, turn, lambda: subscribed_by_another_node(self.node, topic), self.log)

    def _subscribe_joint_states(self) -> Subscription:
        def update(message: JointState) -> None:
            self.joint_states.record(list(message.name), list(message.position), seconds_of(message.header.stamp))
        return Subscription(self.node, JointState, JOINT_STATES_TOPIC, update, JOINT_STATES_QUEUE,
                            self.executor_thread.run)

    # -- stopping -----------------------------------------------------------------------------------
    def request_shutdown(self, reason: str) -> None:
        """Stops the robot as `disabled` does and ends the supervisor (waits at most 1 s)."""
        if not self.supervisor.thread.is_alive():
            self.supervisor.stopped.set()
            return
        done = threading.Event()
        self.supervisor.events.put(Shutdown(reason, done))
        done.wait(1.0)
