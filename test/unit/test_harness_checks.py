"""Unit tests of the test harness's pure part: configuration, oracle, checks and report."""
import datetime
import os

import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import KEYS, ConfigurationError, configuration_items
from cssr_system.animate_behaviour.event_log import LogEntry
from cssr_system.harness import settings, oracle, checks, report
from cssr_system.pepper.joint_table import JOINTS, PARTS, centre_of

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA_DIR = os.path.join(REPO, "data")
SHIPPED_TEST_CONFIGURATION = os.path.join(REPO, "config", "animateBehaviourTestConfiguration.ini")

HARNESS_TEXT = """\
# a harness configuration
tests           all, hands
testDuration    3
iterations      2
platform        simulator
selectedRange   0.5
gestureDuration 0.5
numPoints       10
numPointsLeg    2
legRepeatFactor 3
"""


def harness(text=HARNESS_TEXT, overrides=None, source="harness.ini"):
    return settings.parse_harness_configuration(text, source, overrides, DATA_DIR)


def problems_of(text, overrides=None):
    with pytest.raises(ConfigurationError) as caught:
        harness(text, overrides)
    return caught.value.problems


# ---------------------------------------------------------------------------------------------------
# Configuration


def test_shipped_test_configuration_is_valid():
    config = settings.load_harness_configuration(SHIPPED_TEST_CONFIGURATION, data_dir=DATA_DIR)
    assert config.tests == ("hands", "body", "rotation", "all")
    assert config.iterations == 1 and config.platform == "robot"


def test_configuration_values_defaults_and_node_keys():
    config = harness()
    assert config.tests == ("hands", "all")  # in the README's order, whatever the order written
    assert config.test_duration == 3.0 and config.iterations == 2
    assert config.position_tolerance == 0.001 and config.report_samples == 10
    assert config.platform == "simulator" and config.node.num_points == 10
    assert config.node.arm_maximum_range == (0.2, 0.2, 0.2, 0.35, 0.2)  # shipped value, key left out
    assert settings.node_configuration(config, "hands").behaviour == frozenset({"hands"})
    assert settings.node_configuration(config, "all").behaviour == frozenset({"body", "hands", "rotation"})


def test_parameters_override_harness_and_node_keys():
    config = harness(overrides={"tests": "body", "platform": "robot", "iterations": 1})
    assert config.tests == ("body",) and config.platform == "robot" and config.iterations == 1


def test_every_problem_names_file_line_key_and_expectation():
    text = HARNESS_TEXT.replace("iterations      2", "iterations      0").replace(
        "tests           all, hands", "tests all,dance") + "behaviour all\nselectedRang 0.5\ntestDuration 4\n"
    problems = problems_of(text, {"reportSamples": "many"})
    assert "harness.ini:2: tests = 'all,dance': expected a comma list of hands, body, rotation, all " \
           "(any case) (unknown test 'dance')" in problems
    assert "harness.ini:4: iterations = '0': expected an integer >= 1" in problems
    assert any(p.startswith("harness.ini:11: behaviour is set by each test") for p in problems)
    assert any(p.startswith("harness.ini:12: unknown key 'selectedRang' (did you mean selectedRange?")
               for p in problems)
    assert "harness.ini:13: duplicated key testDuration (first at line 3)" in problems
    assert "parameter ~reportSamples = 'many': expected an integer >= 1" in problems


def test_node_key_problems_keep_their_line_and_missing_harness_keys_are_named():
    problems = problems_of("platform simulator\nselectedRange 1.5\n")
    assert "harness.ini:2: selectedRange = '1.5': expected a number in [0, 1]" in problems
    assert any(p.startswith("harness.ini: missing key tests") for p in problems)
    assert any(p.startswith("harness.ini: missing key testDuration") for p in problems)


def test_test_duration_must_reach_the_first_random_position():
    problems = problems_of(HARNESS_TEXT.replace("testDuration    3", "testDuration    1"))
    assert problems == ("harness.ini:3: testDuration = 1.0: expected at least gestureDuration + 1 s = 1.5 s, "
                        "so that the first random position is reached",)


