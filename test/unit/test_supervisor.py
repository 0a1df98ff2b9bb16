"""Unit tests of the supervisor (core/supervisor.py) with real part streams over fake action clients, a fake clock,
a fake log and a fake animate action server: the live settings and the animate action's goals. No ROS master."""
import threading

import numpy
import pytest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryResult
from conftest import default_configuration
from fakes import FakeClient, FakeJointStates, FakeLog

from cssr_system.animate_behaviour import contract
from cssr_system.core.base_stream import BaseStream
from cssr_system.core.events import (AnimateCancel, AnimateGoal, ControllerConnected, Disable, ForeignGoal,
                                     Enable, GoalDone, Reconfigure, Shutdown)
from cssr_system.core.joint_states import FeedState
from cssr_system.core.part_stream import PartStream
from cssr_system.core.session import (CANCELLED, DISABLED, DURATION_ELAPSED, HOMED, REPLACED, RESULT_MARGIN,
                                      RETURN_POLL, STOPPED)
from cssr_system.core.supervisor import JUDGE_POLL, JUDGE_WAIT, Supervisor
from cssr_system.pepper.joint_table import PARTS

TOPICS = {"RArm": "/pepper_dcm/RightArm_controller/follow_joint_trajectory",
          "Leg": "/pepper_dcm/Pelvis_controller/follow_joint_trajectory"}
CONFIG = default_configuration(random_seed=3, behaviour=frozenset({"body"}))


class FakeActionServer:
    """What the supervisor tells the animate action's goals, in order."""

    def __init__(self):
        self.calls = []

    def accept(self, handle):
        self.calls.append(("accept", handle))

    def succeed(self, handle, animated, reason):
        self.calls.append(("succeed", handle, reason))

    def stop(self, handle, animated, reason):
        self.calls.append(("stop", handle, reason))

    def feedback(self, handle, elapsed, parts, motions_completed=0):
        self.calls.append(("feedback", handle, len(parts)))


class FakeFeed:
    state = FeedState.LISTENING

    def __init__(self):
        self.why = []  # each update's reason to listen (None: none)
        self.still = []  # each update's joints that no goal of ours drives
        self.listened = []  # each reason to listen at once

    def update(self, busy, still, now):
        self.why.append(busy)
        self.still.append(list(still))

    def listen(self, why):
        self.listened.append(why)


class Rig:
    def __init__(self, sends_on_another_thread=False):
        self.now = 50.0
        self.measured = {}  # by part: the measured positions of its joints (none: unknown)
        self.log = FakeLog()
        self.clients = {}
        self.action = FakeActionServer()
        self.statuses = []
        self.shown = []
        self.feed = FakeFeed()
        self.supervisor = Supervisor(lambda: self.now, self.log, self.make_part, self.make_base,
                                     lambda *status: self.statuses.append(status), self.feed,
                                     self.report_error, self.action, self.shown.append,
                                     sends_on_another_thread=sends_on_another_thread)
        self.supervisor.config = CONFIG
        for key, action in TOPICS.items():
            self.supervisor.stream_for(key, action)
            self.post(ControllerConnected(key, action))

    def make_part(self, part, action):
        self.clients[part] = FakeClient()
        return PartStream(part, action, self.clients[part], lambda: self.now,
                          FakeJointStates(lambda joints, part=part: self.measured.get(part)),
                          self.supervisor.events.put, self.log, debug=lambda *args: None, warn=lambda *args: None)

    def make_base(self, topic):
        self.turns = []  # angular.z of each Twist the base publishes; somebody always listens
        return BaseStream(topic, self.turns.append, lambda: True, self.log, debug=lambda *args: None,
                          warn=lambda *args: None)

    @staticmethod
    def report_error(where, error):
        raise error

    def post(self, event):
        """The event, then what it makes happen (goal results the fake clients report), as the thread would."""
        self.supervisor.events.put(event)
        while not self.supervisor.events.empty():
            self.supervisor.step(0.0)

    def finish_running_goals(self):
        for client in self.clients.values():
            handle = client.handles[-1]
            handle.finish(GoalStatus.SUCCEEDED)
        while not self.supervisor.events.empty():
            self.supervisor.step(0.0)

    def goals(self, part):
        return len(self.clients[part].handles)


def enable(rig, config=CONFIG):
    rig.post(Enable("config.ini", config, TOPICS, threading.Event()))


