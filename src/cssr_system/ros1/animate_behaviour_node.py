"""The animateBehaviour node's ROS side: it makes the event log, the status publisher, the services, the action
clients, the base publisher and the subscriptions, and hands them to the supervisor (core/supervisor.py), which owns
the motion state.
"""
import gc
import os
import threading
from typing import Dict, Optional

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import JOINT_ANGLES_ACTUATION, Configuration, configuration_items
from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC
from cssr_system.animate_behaviour.event_log import (BackgroundLog, EventLog, claim_log_file, default_log_path,
                                                     node_log_file_name)
from cssr_system.animate_behaviour.topics import joint_angles_topic
from cssr_system.core.base_stream import BaseStream
from cssr_system.core.controller_watcher import ControllerWatcher
from cssr_system.core.conversation import configured_sources
from cssr_system.core.events import Shutdown
from cssr_system.core.joint_angle_stream import JointAngleStream
from cssr_system.core.joint_states import JointStateCache, JointStateFeed, SubscriptionSwitch
from cssr_system.core.part_stream import PartStream
from cssr_system.core.problems import Problems
from cssr_system.core.supervisor import Supervisor
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.package_files import package_dir, package_version
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros1.animate_action import AnimateActionServer
from cssr_system.ros1.conversation_watch import ConversationWatch
from cssr_system.ros1.foreign_watch import ForeignCommandWatch
from cssr_system.ros1.joint_angles_topic import JointAnglesTopic
from cssr_system.ros1.parameters import LiveSettingsServer, load_node_configuration
from cssr_system.ros1.rospy_compat import has_subscriber_other_than, write_at_once
from cssr_system.ros1.services import ActivationServices
from cssr_system.ros1.status import StatusPublisher
from cssr_system.ros1.trajectory_client import TrajectoryClient, rehearse

JOINT_STATES_QUEUE = 1  # only the latest /joint_states message matters


class Subscription:
    """A subscription the joint-state switch can end (`unregister`)."""

    def __init__(self, subscriber: rospy.Subscriber) -> None:
        self._subscriber = subscriber

    def unregister(self) -> None:
        """Ends the subscription, and collects at once what it leaves: rospy's poller of an ended subscription is
        a reference cycle that holds an epoll descriptor open until the collector's next full pass. The start-up's
        objects are out of the collector's sight (animate_behaviour_main.py), so this takes about a millisecond."""
        self._subscriber.unregister()
        gc.collect()