def test_the_shipped_node_configuration_is_never_written(tmp_path):
    shipped = tmp_path / "animateBehaviourConfiguration.ini"
    shipped.write_text("")
    with pytest.raises(ValueError, match="shipped configuration"):
        settings.check_node_configuration_path(str(tmp_path / "." / "animateBehaviourConfiguration.ini"),
                                               str(shipped))
    settings.check_node_configuration_path(str(tmp_path / "harnessNode.ini"), str(shipped))


# ---------------------------------------------------------------------------------------------------
# Oracle


def test_table1_bounds_by_hand():
    config = harness().node
    # RShoulderPitch: FR = 4.17134, MRO = 0.2 FR, SRO = MRO * 0.5 / 2 = 0.208567
    assert oracle.table1_bounds(config, "RShoulderPitch") == pytest.approx((1.541 - 0.208567, 1.541 + 0.208567))
    # HipPitch: FR = 2.07694, SRO = 0.1 FR * 0.5 / 2 = 0.0519235
    assert oracle.table1_bounds(config, "HipPitch") == pytest.approx((-0.1107 - 0.0519235, -0.1107 + 0.0519235))
    # RHand: FR = 0.96, SRO = 0.7 * 0.96 / 4 = 0.168
    assert oracle.table1_bounds(config, "RHand") == pytest.approx((0.49808, 0.83408))
    # LElbowYaw is the 4th value of armMaximumRange (0.35), not the 3rd
    assert oracle.table1_bounds(config, "LElbowYaw") == pytest.approx((-1.715 - 0.364992, -1.715 + 0.364992))


def test_table1_bounds_are_clamped_to_the_joint_limits():
    config = harness(overrides={"selectedRange": 1.0, "armMaximumRange": "1,1,1,1,1"}).node
    lower, upper = oracle.table1_bounds(config, "RElbowYaw")  # centre 1.6981 + 2.08567 > the limit
    assert upper == JOINTS["RElbowYaw"].upper and lower == pytest.approx(1.6981 - 2.08567)


@pytest.mark.parametrize("test, platform, parts, base", [
    ("hands", "robot", ("RArm", "LArm", "RHand", "LHand"), False),
    ("hands", "simulator", ("RArm", "LArm"), False),
    ("body", "robot", ("RArm", "LArm", "RHand", "LHand", "Leg"), False),
    ("body", "simulator", ("RArm", "LArm", "Leg"), False),
    ("rotation", "robot", (), True),
    ("rotation", "simulator", (), True),
    ("all", "robot", ("RArm", "LArm", "RHand", "LHand", "Leg"), True),
    ("all", "simulator", ("RArm", "LArm", "Leg"), True),
])
def test_expected_parts_per_test_and_platform(test, platform, parts, base):
    expected = oracle.expected_motion(test, platform, harness().node)
    assert expected.parts == parts and expected.base == base
    moving = {name for name, bound in expected.bounds.items() if bound.moving}
    if test == "hands":  # the other arm joints are held exactly at their centre
        assert moving & set(PARTS["RArm"].joints) == {"RElbowRoll", "RWristYaw"}
        held = expected.bounds["LShoulderPitch"]
        assert held.lower == held.upper == held.centre == PARTS["LArm"].centre[0]
    elif parts:
        assert moving == set(expected.bounds)


def test_leg_slots_follow_the_seed_chunks():
    # numPoints 10, legRepeatFactor 3, numPointsLeg 2: chunk 3 -> R R C | R R C | R R C | C
    slots = [oracle.leg_slot_is_random(index, 10, 3, 2) for index in range(10)]
    assert slots == [True, True, False] * 3 + [False]


# ---------------------------------------------------------------------------------------------------
# Checks on a synthetic test: the hands test on the simulator, enabled at t = 100 s for 3 s.

ENABLE, DISABLE, END = 100.0, 103.0, 105.0


def entry(moment, event, **fields):
    return LogEntry(datetime.datetime.fromtimestamp(moment, tz=datetime.timezone.utc), event, fields)