def test_the_watcher_watches_the_base_and_its_listener_reaches_it():
    rig = Rig()
    topic = "/pepper_dcm/cmd_moveto"
    base = rig.supervisor.base_for(topic)
    assert base in rig.supervisor.controlled_streams() and base not in rig.supervisor.part_streams()
    rig.post(Enable("file", CONFIG._replace(behaviour=frozenset({"rotation"})), dict(TOPICS, Wheels=topic),
                    threading.Event()))
    assert base.state.value == "waiting" and rig.turns == []
    rig.post(ControllerConnected("Wheels", topic))
    assert base.state.value == "animating" and len(rig.turns) == 1


@pytest.mark.parametrize("sends_on_another_thread, expected", [
    (False, [("plan", "RArm"), ("plan", "Leg"), ("send", "RArm"), ("send", "Leg")]),  # ROS 1: sent from this thread
    (True, [("plan", "RArm"), ("send", "RArm"), ("plan", "Leg"), ("send", "Leg")]),  # ROS 2: handed to the executor
])
def test_every_first_goal_is_planned_before_the_first_leaves_unless_another_thread_sends_them(
        sends_on_another_thread, expected):
    rig = Rig(sends_on_another_thread)
    calls = []
    for part, client in rig.clients.items():
        client.goal = lambda joints, timed, part=part, build=client.goal: calls.append(("plan", part)) or \
            build(joints, timed)
        client.send = lambda goal, done, part=part, send=client.send: calls.append(("send", part)) or send(goal, done)
    rig.post(Enable("file", CONFIG, TOPICS, threading.Event()))
    assert calls == expected


def test_a_live_change_while_enabled_splices_new_goals_and_is_logged_with_who_asked():
    rig = Rig()
    enable(rig)
    before = {part: rig.goals(part) for part in TOPICS}
    rig.post(Reconfigure("config.ini", CONFIG._replace(intensity=0.5), TOPICS, "dynamic_reconfigure"))
    assert all(rig.goals(part) == before[part] + 1 for part in TOPICS), "each part's next goal leaves at once"
    assert not any(handle.cancelled for client in rig.clients.values() for handle in client.handles), "no stop"
    assert rig.log.events(contract.SETTING_CHANGED) == [
        {"key": "intensity", "old": "1.0", "new": "0.5", "by": "dynamic_reconfigure"}]
    assert rig.statuses[-1][3].intensity == 0.5 and rig.statuses[-1][4] == "dynamic_reconfigure"
    assert rig.shown == [CONFIG], "only what a service brought is shown back to dynamic_reconfigure"


def test_a_part_switched_off_goes_home_and_the_others_go_on():
    rig = Rig()
    enable(rig)
    rig.post(Reconfigure("config.ini", CONFIG._replace(move_leg=False), TOPICS, "dynamic_reconfigure"))
    streams = {stream.part: stream for stream in rig.supervisor.part_streams()}
    assert streams["Leg"].state.value == "homing" and streams["RArm"].state.value == "animating"


def test_a_change_while_disabled_is_kept_and_moves_nothing():
    rig = Rig()
    rig.post(Reconfigure("config.ini", CONFIG._replace(intensity=0.2), TOPICS, "dynamic_reconfigure"))
    assert rig.supervisor.config.intensity == 0.2 and all(rig.goals(part) == 0 for part in TOPICS)


def animate(rig, handle, duration=0.0, config=CONFIG, by="/tree"):
    rig.post(AnimateGoal(handle, "config.ini", config, TOPICS, duration, by))


def run_until(rig, until, step=0.01):
    """The supervisor's thread until `until` on the fake clock, the running goals succeeding at their ends."""
    while rig.now < until:
        rig.now = min(until, rig.now + step)
        rig.supervisor.step(0.0)
        for stream in rig.supervisor.part_streams():
            if stream._sent is not None and rig.now >= stream._sent.end_time:
                stream._sent.handle.finish(GoalStatus.SUCCEEDED)
                while not rig.supervisor.events.empty():
                    rig.supervisor.step(0.0)