class AnimateBehaviourNode:
    """The node: its ROS interfaces, and the supervisor that drives the streams."""

    def __init__(self) -> None:
        self.version = package_version()
        # Named after the node's resolved name, and never shared with another running instance (README: "Several
        # robots").
        node = rospy.get_name()
        default_log_file = default_log_path(package_dir(), os.environ.get("ROS_HOME"), node_log_file_name(node))
        log_file, clash = claim_log_file(rospy.get_param("~logFile", default_log_file), node)
        if clash:
            console.warning(clash)
        self.log = BackgroundLog(EventLog(log_file))
        problems = Problems(self.log)  # one console line and one log line each
        self.report_error, self.report_problem = problems.error, problems.bad_input
        # The clock the controllers execute goals on (ROS time, as Gazebo's controllers): the streams' deadlines.
        self.clock = rospy.get_time
        joint_states = rospy.resolve_name(JOINT_STATES_TOPIC)  # in the node's namespace, remapped where asked
        self.joint_states = JointStateCache(self.clock, lambda text: self.report_problem("joint_states", text),
                                            joint_states)
        self._switch = SubscriptionSwitch(self._subscribe_joint_states, None, self.report_error, joint_states)
        self.feed = JointStateFeed(self.joint_states, self._switch, console.debug)
        self.status = StatusPublisher()
        post = self._post  # the supervisor's queue, for the servers made before it
        self.live_settings = LiveSettingsServer(load_node_configuration, post)
        self.action = AnimateActionServer(load_node_configuration, post)
        self.supervisor = Supervisor(self.clock, self.log, self._make_part, self._make_base, self.status.publish,
                                     self.feed, self.report_error, self.action,
                                     self.live_settings.show)
        self.services = ActivationServices(self.supervisor.events.put, self.log)
        self._watcher = ControllerWatcher(self.supervisor.controlled_streams, self.supervisor.events.put, self.log,
                                          self.supervisor.stopped, self.report_error)
        self.joint_angles: Optional[JointAnglesTopic] = None  # the shared publisher of actuation joint_angles
        self.watch = ForeignCommandWatch(rospy.get_caller_id(), self.supervisor.events.put, self.clock,
                                         self.report_error, self._watcher.status_seen)
        self.conversation = ConversationWatch(self._post, self.report_error)  # README: "Modes"

    def start(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        self.log.write(contract.CONFIGURATION_LOADED, file=config_file, items=configuration_items(config))
        self._choose_actuation(config, topics)
        self.supervisor.set_up(config, topics, self.conversation.watch(configured_sources(config)))
        self._switch.start()
        self._rehearse(config, topics)
        self.supervisor.start()
        self._watcher.thread.start()
        self.live_settings.start(config)
        self.action.start()
        self.services.advertise()

    def _post(self, event) -> None:
        self.supervisor.events.put(event)

    def _choose_actuation(self, config: Configuration, topics: Dict[str, str]) -> None:
        """The actuation of this run (README: "Actuation on the robot"), and the JointAngles topic: published on
        with joint_angles, watched for other nodes' calls either way."""
        topic = joint_angles_topic(topics)
        self.supervisor.actuation = config.actuation
        if config.actuation == JOINT_ANGLES_ACTUATION:
            self.joint_angles = JointAnglesTopic(topic, rospy.get_caller_id())
        self.watch.watch_joint_angles(topic, self.joint_states.positions)

    def _make_part(self, part: str, action: str) -> PartStream:
        self.watch.watch_controller(action)  # other nodes' goals still move the part where pepper_dcm runs too
        if self.joint_angles is not None:
            return JointAngleStream(part, action, self.joint_angles, self.clock, self.joint_states, self.log)
        return PartStream(part, action, TrajectoryClient(action, last_look=self.watch.goals), self.clock,
                          self.joint_states, self.supervisor.events.put, self.log)

    def _make_base(self, topic: str) -> BaseStream:
        self.watch.watch_base(topic)
        publisher = rospy.Publisher(topic, Twist, queue_size=10)
        write_at_once(publisher)  # the zero Twist of a stop is on the wire when publish returns

        def turn(angular_z: float) -> None:
            twist = Twist()
            twist.angular.z = angular_z
            publisher.publish(twist)
        return BaseStream(topic, turn, lambda: has_subscriber_other_than(publisher, rospy.get_caller_id()), self.log)

    def _subscribe_joint_states(self) -> "Subscription":
        return Subscription(rospy.Subscriber(JOINT_STATES_TOPIC, JointState, self.joint_states.update,
                                             queue_size=JOINT_STATES_QUEUE))

    @staticmethod
    def _rehearse(config: Configuration, topics: Dict[str, str]) -> None:
        """Every part's goal is planned and encoded once before the first enable (goals.rehearse)."""
        style = MotionStyle(config, make_rng(config.random_seed))
        for motion in animated_parts(config, [key for key in topics if key in PARTS]):
            rehearse(motion.part, style.planner(motion))

    # -- stopping -----------------------------------------------------------------------------------
    def request_shutdown(self, reason: str) -> None:
        """Stops the robot as `disabled` does and ends the supervisor (waits at most 1 s)."""
        if not self.supervisor_alive():
            self.supervisor.stopped.set()
            return
        done = threading.Event()
        self.supervisor.events.put(Shutdown(reason, done))
        done.wait(1.0)

    @property
    def stopped(self) -> bool:
        return self.supervisor.stopped.is_set()

    def supervisor_alive(self) -> bool:
        return self.supervisor.thread.is_alive()
