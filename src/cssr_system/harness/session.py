"""One round of harness tests, apart from the ROS library that carries it (README: "Test harness").

The ROS 1 runner (runner.py) and the ROS 2 one (cssr_system.ros2.harness_runner) share all of it: the samples the
robot reports (`SampleRecorder`, fed by their subscriptions), the node's configuration file for a test, the
sequence of a test (disabled and at rest, enabled for testDuration, disabled, at rest again), the node's log, the
`checks.Observation` they make and the report. A runner supplies a `NodeLink`: the activation service and the way
its node is given a test's configuration. No ROS import.
"""
import datetime
import os
import posixpath
import threading
import time
from typing import Callable, List, Mapping, Optional, Sequence, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import (Configuration, configuration_items,
                                                         format_configuration_file, topic_file_path)
from cssr_system.animate_behaviour.event_log import ROTATED_SUFFIX, LogEntry, read_log
from cssr_system.animate_behaviour.topics import WHEELS_KEY, TopicFileError, load_topic_map
from cssr_system.harness import checks, oracle, report, settings
from cssr_system.pepper.joint_table import RELATIVE, wheels_command_kind
from cssr_system.recording.recording import unwrap_heading, yaw_from_quaternion

HARNESS_NAME = "animateBehaviourTest"  # the harness's node, on either ROS
POLL_PERIOD = 0.05  # s between looks at the samples while waiting
CONFIG_FILE_NAME = "animateBehaviourTestConfiguration.ini"  # the harness configuration, in config/
REPORT_FILE_NAME = "animateBehaviourTestOutput.dat"
NODE_CONFIG_FILE_NAME = "animateBehaviourHarnessNode.ini"


class HarnessError(Exception):
    """The harness cannot run (a message for the user, never a traceback)."""


class SampleRecorder:
    """/joint_states, the base heading and the Wheels commands, stamped on arrival (wall clock, like the node's
    log). A runner's subscriptions call `joint_state`, `odometry` and `base_command` from any thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._joints: List[checks.JointSample] = []
        self._headings: List[checks.HeadingSample] = []
        self._commands: List[checks.BaseCommand] = []
        self._stamped: List[checks.JointSample] = []  # the same samples at the robot's stamps, where given
        self._recording = False
        self.joint_states_seen = threading.Event()
        self.odometry_seen = threading.Event()
        self._heading: Optional[float] = None  # unwrapped, so a turn across +-pi stays continuous

    def joint_state(self, names: Sequence[str], positions: Sequence[float], stamp: Optional[float] = None) -> None:
        """A /joint_states message; `stamp`: its header's time (s), kept apart for `stamped_joints`."""
        now = time.time()
        self.joint_states_seen.set()
        if self._recording:
            sample = checks.JointSample(now, dict(zip(names, positions)))
            with self._lock:
                self._joints.append(sample)
                if stamp is not None:
                    self._stamped.append(sample._replace(time=stamp))

    def odometry(self, x: float, y: float, z: float, w: float) -> None:
        """An odometry message's orientation quaternion."""
        now = time.time()
        self.odometry_seen.set()
        yaw = yaw_from_quaternion(x, y, z, w)
        with self._lock:
            # Unwrapped also while not recording, so the first recorded heading continues the last one.
            self._heading = unwrap_heading(self._heading, yaw)
            if self._recording:
                self._headings.append(checks.HeadingSample(now, self._heading))

    def base_command(self, angular_z: float) -> None:
        if self._recording:
            with self._lock:
                self._commands.append(checks.BaseCommand(time.time(), angular_z))

    def start(self) -> None:
        with self._lock:
            self._joints, self._headings, self._commands, self._stamped = [], [], [], []
            self._recording = True

    def stamped_joints(self) -> List[checks.JointSample]:
        """The joint samples at their header stamps: evenly spaced as the robot sent them, which arrival times on
        a busy machine are not (for figures of the motion, not for the checks, which compare arrivals with the
        node's log)."""
        with self._lock:
            return list(self._stamped)

    def snapshot(self):
        with self._lock:
            return list(self._joints), list(self._headings), list(self._commands)

    def stop(self):
        with self._lock:
            self._recording = False
        return self.snapshot()


def base_topics(config: settings.HarnessConfiguration, data_dir: str) -> Tuple[str, str]:
    """(the Wheels topic of the configured platform, the odometry topic beside it); "" where there is none.
    Raises HarnessError when the platform's topic file cannot be read."""
    try:
        topics = load_topic_map(topic_file_path(config.node, data_dir)).topics
    except TopicFileError as error:
        raise HarnessError(str(error)) from None
    wheels = topics.get(WHEELS_KEY, "")
    return wheels, posixpath.join(posixpath.dirname(wheels), "odom") if wheels else ""