def test_a_goal_with_a_duration_sends_each_part_home_as_late_as_its_return_allows_then_succeeds_on_time():
    rig = Rig()
    started = rig.now
    # The arm's widest bands: far from its centre and fast, it needs longer to come back than the leg.
    wide = CONFIG._replace(intensity=1.0, selected_range=1.0, arm_maximum_range=(1.0,) * 5)
    animate(rig, "first", duration=5.0, config=wide)
    assert rig.action.calls == [("accept", "first")] and rig.supervisor.enabled
    assert rig.shown == [wide]
    run_until(rig, started + 5.0 - 4.0 - 0.01)
    assert all(stream.sent_purpose == contract.PURPOSE_ANIMATE for stream in rig.supervisor.part_streams()), \
        "no return is due yet"
    returns = {}  # part: (when its return left, how long it lasts)
    while rig.now < started + 5.0 and len(returns) < len(TOPICS):
        run_until(rig, rig.now + 0.01)
        for part in TOPICS:
            stream = rig.supervisor.parts[TOPICS[part]]
            if part not in returns and stream.state.value == "homing":
                returns[part] = (rig.now, stream._sent.duration)
    assert sorted(returns) == sorted(TOPICS)
    for part, (left, lasts) in returns.items():
        assert started + 5.0 - RETURN_POLL - RESULT_MARGIN - 0.02 <= left + lasts <= started + 5.0 - RESULT_MARGIN, \
            "%s's return ends just before the duration does" % part
    assert returns["RArm"][1] > returns["Leg"][1] and returns["RArm"][0] < returns["Leg"][0], \
        "the arm, farther and faster, starts back earlier"
    assert not rig.supervisor.enabled
    run_until(rig, started + 5.0 - 0.02)
    assert ("succeed", "first", DURATION_ELAPSED) not in rig.action.calls, "not before the duration"
    run_until(rig, started + 5.0 + 0.02)
    assert rig.action.calls[-1] == ("succeed", "first", DURATION_ELAPSED)
    assert all(stream.state.value == "idle" for stream in rig.supervisor.part_streams())
    ends = rig.log.events(contract.ANIMATE_GOAL)
    assert [fields["outcome"] for fields in ends] == ["accepted", "succeeded"] and ends[-1]["by"] == "/tree"


@pytest.mark.parametrize("ending, reason", [("second goal", REPLACED), ("cancel", CANCELLED),
                                            ("disable", DISABLED), ("enable", REPLACED)])
def test_a_goal_ends_preempted_with_its_reason(ending, reason):
    rig = Rig()
    animate(rig, "first")
    if ending == "second goal":
        animate(rig, "second", config=CONFIG._replace(intensity=0.5))
    elif ending == "cancel":
        rig.post(AnimateCancel("first"))
    elif ending == "disable":
        rig.post(Disable("disabled", threading.Event()))
    else:
        enable(rig)
    assert ("stop", "first", reason) in rig.action.calls
    assert rig.supervisor.enabled == (ending in ("second goal", "enable")), "a new goal or enable goes on"
    if ending == "second goal":
        assert rig.supervisor.settings_by == "/tree" and rig.supervisor.session.handle == "second"


def test_feedback_about_once_a_second():
    rig = Rig()
    animate(rig, "first")
    for _ in range(25):
        rig.now += 0.1
        rig.supervisor.step(0.0)
    assert [call[0] for call in rig.action.calls].count("feedback") == 2


def test_a_cancel_for_a_goal_already_replaced_changes_nothing():
    rig = Rig()
    animate(rig, "first")
    animate(rig, "second")
    calls = list(rig.action.calls)
    rig.post(AnimateCancel("first"))
    assert rig.action.calls == calls and rig.supervisor.enabled


def test_goal_results_reach_the_streams():
    rig = Rig()
    enable(rig)
    before = rig.goals("RArm")
    rig.post(GoalDone("RArm", TOPICS["RArm"], before, "SUCCEEDED", 0, ""))
    assert rig.goals("RArm") == before + 1


def test_joint_states_are_not_needed_while_every_part_runs_a_goal_of_ours():
    rig = Rig()
    assert rig.feed.why[-1] is None, "disabled: at rest"
    enable(rig)
    assert rig.feed.why[-1] is None, "every part runs a goal of ours: the goals say where the joints are"
    assert rig.feed.still[-1] == [], "no joint is still"
    rig.now = max(stream._sent.end_time for stream in rig.supervisor.part_streams())
    rig.finish_running_goals()
    assert rig.feed.why[-1] is None, "the next goals start where the ended ones left the joints"
    rig.post(Disable("disabled", threading.Event()))
    rig.now = max(stream._sent.end_time for stream in rig.supervisor.part_streams())
    rig.finish_running_goals()
    assert rig.feed.why[-1] is None, "at the centre"
    assert sorted(rig.feed.still[-1]) == sorted(PARTS["RArm"].joints + PARTS["Leg"].joints), "every joint is still"