def goal_entry(moment, part, expected, rows, purpose="animate", number=1, times=None):
    joints = PARTS[part].joints
    bounds = [expected.bounds[joint] for joint in joints]
    return entry(moment, contract.GOAL_SENT, part=part, label=PARTS[part].label, action="/x", purpose=purpose,
                 goal=number, joints=list(joints), centre=list(PARTS[part].centre),
                 lower=[b.lower for b in bounds], upper=[b.upper for b in bounds],
                 moving=[b.moving for b in bounds],
                 times=times or [0.5 * (index + 1) for index in range(len(rows))], positions=rows)


def random_rows(expected, part, count, fraction=0.25):
    rows = []
    for index in range(count):
        share = fraction if index % 2 == 0 else 1 - fraction
        bounds = [expected.bounds[joint] for joint in PARTS[part].joints]
        rows.append([b.lower + share * (b.upper - b.lower) for b in bounds])
    return rows


def synthetic(test="hands", platform="simulator", overrides=None):
    config = harness(overrides=dict({"platform": platform}, **(overrides or {})))
    node = settings.node_configuration(config, test)
    expected = oracle.expected_motion(test, platform, node)
    entries = [entry(ENABLE + 0.01, contract.CONFIGURATION_LOADED, file="n.ini", items=configuration_items(node)),
               entry(ENABLE + 0.02, contract.BEHAVIOUR_STARTED, behaviour=sorted(node.behaviour),
                     platform=platform, parts=list(expected.parts), wheels=None)]
    for part in expected.parts:
        rows = random_rows(expected, part, node.num_points)
        if part == "Leg":
            rows = [row if oracle.leg_slot_is_random(index, node.num_points, node.leg_repeat_factor,
                                                     node.num_points_leg) else list(PARTS[part].centre)
                    for index, row in enumerate(rows)]
        entries.append(goal_entry(ENABLE + 0.03, part, expected, rows))
    for part in expected.parts:
        entries.append(goal_entry(DISABLE + 0.005, part, expected, [list(PARTS[part].centre)], "home", 2, [1.0]))
    entries.append(entry(DISABLE + 0.01, contract.BEHAVIOUR_ENDED, reason="disabled", home=True))

    centres = {name: centre_of(name) for part in PARTS for name in PARTS[part].joints}
    centres.update(HeadYaw=0.0, HeadPitch=0.0)
    samples = []
    for step in range(int((END - ENABLE + 0.5) * 50)):
        moment = ENABLE - 0.5 + step / 50.0
        positions = dict(centres)
        if ENABLE + 0.5 <= moment < DISABLE + 1.0:  # moving between in-bound positions, then home
            share = 0.3 if int(moment * 2) % 2 else 0.7
            for name, bound in expected.bounds.items():
                positions[name] = bound.lower + share * (bound.upper - bound.lower)
        samples.append(checks.JointSample(moment, positions))
    observation = checks.Observation(
        enable_sent=ENABLE, enable_reply="1", disable_sent=DISABLE, disable_reply="1", ended=END,
        entries=entries, joints=samples, headings=[checks.HeadingSample(ENABLE - 0.5, 0.0)],
        heading_source="odometry on /pepper/odom", base_commands=[], base_topic="/pepper/cmd_vel",
        written_items=configuration_items(node))
    return config, expected, observation


def failed(outcome):
    return {check.name: check.detail for check in outcome.failures}


def test_a_correct_run_passes_every_check():
    config, expected, observation = synthetic()
    outcome = checks.evaluate_test("hands", 1, config, observation)
    assert failed(outcome) == {}
    assert [check.name for check in outcome.checks][:2] == ["Animate behaviour enabled", "Flexi movement started"]
    assert outcome.passed