def write_configuration_file(path: str, config: Configuration, test: str) -> None:
    """The node's configuration for `test`, replacing the file at `path` whole; HarnessError when it cannot."""
    temporary = path + ".tmp"
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(temporary, "w", encoding="utf-8") as stream:
            stream.write("# Written by animateBehaviourTest for the test '{}'; rewritten at every test.\n".format(test))
            stream.write(format_configuration_file(config))
        os.replace(temporary, path)  # the node never reads half a file
    except OSError as error:
        raise HarnessError("cannot write the node's configuration {}: {}".format(path, error)) from None


def read_node_log(path: str, since: float) -> Tuple[List[LogEntry], str]:
    """Entries of the node's log written since `since` (also in the rotated file), and a problem."""
    moment = datetime.datetime.fromtimestamp(since - 1.0).astimezone()
    entries: List[LogEntry] = []
    try:
        rotated = path + ROTATED_SUFFIX
        if os.path.exists(rotated) and os.path.getmtime(rotated) >= since - 1.0:
            entries.extend(read_log(rotated, moment))
        entries.extend(read_log(path, moment))
    except (OSError, ValueError) as error:
        return entries, "cannot read the node's log {}: {}".format(path, error)
    return entries, ""


def verdict(passed: bool, report_file: str) -> int:
    """The harness's last line, and its exit status: 0 when every test passed, 1 when one failed."""
    print("{}: {}; report: {}".format(HARNESS_NAME, "all tests PASSED" if passed else "some tests FAILED",
                                      report_file), flush=True)
    return 0 if passed else 1


def append_report(path: str, text: str) -> None:
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "a", encoding="utf-8") as stream:
            stream.write(text)
    except OSError as error:
        raise HarnessError("cannot write the report {}: {}".format(path, error)) from None


class NodeLink:
    """What a runner supplies for its ROS: the node's activation service and how the node gets a test's
    configuration."""

    def request(self, state: str) -> str:
        """The reply of setActivation to `state`, or a text saying why there was none."""
        raise NotImplementedError

    def apply_configuration(self, config: Configuration, path: str) -> None:
        """Make the node use `config` (written to `path`) from its next enable; HarnessError when it cannot."""
        raise NotImplementedError

    def node_overrides(self) -> Mapping[str, str]:
        """The node's parameters that override keys of the written configuration (named when it differs)."""
        return {}

    def interrupted(self) -> bool:
        """Whether the runner is being shut down."""
        return False