def aborted_at_its_end(rig, part="RArm"):
    """The part's running goal ends ABORTED for its end state, at its end; its number."""
    stream = rig.supervisor.parts[TOPICS[part]]
    rig.now = stream._sent.end_time
    rig.clients[part].handles[-1].finish(GoalStatus.ABORTED, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED,
                                         "RShoulderPitch still moving")
    rig.supervisor.step(0.0)
    return stream._sent.number


def test_an_abort_for_the_end_state_waits_for_a_measurement_then_is_judged():
    rig = Rig()
    enable(rig)
    number = aborted_at_its_end(rig)
    assert rig.feed.listened[-1] == "judging the end of RArm goal %d" % number
    assert rig.feed.why[-1] == rig.feed.listened[-1], "listened to until measured"
    assert rig.log.events(contract.GOAL_FINISHED) == [] and rig.goals("RArm") == number, "not judged yet"
    assert rig.supervisor._next_timeout() == pytest.approx(JUDGE_POLL)
    rig.measured["RArm"] = rig.supervisor.parts[TOPICS["RArm"]]._sent.last_positions
    rig.supervisor.step(0.0)
    finished = rig.log.events(contract.GOAL_FINISHED)[-1]
    assert finished["state"] == "ABORTED" and finished["reached"] is True, "judged from the measurement"
    assert rig.goals("RArm") == number + 1 and rig.feed.why[-1] is None


def test_an_end_that_no_measurement_reaches_is_judged_after_its_wait_as_a_failure():
    rig = Rig()
    enable(rig)
    aborted_at_its_end(rig)
    rig.now += JUDGE_WAIT - 0.01
    rig.supervisor.step(0.0)
    assert rig.log.events(contract.GOAL_FINISHED) == []
    rig.now += 0.01
    rig.supervisor.step(0.0)
    assert rig.log.events(contract.GOAL_FINISHED)[-1]["reached"] is False
    assert rig.supervisor.parts[TOPICS["RArm"]].state.value == "waiting", "tried again later"


def test_an_end_waiting_for_a_measurement_at_shutdown_is_logged_as_it_ended():
    rig = Rig()
    enable(rig)
    aborted_at_its_end(rig)
    rig.post(Shutdown("signal", threading.Event()))
    states = {(fields["part"], fields["state"]) for fields in rig.log.events(contract.GOAL_FINISHED)}
    assert ("RArm", "ABORTED") in states


def test_a_home_goal_brings_every_part_back_even_those_another_node_left_away_from_its_centre():
    rig = Rig()
    rig.measured["RArm"] = numpy.array(PARTS["RArm"].centre) + 0.2  # where a gesture left it
    rig.measured["Leg"] = numpy.array(PARTS["Leg"].centre)
    rig.post(AnimateGoal("home goal", "config.ini", CONFIG, TOPICS, 0.0, "/tree", home=True))
    streams = {stream.part: stream for stream in rig.supervisor.part_streams()}
    assert all(stream.state.value == "homing" and stream.sent_purpose == contract.PURPOSE_HOME
               for stream in streams.values())
    assert not rig.supervisor.enabled and ("succeed", "home goal", HOMED) not in rig.action.calls
    run_until(rig, rig.now + 2.0)
    assert rig.action.calls[-1] == ("succeed", "home goal", HOMED)
    assert rig.log.events(contract.ANIMATE_GOAL)[0]["home"] is True


def test_a_home_goal_leaves_a_part_alone_while_another_node_moves_it():
    rig = Rig()
    enable(rig)
    rig.post(ForeignGoal(TOPICS["RArm"], "goal-1", "/gestureExecution", rig.now + 3.0))
    rig.post(AnimateGoal("home goal", "config.ini", CONFIG, TOPICS, 0.0, "/tree", home=True))
    streams = {stream.part: stream for stream in rig.supervisor.part_streams()}
    assert streams["RArm"].state.value == "idle" and streams["Leg"].state.value == "homing"


def test_the_stop_service_ends_the_goal_as_a_disable_does_and_the_log_names_who_asked():
    rig = Rig()
    animate(rig, "first")
    rig.post(Disable(STOPPED, threading.Event(), "/animate_behavior/stop"))
    assert ("stop", "first", STOPPED) in rig.action.calls and not rig.supervisor.enabled
    end = rig.log.events(contract.ANIMATE_GOAL)[-1]
    assert (end["outcome"], end["reason"], end["by"]) == ("preempted", STOPPED, "/animate_behavior/stop")
    assert rig.log.events(contract.BEHAVIOUR_ENDED)[-1]["reason"] == STOPPED
