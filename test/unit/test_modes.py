"""Unit tests of the modes (README: "Modes"): the motion of each (motion/modes.py), and the supervisor following the
conversation (core/supervisor.py with core/conversation.py): switches from a topic and from an action's status splice
one new goal per part at once without a velocity jump, a source's time-out, a mode set by hand, the base, yielding."""
import threading

import numpy
import pytest
from conftest import ROBOT_PARTS, default_configuration
from test_supervisor import CONFIG, TOPICS, Rig, run_until

from cssr_system.animate_behaviour import contract
from cssr_system.core.conversation import Conversation
from cssr_system.core.events import (AnimateGoal, ControllerConnected, ConversationHeard, ConversationPresent, Enable,
                                     ForeignGoal, Reconfigure)
from cssr_system.motion.modes import BEATS_PER_GOAL, BeatPlanner, shaped_motions, turns_base
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import speed_caps
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import JOINTS, PARTS

SHIPPED = default_configuration()
SOURCES = [("speakingTopic", "/speaking", "speaking"), ("listeningTopic", "/listening", "listening"),
           ("speakingAction", "/tts", "speaking"), ("listeningAction", "/speech_recognition", "listening")]


def bands(mode, config=SHIPPED):
    motions = shaped_motions(animated_parts(config, ROBOT_PARTS), config, mode)
    return {bounds.name: bounds for motion in motions for bounds in motion.bounds}


def test_listening_narrows_the_arms_and_hands_and_leans_the_hip_forward_within_its_band():
    idle, listening = bands("idle"), bands("listening")
    for name in idle:
        assert idle[name].lower - 1e-12 <= listening[name].lower <= listening[name].upper <= idle[name].upper + 1e-12
        width, idle_width = listening[name].upper - listening[name].lower, idle[name].upper - idle[name].lower
        if name[1:] in ("ShoulderPitch", "ShoulderRoll", "ElbowRoll", "ElbowYaw", "WristYaw", "Hand"):
            assert width == pytest.approx(SHIPPED.listening_range * idle_width)
    hip = listening["HipPitch"]
    assert hip.upper == pytest.approx((idle["HipPitch"].lower + idle["HipPitch"].upper) / 2) and \
        hip.centre < PARTS["Leg"].centre[0], "the forward (negative) half: a slight lean"
    assert listening["HipRoll"] == idle["HipRoll"], "the rest of the leg keeps its band"


def test_speaking_bands_come_from_their_own_key_within_the_limits():
    wide = SHIPPED._replace(speaking_arm_range=(1.0,) * 5, selected_range=1.0)
    for name, bounds in bands("speaking", wide).items():
        assert JOINTS[name].lower <= bounds.lower <= bounds.upper <= JOINTS[name].upper
    idle, speaking = bands("idle"), bands("speaking")
    widths = [(speaking[name].upper - speaking[name].lower, idle[name].upper - idle[name].lower)
              for name in PARTS["RArm"].joints]
    assert all(wide >= narrow for wide, narrow in widths) and \
        sum(wide for wide, _ in widths) > 1.5 * sum(narrow for _, narrow in widths)
    assert speaking["RHand"] == idle["RHand"] and speaking["HipPitch"] == idle["HipPitch"]


def test_only_idle_turns_the_base():
    assert [turns_base(mode) for mode in ("idle", "listening", "speaking")] == [True, False, False]