class Session:
    """Runs tests against the node through `link` with the samples of `recorder`, and writes the report."""

    def __init__(self, config: settings.HarnessConfiguration, link: NodeLink, recorder: SampleRecorder,
                 node_config_file: str, node_log_file: str, wheels_topic: str, odometry_topic: str,
                 say: Callable[[str], None] = print, complain: Callable[[str], None] = print) -> None:
        self.config = config
        self.link = link
        self.recorder = recorder
        self.node_config_file = node_config_file
        self.node_log_file = node_log_file
        self.wheels_topic = wheels_topic
        self.odometry_topic = odometry_topic
        self.say = say  # an information line
        self.complain = complain  # an error line
        self.last_observation: Optional[checks.Observation] = None  # of the last test run, for figures of its own

    # -- waiting -------------------------------------------------------------------------------
    def sleep_until(self, deadline: float) -> None:
        while time.time() < deadline:
            if self.link.interrupted():
                raise HarnessError("interrupted")
            time.sleep(min(POLL_PERIOD, max(0.0, deadline - time.time())))

    def wait_for_rest(self, since: float, timeout: float, reference_heading=None, return_tolerance=0.0) -> None:
        """Until the robot has been still for the quiet window (and, given a reference, the base is
        back at that heading, within `return_tolerance`), or `timeout` s after `since`."""
        tolerance, heading_tolerance = self.config.position_tolerance, self.config.heading_tolerance
        while time.time() < since + timeout:
            joints, headings, _ = self.recorder.snapshot()
            joints = [sample for sample in joints if sample.time >= since]
            headings = [sample for sample in headings if sample.time >= since]
            still = checks.settled_since(joints, headings, tolerance, heading_tolerance)
            returned = reference_heading is None or not headings or \
                abs(headings[-1].heading - reference_heading) <= return_tolerance
            if still is not None and time.time() - still >= settings.QUIET_WINDOW and returned:
                return
            self.sleep_until(time.time() + POLL_PERIOD)

    # -- one test ------------------------------------------------------------------------------
    def configure_node(self, test: str) -> Configuration:
        config = settings.node_configuration(self.config, test)
        write_configuration_file(self.node_config_file, config, test)
        self.link.apply_configuration(config, self.node_config_file)
        return config

    def run_test(self, test: str, iteration: int) -> checks.HarnessOutcome:
        config = self.configure_node(test)
        rotates = oracle.expected_motion(test, config.platform, config).base
        # Start from a disabled node and a robot at rest.
        self.link.request(contract.DISABLED)
        rest_from = time.time()
        self.recorder.start()
        self.wait_for_rest(rest_from, settings.BASE_STOP_LIMIT + settings.QUIET_WINDOW + 2.0)

        self.recorder.start()
        self.sleep_until(time.time() + 0.2)  # a heading and joint sample from before the enable
        enable_sent = time.time()
        enable_reply = self.link.request(contract.ENABLED)
        self.say("{}: enabled (reply {!r}), running {:g} s".format(settings.TESTS[test].title, enable_reply,
                                                                   self.config.test_duration))
        self.sleep_until(enable_sent + self.config.test_duration)
        disable_sent = time.time()
        disable_reply = self.link.request(contract.DISABLED)
        _, headings, _ = self.recorder.snapshot()
        reference = checks.heading_at(headings, enable_sent) if rotates and config.home_on_disable else None
        limit = settings.BASE_STOP_LIMIT if rotates else settings.JOINT_STOP_LIMIT
        # Wait past the limit so that a late motion (e.g. a late return turn) is seen, not missed.
        self.wait_for_rest(disable_sent, limit + settings.QUIET_WINDOW + 2.0, reference,
                           checks.return_tolerance(self.config, config, self.wheels_topic))
        ended = time.time()
        joints, headings, commands = self.recorder.stop()
        observation = self.observation(config, (enable_sent, enable_reply), (disable_sent, disable_reply), ended,
                                       joints, headings, commands)
        self.last_observation = observation
        return checks.evaluate_test(test, iteration, self.config, observation)

    def observation(self, config: Configuration, enable: Tuple[float, str], disable: Tuple[float, str], ended: float,
                    joints, headings, commands) -> checks.Observation:
        """What the test saw: `enable` and `disable` are (request time, reply); the samples are the recorder's.
        Without odometry the base heading is the one its commands ask for."""
        heading_source = "odometry on {}".format(self.odometry_topic)
        if not headings and self.wheels_topic:
            relative = wheels_command_kind(self.wheels_topic) == RELATIVE
            headings = checks.headings_from_commands(commands, relative, joints[0].time if joints else enable[0],
                                                     ended)
            heading_source = "commands on {} (no odometry on {})".format(self.wheels_topic, self.odometry_topic)
        entries, log_problem = read_node_log(self.node_log_file, enable[0])
        return checks.Observation(
            enable_sent=enable[0], enable_reply=enable[1], disable_sent=disable[0], disable_reply=disable[1],
            ended=ended, entries=entries, joints=joints, headings=headings, heading_source=heading_source,
            base_commands=commands, base_topic=self.wheels_topic, written_items=configuration_items(config),
            node_overrides=self.link.node_overrides(), log_problem=log_problem)

    # -- a round -------------------------------------------------------------------------------
    def run_round(self, iteration: int, planned: int, node_name: str,
                  report_file: Optional[str]) -> List[checks.HarnessOutcome]:
        """One round of the selected tests: outcomes, and the report appended (none without `report_file`)."""
        started = datetime.datetime.now()
        self._report(report_file, report.format_run_header(started, self.config, iteration, node_name,
                                                           self.node_config_file, self.node_log_file, planned))
        outcomes = []
        for test in self.config.tests:
            outcome = self.run_test(test, iteration)
            outcomes.append(outcome)
            self._report(report_file, report.format_test(outcome))
            if outcome.passed:
                self.say("{} (iteration {}): PASSED".format(settings.TESTS[test].title, iteration))
            else:
                self.complain(checks.failure_message(outcome).replace("\n", "\n  "))
        self._report(report_file, report.format_run_footer(outcomes))
        self.say("round {} {}; report: {}".format(
            iteration, "PASSED" if all(outcome.passed for outcome in outcomes) else "FAILED", report_file or "none"))
        return outcomes

    @staticmethod
    def _report(report_file: Optional[str], text: str) -> None:
        if report_file:
            append_report(report_file, text)