def test_a_position_beyond_its_bound_is_named_with_the_numbers():
    config, expected, observation = synthetic()
    bound = expected.bounds["RWristYaw"]
    sample = observation.joints[150]  # 2.5 s after enabled
    observation.joints[150] = sample._replace(positions=dict(sample.positions, RWristYaw=bound.upper + 0.05))
    outcome = checks.evaluate_test("hands", 1, config, observation)
    assert set(failed(outcome)) == {"Observed positions within bounds"}
    assert failed(outcome)["Observed positions within bounds"].startswith(
        "RWristYaw = {:.6g} at +2.50 s after enabled, outside [{:.6g}, {:.6g}] by 0.05;".format(
            bound.upper + 0.05, bound.lower, bound.upper))
    assert "Observed positions within bounds: FAILED: RWristYaw" in checks.failure_message(outcome)


def test_an_overshoot_on_the_way_back_to_the_centre_is_its_own_failure():
    config, expected, observation = synthetic()
    bound = expected.bounds["LWristYaw"]
    index = next(i for i, sample in enumerate(observation.joints) if sample.time >= DISABLE + 0.3)
    sample = observation.joints[index]
    observation.joints[index] = sample._replace(positions=dict(sample.positions, LWristYaw=bound.upper + 0.02))
    problems = failed(checks.evaluate_test("hands", 1, config, observation))
    assert set(problems) == {"Return to the centre within bounds"}
    assert problems["Return to the centre within bounds"].startswith(
        "LWristYaw = {:.6g} at +0.30 s after disabled, outside [".format(bound.upper + 0.02))


def test_a_held_joint_that_moves_and_a_part_that_should_not_move_fail():
    config, expected, observation = synthetic()
    for index in range(100, 110):
        sample = observation.joints[index]
        observation.joints[index] = sample._replace(positions=dict(sample.positions, RShoulderPitch=1.6,
                                                                   HipRoll=0.1))
    problems = failed(checks.evaluate_test("hands", 1, config, observation))
    assert "RShoulderPitch = 1.6" in problems["Observed positions within bounds"]
    assert "(held)" in problems["Observed positions within bounds"]
    assert problems["Exactly the expected parts moved"].startswith("leg moved but should not: HipRoll changed by")


def test_goals_from_a_node_that_ignores_selected_range_fail():
    config, expected, observation = synthetic()
    wide = oracle.expected_motion("hands", "simulator", config.node._replace(selected_range=1.0))
    entries = [goal_entry(ENABLE + 0.03, part, wide, random_rows(wide, part, 10, fraction=0.02))
               if item.event == contract.GOAL_SENT and item.fields["purpose"] == "animate" else item
               for item in observation.entries for part in [item.fields.get("part")]]
    problems = failed(checks.evaluate_test("hands", 1, config, observation._replace(entries=entries)))
    assert problems["Goal bounds match Table 1"].startswith("RElbowRoll: logged [")
    assert "outside their bounds; worst:" in problems["Random positions sent within bounds"]


def test_leg_pattern_accepts_the_seed_pattern_and_rejects_others():
    config, expected, observation = synthetic("body")
    node = settings.node_configuration(config, "body")
    centre = list(PARTS["Leg"].centre)
    good = [row if oracle.leg_slot_is_random(i, 10, 3, 2) else centre
            for i, row in enumerate(random_rows(expected, "Leg", 10))]

    def verdict(rows):
        leg = goal_entry(ENABLE + 0.03, "Leg", expected, rows)
        return checks.check_leg_pattern(node, expected, observation._replace(entries=[leg]))

    assert verdict(good).passed, verdict(good).detail
    assert "chunk 3 = floor(10 / 3), 2 random then the centre, last 1 at the centre" in verdict(good).detail
    random_third = list(good)
    random_third[2] = good[0]
    assert not verdict(random_third).passed
    assert verdict(random_third).detail.startswith("goal 1: point 3 (chunk 1, slot 3) should be the centre")
    last_not_centre = good[:9] + [good[0]]
    assert "point 10 (after the last chunk) should be the centre" in verdict(last_not_centre).detail
    centre_first = [centre] + good[1:]
    assert "point 1 (chunk 1, slot 1) should be random but is the centre" in verdict(centre_first).detail
    assert "has 9 points, expected numPoints = 10" in verdict(good[:9]).detail