@pytest.mark.parametrize("part", ["RArm", "LHand"])
def test_speaking_beats_alternate_in_the_band_under_the_speed_cap_and_end_at_rest(part):
    (motion,) = [motion for motion in shaped_motions(animated_parts(SHIPPED, ROBOT_PARTS), SHIPPED, "speaking")
                 if motion.part == part]
    plan = MotionStyle(SHIPPED, make_rng(4), "speaking").planner(motion)
    assert isinstance(plan, BeatPlanner)
    start = numpy.array(PARTS[part].centre)
    timed = plan(0.0, start, numpy.zeros(len(start)), numpy.zeros(len(start)))
    assert len(timed.times) == 2 * BEATS_PER_GOAL
    assert 2 * BEATS_PER_GOAL * 30.0 / SHIPPED.beats_per_minute <= timed.times[-1] <= 1.3 * BEATS_PER_GOAL
    lower, upper = (numpy.array([getattr(b, side) for b in motion.bounds]) for side in ("lower", "upper"))
    assert numpy.all(timed.positions >= lower - 1e-9) and numpy.all(timed.positions <= upper + 1e-9)
    assert numpy.all(numpy.abs(timed.velocities) <= speed_caps(motion.joints) + 1e-9)
    assert not numpy.any(timed.velocities[-1]) and not numpy.any(timed.accelerations[-1])
    middle = (lower + upper) / 2
    moves = numpy.array(motion.moving)
    first = timed.positions[0][moves] - middle[moves]
    assert numpy.all(numpy.sign(timed.positions[1][moves] - middle[moves]) == -numpy.sign(first)), "stroke, return"


# -- the supervisor ------------------------------------------------------------------------------------------------

def conversing_rig(config=CONFIG):
    rig = Rig()
    rig.supervisor.conversation = Conversation(SOURCES, config.conversation_timeout)
    rig.post(Enable("config.ini", config, TOPICS, threading.Event()))
    return rig


def running_states(rig):
    """Each part's (goals sent, state the controller executes now: positions, velocities)."""
    states = {}
    for stream in rig.supervisor.part_streams():
        positions, velocities, _ = stream._sent.spline.sample(rig.now)
        states[stream.part] = (rig.goals(stream.part), numpy.array(positions), numpy.array(velocities))
    return states


def switch(rig, event, seconds=0.9):
    """`event` after `seconds` of motion: the state each part's controller executed at that instant, before it."""
    run_until(rig, rig.now + seconds)
    before = running_states(rig)
    rig.post(event)
    return before


@pytest.mark.parametrize("event, mode", [
    (ConversationHeard("listeningTopic", True), "listening"),
    (ConversationHeard("speakingAction", True), "speaking"),
])
def test_each_switch_splices_one_goal_per_part_at_once_without_a_velocity_jump(event, mode):
    rig = conversing_rig()
    steps = [(event, mode), (ConversationHeard(event.source, False), "idle")]
    if mode == "listening":  # every direction: idle, listening, speaking, listening, idle
        steps[1:1] = [(ConversationHeard("speakingAction", True), "speaking"),
                      (ConversationHeard("speakingAction", False), "listening")]
    for step, expected in steps:
        before = switch(rig, step)
        assert rig.supervisor.conversation.mode == expected and rig.statuses[-1][5] == expected
        for stream in rig.supervisor.part_streams():
            sent, positions, velocities = before[stream.part]
            handles = rig.clients[stream.part].handles
            assert len(handles) == sent + 1 and not any(handle.cancelled for handle in handles), "spliced, no stop"
            start = stream._sent.spline.sample(rig.now)
            numpy.testing.assert_allclose(start[0], positions, atol=1e-9)
            numpy.testing.assert_allclose(start[1], velocities, atol=1e-9, err_msg="no velocity jump")
    changes = rig.log.events(contract.MODE_CHANGED)
    assert [change["mode"] for change in changes] == [mode for _, mode in steps]
    assert changes[0]["by"] == "%s %s" % (event.source, dict((k, n) for k, n, _ in SOURCES)[event.source])


def test_listening_and_speaking_stop_the_base_where_it_is_and_idle_turns_it_again():
    rig = Rig()
    rig.supervisor.conversation = Conversation(SOURCES, 3.0)
    topic = "/pepper/cmd_vel"
    config = CONFIG._replace(behaviour=frozenset({"body", "rotation"}))
    rig.post(Enable("config.ini", config, dict(TOPICS, Wheels=topic), threading.Event()))
    base = rig.supervisor.bases[topic]
    rig.post(ControllerConnected("Wheels", topic))
    assert base.state.value == "animating"
    rig.post(ConversationHeard("speakingTopic", True))
    assert base.state.value == "idle", "speaking: no turn, and no turn back"
    rig.post(ConversationHeard("speakingTopic", False))
    assert base.state.value == "animating"