def test_heading_bound_and_base_stop():
    config, expected, observation = synthetic("rotation")
    node = settings.node_configuration(config, "rotation")
    headings = [checks.HeadingSample(ENABLE - 0.5 + k * 0.02, 0.25 * min(1.0, max(0.0, (ENABLE - 0.5 + k * 0.02
                                                                                        - ENABLE) / 2)))
                for k in range(int((END - ENABLE + 0.5) * 50))]
    observation = observation._replace(headings=headings)
    check = checks.check_heading_bounded(config, node, observation)
    assert check.passed and check.detail.startswith("largest turn 0.25 rad (headingBound 0.3")
    beyond = observation._replace(headings=[h._replace(heading=h.heading * 1.5) for h in headings])
    assert not checks.check_heading_bounded(config, node, beyond).passed
    not_back = checks.check_motion_stopped(config, node, expected, observation)
    assert not not_back.passed
    # on /pepper/cmd_vel a stop at the peak speed 0.6 rad/s may brake for 0.6^2 / (2 * 2.4) = 0.075 rad
    assert not_back.detail == "the base rests 0.25 rad from its heading at enable (allowed 0.085; " \
                              "homeOnDisable true)"
    back = [h._replace(heading=0.0) if h.time > DISABLE + 1 else h for h in headings]
    assert checks.check_motion_stopped(config, node, expected, observation._replace(headings=back)).passed
    turning = observation._replace(headings=[checks.HeadingSample(h.time, 0.1 * h.time) for h in headings])
    stopped = checks.check_motion_stopped(config, node, expected, turning)
    assert not stopped.passed and stopped.detail.startswith("still moving")


def test_settled_since_and_headings_from_commands():
    samples = [checks.JointSample(t, {"HipRoll": 0.0 if t >= 2 else 0.1}) for t in range(5)]
    assert checks.settled_since(samples, [], 1e-3, 1e-2) == 2
    turns = checks.headings_from_commands([checks.BaseCommand(1.0, 0.2), checks.BaseCommand(3.0, -0.1)],
                                          True, 0.0, 5.0)
    assert [round(h.heading, 9) for h in turns] == [0.0, 0.2, 0.1, 0.1]
    velocity = checks.headings_from_commands([checks.BaseCommand(1.0, 0.5)], False, 0.0, 3.0)
    assert velocity[-1].heading == pytest.approx(0.25, abs=0.011)  # 0.5 rad/s held for 0.5 s


# ---------------------------------------------------------------------------------------------------
# Report

WIDEST_KEY = max(len(key) for key in KEYS)  # the report aligns the configuration's values after the longest key


def test_report_reads_like_the_harness_report():
    config, expected, observation = synthetic("body")
    outcome = checks.evaluate_test("body", 1, config, observation)
    started = datetime.datetime(2026, 11, 21, 16, 52, 22)
    text = (report.format_run_header(started, config, 1, "/animateBehaviour", "/tmp/n.ini", "/tmp/n.log")
            + report.format_test(outcome) + report.format_run_footer([outcome]))
    for expected_text in ("=== New Test Run Started at 2026-11-21 16:52:22 ===",
                          "Test 2: Test Subtle Body Animate behaviour (behaviour body, iteration 1)",
                          "Configuration Settings:", "selectedRange".ljust(WIDEST_KEY + 1) + " : 0.5", "Joint names:",
                          'leg: ["HipPitch", "HipRoll", "KneePitch"]', "Home positions",
                          "leg: [-0.1107, -0.00766, 0.03221]", "Bounds of the random positions",
                          "Random positions sent", "Positions observed while enabled (/joint_states)",
                          "Subtle body movement started: PASSED", "Animate behaviour disabled: PASSED",
                          "Leg follows its chunk pattern: PASSED", "Result of Test 2: PASSED",
                          "Test Run Completed with Result: PASSED"):
        assert expected_text in text, expected_text
    broken = outcome._replace(checks=outcome.checks + (checks.Check("Something", False, "went wrong: 1 > 0"),))
    footer = report.format_run_footer([broken])
    assert "Test Run Completed with Result: FAILED" in footer and "FAILED: Something: went wrong: 1 > 0" in footer