def test_a_silent_source_falls_back_to_idle_after_its_time_out_unless_its_publisher_is_there():
    rig = conversing_rig()
    rig.post(ConversationHeard("speakingTopic", True))
    assert rig.supervisor._next_timeout() <= CONFIG.conversation_timeout, "the supervisor wakes for the time-out"
    for _ in range(5):  # a latched topic: nothing new, but its publisher is there
        run_until(rig, rig.now + 1.0)
        rig.post(ConversationPresent("speakingTopic"))
    assert rig.supervisor.conversation.mode == "speaking"
    run_until(rig, rig.now + CONFIG.conversation_timeout + 0.1)  # its node died
    assert rig.supervisor.conversation.mode == "idle"
    assert rig.log.events(contract.MODE_CHANGED)[-1]["by"] == "speakingTopic /speaking silent"


def test_a_mode_set_by_hand_holds_through_other_changes_until_a_conversation_event_puts_it_back_to_auto():
    rig = conversing_rig()
    rig.post(Reconfigure("config.ini", CONFIG._replace(mode="listening"), TOPICS, "dynamic_reconfigure",
                         frozenset({"mode"})))
    assert rig.supervisor.conversation.mode == "listening" and rig.statuses[-1][6] == "dynamic_reconfigure"
    rig.post(Reconfigure("config.ini", CONFIG._replace(mode="listening", intensity=0.5), TOPICS,
                         "dynamic_reconfigure", frozenset({"intensity"})))
    assert rig.supervisor.conversation.mode == "listening"
    rig.post(ConversationHeard("speakingAction", True))
    assert rig.supervisor.conversation.mode == "speaking" and rig.supervisor.config.mode == "auto"
    assert rig.shown[-1].mode == "auto", "dynamic_reconfigure shows the setting back at auto"
    stale = CONFIG._replace(mode="listening", intensity=0.7)  # ROS 2's parameter still says listening
    rig.post(Reconfigure("config.ini", stale, TOPICS, "parameters", frozenset({"intensity"})))
    assert rig.supervisor.conversation.mode == "speaking", "a change of another setting leaves the mode alone"


def test_an_animate_goal_sets_the_mode_by_hand_and_one_without_keeps_it():
    rig = conversing_rig()
    rig.post(AnimateGoal("first", "config.ini", CONFIG._replace(mode="speaking"), TOPICS, 0.0, "/tree",
                         sets_mode=True))
    assert rig.supervisor.conversation.mode == "speaking" and rig.supervisor.conversation.by == "/tree"
    rig.post(AnimateGoal("second", "config.ini", CONFIG, TOPICS, 0.0, "/tree"))
    assert rig.supervisor.conversation.mode == "speaking", "no mode in the goal: the mode in force stays"


@pytest.mark.parametrize("mode", ["idle", "listening", "speaking"])
def test_a_part_another_node_moves_yields_in_every_mode_and_a_switch_sends_it_nothing(mode):
    rig = conversing_rig()
    if mode != "idle":
        rig.post(ConversationHeard(mode + "Topic", True))
    arm = rig.supervisor.parts[TOPICS["RArm"]]
    rig.post(ForeignGoal(TOPICS["RArm"], "gesture-1", "/gestureExecution", None))
    assert arm.state.value == "yielding"
    sent = rig.goals("RArm")
    rig.post(ConversationHeard("speakingAction", mode != "speaking"))
    assert arm.state.value == "yielding" and rig.goals("RArm") == sent, "nothing of ours reaches a yielding part"
    assert rig.supervisor.parts[TOPICS["Leg"]].state.value == "animating"
