"""The harness's checks: what one test observed (service replies, the node's log entries, /joint_states,
the base heading and the Wheels commands) turned into `Check` results by `evaluate_test`.
"""
import math
from collections import OrderedDict
from typing import Dict, Iterable, Iterator, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration, configuration_items
from cssr_system.animate_behaviour.contract import REPLY_SUCCESS
from cssr_system.animate_behaviour.event_log import LogEntry
from cssr_system.harness.oracle import (ExpectedMotion, JointBound, expected_motion,
                                        leg_slot_is_random)
from cssr_system.harness.settings import (HOME_MAX_DURATION, BASE, BASE_STOP_LIMIT,
                                          DISABLE_LATENCY, EXACT, FIRST_WAYPOINT_MARGIN,
                                          HarnessConfiguration, HarnessTest,
                                          JOINT_STOP_LIMIT, LOG_CLOCK_MARGIN, QUIET_WINDOW,
                                          TESTS, node_configuration)
from cssr_system.pepper.joint_table import (RELATIVE, wheels_command_kind, BASE_MAX_ANGULAR_ACCELERATION,
                                            BASE_MAX_ANGULAR_VELOCITY, BASE_VELOCITY_COMMAND_TIMEOUT,
                                            HEAD_PART, JOINTS, PARTS, Part, centre_of)


class Check(NamedTuple):
    name: str
    passed: bool
    detail: str  # what was found; on failure, what went wrong, with the numbers


class JointSample(NamedTuple):
    time: float  # wall-clock seconds (time.time()) when it arrived
    positions: Mapping[str, float]


class HeadingSample(NamedTuple):
    time: float
    heading: float  # rad, unwrapped


class BaseCommand(NamedTuple):
    time: float
    angular_z: float  # as sent on the Wheels topic (an angle on cmd_moveto, a velocity otherwise)


class Observation(NamedTuple):
    """Everything one test saw. Times are wall-clock seconds, like the log's timestamps."""

    enable_sent: float
    enable_reply: str
    disable_sent: float
    disable_reply: str
    ended: float
    entries: Sequence[LogEntry]  # the node's log entries written during the test
    joints: Sequence[JointSample]
    headings: Sequence[HeadingSample]
    heading_source: str  # e.g. "odometry on /pepper/odom"
    base_commands: Sequence[BaseCommand]
    base_topic: str  # the Wheels topic, "" when unknown
    written_items: Mapping[str, str]  # the configuration the harness wrote for the node
    node_overrides: Mapping[str, str] = {}  # the node's private parameters that override keys
    log_problem: str = ""  # why the node's log could not be read, if it could not


class HarnessOutcome(NamedTuple):
    test: str
    iteration: int
    platform: str
    items: Mapping[str, str]  # the node's configuration during the test
    expected: ExpectedMotion
    checks: Tuple[Check, ...]
    random_positions: Mapping[str, Sequence[Sequence[float]]]  # part -> rows of its first goal
    random_count: Mapping[str, int]  # part -> points in that goal
    observed: Mapping[str, Sequence[Sequence[float]]]  # part -> sampled rows; BASE -> [[heading]]
    observed_source: str

    @property
    def passed(self) -> bool:
        return all(check.passed for check in self.checks)

    @property
    def failures(self) -> Tuple[Check, ...]:
        return tuple(check for check in self.checks if not check.passed)


def entry_time(entry: LogEntry) -> float:
    return entry.timestamp.timestamp()


def format_number(value: float) -> str:
    return "{:.6g}".format(value)


def format_vector(values: Iterable[float]) -> str:
    return "[" + ", ".join(format_number(value) for value in values) + "]"


def _first(entries: Sequence[LogEntry], event: str, after: float, condition=None) -> Optional[LogEntry]:
    for entry in entries:
        if entry.event == event and entry_time(entry) >= after - LOG_CLOCK_MARGIN and \
                (condition is None or condition(entry)):
            return entry
    return None


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def check_reply(name: str, reply: str) -> Check:
    if reply == REPLY_SUCCESS:
        return Check(name, True, 'reply "{}"'.format(REPLY_SUCCESS))
    return Check(name, False, 'reply {!r}, expected "{}"'.format(reply, REPLY_SUCCESS))


def check_started(spec: HarnessTest, config: Configuration, observation: Observation) -> Check:
    name = "{} started".format(spec.movement)
    entry = _first(observation.entries, contract.BEHAVIOUR_STARTED, observation.enable_sent)
    if entry is None:
        why = " ({})".format(observation.log_problem) if observation.log_problem else ""
        return Check(name, False, "no {} entry in the node's log after the enabled request{}".format(
            contract.BEHAVIOUR_STARTED, why))
    behaviour = sorted(entry.fields.get("behaviour") or [])
    platform = entry.fields.get("platform")
    found = "behaviour {}, platform {}, parts {}, wheels {}".format(
        ",".join(behaviour) or "none", platform, ",".join(entry.fields.get("parts") or []) or "none",
        entry.fields.get("wheels") or "none")
    problems = []
    if behaviour != sorted(spec.behaviours):
        problems.append("behaviour {} instead of {}".format(",".join(behaviour),
                                                            ",".join(sorted(spec.behaviours))))
    if platform != config.platform:
        problems.append("platform {} instead of {}".format(platform, config.platform))
    at = entry_time(entry) - observation.enable_sent
    if problems:
        return Check(name, False, "logged {} at +{:.3f} s: {}".format(found, at, "; ".join(problems)))
    return Check(name, True, "logged at +{:.3f} s: {}".format(at, found))


def check_ended(spec: HarnessTest, observation: Observation) -> Check:
    name = "{} ended".format(spec.movement)
    entry = _first(observation.entries, contract.BEHAVIOUR_ENDED, observation.disable_sent)
    if entry is None:
        return Check(name, False, "no {} entry in the node's log after the disabled request".format(
            contract.BEHAVIOUR_ENDED))
    return Check(name, True, "logged at +{:.3f} s after disabled (reason {}, home {})".format(
        entry_time(entry) - observation.disable_sent, entry.fields.get("reason"), entry.fields.get("home")))


def check_configuration_applied(observation: Observation) -> Check:
    """The configuration the node logged at enable is the one the harness wrote."""
    name = "Node applied the test configuration"
    entry = _first(observation.entries, contract.CONFIGURATION_LOADED, observation.enable_sent)
    if entry is None:
        return Check(name, False, "no {} entry in the node's log after the enabled request".format(
            contract.CONFIGURATION_LOADED))
    items = entry.fields.get("items") or {}
    differences = ["{}: node used {}, the harness wrote {}".format(key, items.get(key, "nothing"), value)
                   for key, value in observation.written_items.items() if items.get(key) != value]
    if not differences:
        return Check(name, True, "{} keys as written, from {}".format(len(observation.written_items),
                                                                      entry.fields.get("file")))
    detail = "; ".join(differences)
    if observation.node_overrides:
        detail += " (the node's private parameters override: {})".format(", ".join(
            "~{}={}".format(key, value) for key, value in sorted(observation.node_overrides.items())))
    return Check(name, False, detail)


def _goals(observation: Observation, purpose: Optional[str], after: float, before: float) -> List[LogEntry]:
    return [entry for entry in observation.entries
            if entry.event == contract.GOAL_SENT
            and after - LOG_CLOCK_MARGIN <= entry_time(entry) <= before + LOG_CLOCK_MARGIN
            and (purpose is None or entry.fields.get("purpose") == purpose)]


def _animation_goals(observation: Observation) -> List[LogEntry]:
    return _goals(observation, contract.PURPOSE_ANIMATE, observation.enable_sent, _animation_end(observation))


def _animation_end(observation: Observation) -> float:
    ended = _first(observation.entries, contract.BEHAVIOUR_ENDED, observation.disable_sent)
    return entry_time(ended) if ended is not None else observation.disable_sent


def part_label(key: str) -> str:
    return PARTS[key].label if key in PARTS else key


def _labels(keys: Iterable[str]) -> str:
    names = [part_label(key) for key in keys]
    return ", ".join(names) if names else "none"


def check_goal_parts(expected: ExpectedMotion, observation: Observation) -> Check:
    """Goals went to exactly the expected parts, each naming every joint of its controller."""
    name = "Goals sent to exactly the expected parts"
    goals = _animation_goals(observation)
    sent = [key for key in PARTS if any(goal.fields.get("part") == key for goal in goals)]
    problems = []
    missing = [key for key in expected.parts if key not in sent]
    extra = [key for key in sent if key not in expected.parts]
    if missing:
        problems.append("no goal for {}".format(_labels(missing)))
    if extra:
        problems.append("goals for {}, which this test must not move".format(_labels(extra)))
    for goal in goals:
        key = goal.fields.get("part")
        if key in PARTS and set(goal.fields.get("joints") or []) != set(PARTS[key].joints):
            problems.append("goal {} of {} names {} instead of every joint of its controller {}".format(
                goal.fields.get("goal"), key, goal.fields.get("joints"), list(PARTS[key].joints)))
            break
    if problems:
        return Check(name, False, "; ".join(problems) + " (expected {})".format(_labels(expected.parts)))
    return Check(name, True, "{} goal(s) to {}".format(len(goals), _labels(sent)))


def _goal_joint_table(goal: LogEntry) -> List[Tuple[int, str]]:
    return list(enumerate(goal.fields.get("joints") or []))


def check_goal_bounds(expected: ExpectedMotion, observation: Observation) -> Check:
    """The bounds and moving flags the node logged are those of Table 1."""
    name = "Goal bounds match Table 1"
    problems = []
    checked = 0
    for goal in _animation_goals(observation):
        lower, upper = goal.fields.get("lower") or [], goal.fields.get("upper") or []
        moving = goal.fields.get("moving") or []
        for index, joint in _goal_joint_table(goal):
            bound = expected.bounds.get(joint)
            if bound is None:
                continue
            checked += 1
            if index >= len(lower) or index >= len(upper):
                problems.append("goal {}: no bounds logged for {}".format(goal.fields.get("goal"), joint))
                continue
            if abs(lower[index] - bound.lower) > EXACT or abs(upper[index] - bound.upper) > EXACT:
                problems.append("{}: logged [{}, {}], Table 1 gives [{}, {}]".format(
                    joint, format_number(lower[index]), format_number(upper[index]),
                    format_number(bound.lower), format_number(bound.upper)))
            if index < len(moving) and bool(moving[index]) != bound.moving:
                problems.append("{}: logged as {}, expected {}".format(
                    joint, "moving" if moving[index] else "held", "moving" if bound.moving else "held"))
    problems = list(OrderedDict.fromkeys(problems))  # the same joint in every goal: say it once
    if problems:
        return Check(name, False, "; ".join(problems[:6]) + ("; ..." if len(problems) > 6 else ""))
    if not checked:
        return Check(name, True, "no joint goal in this test")
    return Check(name, True, "{} joint bounds checked".format(checked))


def _excess(bound: JointBound, value: float) -> float:
    return max(bound.lower - value, value - bound.upper, 0.0)


def check_goal_positions(expected: ExpectedMotion, observation: Observation) -> Check:
    """Every random position the node sent lies within the oracle's bounds (held joints: the centre)."""
    name = "Random positions sent within bounds"
    worst: Optional[Tuple[float, str]] = None
    count = outside = 0
    for goal in _animation_goals(observation):
        positions = goal.fields.get("positions") or []
        for row_number, row in enumerate(positions, start=1):
            for index, joint in _goal_joint_table(goal):
                bound = expected.bounds.get(joint)
                if bound is None or index >= len(row):
                    continue
                count += 1
                excess = _excess(bound, row[index])
                if excess > EXACT:
                    outside += 1
                    if worst is None or excess > worst[0]:
                        worst = (excess, "{} = {} at goal {} point {} is outside [{}, {}] by {}".format(
                            joint, format_number(row[index]), goal.fields.get(
                                "goal"), row_number, format_number(bound.lower),
                            format_number(bound.upper), format_number(excess)))
    if worst is not None:
        return Check(name, False, "{} of {} positions outside their bounds; worst: {}".format(
            outside, count, worst[1]))
    return Check(name, True, "{} positions checked".format(count))


def check_leg_pattern(config: Configuration, expected: ExpectedMotion, observation: Observation) -> Check:
    """Each leg goal: numPoints points; per chunk numPointsLeg random positions, then the centre."""
    name = "Leg follows its chunk pattern"
    goals = [goal for goal in _animation_goals(observation) if goal.fields.get("part") == "Leg"]
    chunk = config.num_points // config.leg_repeat_factor
    pattern = "chunk {} = floor({} / {}), {} random then the centre, last {} at the centre".format(
        chunk, config.num_points, config.leg_repeat_factor, config.num_points_leg,
        config.num_points - chunk * config.leg_repeat_factor)
    if not goals:
        return Check(name, False, "no leg goal in the node's log")
    leg_moves = any(bound.moving and bound.upper > bound.lower for bound in expected.bounds.values()
                    if bound.part == "Leg")
    for goal in goals:
        joints = goal.fields.get("joints") or []
        rows = goal.fields.get("positions") or []
        centre = [centre_of(joint) for joint in joints]
        label = "goal {}".format(goal.fields.get("goal"))
        if len(rows) != config.num_points:
            return Check(name, False, "{} has {} points, expected numPoints = {}".format(
                label, len(rows), config.num_points))
        for index, row in enumerate(rows):
            at_centre = all(abs(value - middle) <= EXACT for value, middle in zip(row, centre))
            chunk_number, slot = divmod(index, chunk)
            if leg_slot_is_random(index, config.num_points, config.leg_repeat_factor, config.num_points_leg):
                if at_centre and leg_moves:
                    return Check(name, False, "{}: point {} (chunk {}, slot {}) should be random but is the "
                                 "centre {} ({})".format(label, index + 1, chunk_number + 1, slot + 1,
                                                         format_vector(row), pattern))
            elif not at_centre:
                where = "chunk {}, slot {}".format(chunk_number + 1, slot + 1) \
                    if chunk_number < config.leg_repeat_factor else "after the last chunk"
                return Check(name, False, "{}: point {} ({}) should be the centre {} but is {} ({})".format(
                    label, index + 1, where, format_vector(centre), format_vector(row), pattern))
    return Check(name, True, "{} leg goal(s): {}".format(len(goals), pattern))


def _joint_range(samples: Sequence[JointSample], joint: str, start: float, end: float) -> Optional[float]:
    values = [sample.positions[joint] for sample in samples
              if start <= sample.time <= end and joint in sample.positions]
    return max(values) - min(values) if values else None


def heading_at(headings: Sequence[HeadingSample], moment: float) -> Optional[float]:
    """The last heading at or before `moment`, else the first after it."""
    before = [sample for sample in headings if sample.time <= moment]
    if before:
        return before[-1].heading
    return headings[0].heading if headings else None


def _largest_turn(headings: Sequence[HeadingSample], reference: float, start: float, end: float) -> float:
    turns = [abs(_wrap(sample.heading - reference)) for sample in headings if start <= sample.time <= end]
    return max(turns) if turns else 0.0


def check_parts_moved(harness: HarnessConfiguration, config: Configuration, expected: ExpectedMotion,
                      observation: Observation) -> Check:
    """The robot moved exactly the expected parts (base included); the others did not move at all."""
    name = "Exactly the expected parts moved"
    tolerance = harness.position_tolerance
    if not observation.joints:
        return Check(name, False, "no /joint_states received")
    moved, problems = [], []
    for part in list(PARTS.values()) + [HEAD_PART]:
        if part.key in expected.parts:
            part_moved, part_problems = _driven_part_moved(part, expected, observation, tolerance)
        else:
            part_moved, part_problems = _idle_part_moved(part, observation, tolerance)
        if part_moved:
            moved.append(part.key)
        problems.extend(part_problems)
    base_turned, base_problems = _base_turned(harness, config, expected, observation)
    if base_turned:
        moved.append(BASE)
    problems.extend(base_problems)
    detail = "moved: {}; expected: {}".format(_labels(moved),
                                              _labels(expected.parts + ((BASE,) if expected.base else ())))
    if problems:
        return Check(name, False, "; ".join(problems) + " (" + detail + ")")
    return Check(name, True, detail)


def _driven_part_moved(part: Part, expected: ExpectedMotion, observation: Observation,
                       tolerance: float) -> Tuple[bool, List[str]]:
    """Whether a part the test drives moved while enabled, and what is wrong: a joint missing from
    /joint_states, or no movement where the bounds leave room for one."""
    # A driven part moved if one of its moving joints did; held joints are checked by the
    # bounds. Random positions may land close together: a quarter of the range is enough.
    problems = []
    changes, can_move = [], False
    for joint in part.joints:
        bound = expected.bounds[joint]
        change = _joint_range(observation.joints, joint, observation.enable_sent, observation.disable_sent)
        if change is None:
            problems.append("{} is missing from /joint_states".format(joint))
            continue
        if bound.moving:
            width = bound.upper - bound.lower
            can_move = can_move or width > 4 * tolerance
            changes.append((change, joint, max(tolerance, min(5 * tolerance, 0.25 * width))))
    if any(change > threshold for change, _, threshold in changes):
        return True, problems
    if can_move and changes:
        change, joint, _ = max(changes)
        problems.append("{} did not move: largest change {} ({})".format(part.label, format_number(change), joint))
    return False, problems


def _idle_part_moved(part: Part, observation: Observation, tolerance: float) -> Tuple[bool, List[str]]:
    """Whether a part the test must not move moved, from enable to the end of the test, and the problem
    that makes."""
    changes = [(change, joint) for change, joint in
               ((_joint_range(observation.joints, joint, observation.enable_sent, observation.ended), joint)
                for joint in part.joints) if change is not None]
    if not changes or max(changes)[0] <= tolerance:
        return False, []
    change, joint = max(changes)
    return True, ["{} moved but should not: {} changed by {}".format(part.label, joint, format_number(change))]


def _base_turned(harness: HarnessConfiguration, config: Configuration, expected: ExpectedMotion,
                 observation: Observation) -> Tuple[bool, List[str]]:
    """Whether the base turned beyond the heading tolerance during the test, and what is wrong: a turn
    the test does not expect, no turn where the configuration allows one, or no heading at all."""
    if not observation.headings:
        if expected.base:
            return False, ["no base heading observed ({})".format(observation.heading_source or "no source")]
        return False, []
    reference = heading_at(observation.headings, observation.enable_sent)
    turn = _largest_turn(observation.headings, reference,  # type: ignore[arg-type]
                         observation.enable_sent, observation.ended)
    if turn > harness.heading_tolerance:
        return True, [] if expected.base else ["the base turned by {} rad but should not".format(format_number(turn))]
    if expected.base and config.rot_maximum_range > 0 and config.heading_bound > harness.heading_tolerance:
        return False, ["the base did not turn: largest turn {} rad ({})".format(
            format_number(turn), observation.heading_source)]
    return False, []


def bounded_from(expected: ExpectedMotion, config: Configuration, observation: Observation) -> Dict[str, float]:
    """Per part, the time from which its observed positions must lie within the bounds: the first
    waypoint of its first goal (the first segment starts from wherever the joints were)."""
    starts = {}
    goals = _animation_goals(observation)
    for key in expected.parts:
        first = next((goal for goal in goals if goal.fields.get("part") == key), None)
        if first is not None and first.fields.get("times"):
            starts[key] = entry_time(first) + float(first.fields["times"][0]) + FIRST_WAYPOINT_MARGIN
        else:
            starts[key] = observation.enable_sent + config.gesture_duration + 0.5
    return starts


def check_observed_within_bounds(harness: HarnessConfiguration, config: Configuration, expected: ExpectedMotion,
                                 observation: Observation, returning: bool = False) -> Check:
    """Every observed position after the first waypoint lies within its bounds (held joints: at the
    centre), up to the position tolerance: while enabled, or (`returning`) during the return to the
    centre after disabled."""
    name = "Return to the centre within bounds" if returning else "Observed positions within bounds"
    tolerance = harness.position_tolerance
    starts = bounded_from(expected, config, observation)
    origin, moment_name = ((observation.disable_sent, "disabled") if returning
                           else (observation.enable_sent, "enabled"))
    count = outside = 0
    worst: Optional[Tuple[float, str]] = None
    joints_outside = []
    for sample, joint, bound in _bounded_positions(expected, starts, observation, returning):
        value = sample.positions[joint]
        count += 1
        excess = _excess(bound, value)
        if excess > tolerance:
            outside += 1
            if joint not in joints_outside:
                joints_outside.append(joint)
            if worst is None or excess > worst[0]:
                worst = (excess, _outside_text(joint, bound, value, sample.time - origin, moment_name, excess))
    if worst is not None:
        return Check(name, False, "{}; {} of {} observed positions beyond the tolerance {} in {}".format(
            worst[1], outside, count, format_number(tolerance), ", ".join(joints_outside)))
    if not expected.bounds:
        return Check(name, True, "no joint moves in this test")
    if not count:
        return Check(name, False, "no observed position {}".format(
            "after disabled" if returning else "between the first waypoint and disabled"))
    return Check(name, True, "{} positions of {} joints within their bounds (tolerance {})".format(
        count, len(expected.bounds), format_number(tolerance)))


def _bounded_positions(expected: ExpectedMotion, starts: Mapping[str, float], observation: Observation,
                       returning: bool) -> Iterator[Tuple[JointSample, str, JointBound]]:
    """(sample, joint, bound) for every observed position that must lie within its bounds: from its
    part's time in `starts` (see `bounded_from`), and while enabled or (`returning`) after the disabled
    request reached the controllers."""
    switch = observation.disable_sent + DISABLE_LATENCY
    for sample in observation.joints:
        if (sample.time > switch) != returning:
            continue
        for joint, bound in expected.bounds.items():
            if sample.time < starts[bound.part] or joint not in sample.positions:
                continue
            yield sample, joint, bound


def _outside_text(joint: str, bound: JointBound, value: float, elapsed: float, moment_name: str,
                  excess: float) -> str:
    """An observed position beyond its bound, `elapsed` seconds after the `moment_name` request."""
    where = "[{}, {}]".format(format_number(bound.lower), format_number(bound.upper)) if bound.moving \
        else "its centre {} (held)".format(format_number(bound.centre))
    return "{} = {} at +{:.2f} s after {}, outside {} by {}".format(
        joint, format_number(value), elapsed, moment_name, where, format_number(excess))


def check_heading_bounded(harness: HarnessConfiguration, config: Configuration, observation: Observation) -> Check:
    name = "Base heading within headingBound of its heading at enable"
    if not observation.headings:
        return Check(name, False, "no base heading observed ({})".format(
            observation.heading_source or "no source"))
    reference = heading_at(observation.headings, observation.enable_sent)
    turn = _largest_turn(observation.headings, reference,  # type: ignore[arg-type]
                         observation.enable_sent, observation.ended)
    limit = config.heading_bound + harness.heading_tolerance
    detail = "largest turn {} rad (headingBound {} + tolerance {}), {}".format(
        format_number(turn), format_number(config.heading_bound), format_number(harness.heading_tolerance),
        observation.heading_source)
    return Check(name, turn <= limit, detail)


def check_base_speed(config: Configuration, observation: Observation) -> Check:
    """On a velocity topic, no command exceeds rotMaximumRange x the base's maximum."""
    name = "Base angular speed within rotMaximumRange x {:g} rad/s".format(BASE_MAX_ANGULAR_VELOCITY)
    limit = config.rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY
    speeds = [abs(command.angular_z) for command in observation.base_commands]
    if not speeds:
        return Check(name, False, "no command on {}".format(observation.base_topic))
    fastest = max(speeds)
    return Check(name, fastest <= limit * (1 + 1e-9) + EXACT, "fastest command {} rad/s on {} (limit {})".format(
        format_number(fastest), observation.base_topic, format_number(limit)))


def check_nothing_after_disabled(expected: ExpectedMotion, observation: Observation) -> Check:
    """After disabled: at most one return-to-centre goal per part, ending at the centre within 2 s;
    after behaviour_ended, no animation goal and no random turn."""
    name = "No animation goal after disabled"
    end = _animation_end(observation)
    problems = []
    homes: Dict[str, int] = {}
    for goal in _goals(observation, None, observation.disable_sent, observation.ended):
        key = goal.fields.get("part")
        if goal.fields.get("purpose") != contract.PURPOSE_HOME:
            if entry_time(goal) > end + LOG_CLOCK_MARGIN:
                problems.append("{} goal {} to {} at +{:.3f} s after disabled".format(
                    goal.fields.get("purpose"), goal.fields.get("goal"), key,
                    entry_time(goal) - observation.disable_sent))
            continue
        homes[key] = homes.get(key, 0) + 1
        rows, times = goal.fields.get("positions") or [], goal.fields.get("times") or []
        centre = [centre_of(joint) for joint in goal.fields.get("joints") or []]
        if not rows or any(abs(value - middle) > EXACT for value, middle in zip(rows[-1], centre)):
            problems.append("the return goal of {} ends at {}, not at the centre {}".format(
                key, format_vector(rows[-1]) if rows else "nothing", format_vector(centre)))
        if times and times[-1] > HOME_MAX_DURATION + EXACT:
            problems.append("the return goal of {} lasts {} s (at most {:g} s)".format(
                key, format_number(times[-1]), HOME_MAX_DURATION))
    problems.extend("{} return goals to {}".format(count, key) for key, count in homes.items() if count > 1)
    turns = [entry for entry in observation.entries if entry.event == contract.BASE_COMMAND
             and entry_time(entry) > end + LOG_CLOCK_MARGIN
             and entry.fields.get("purpose") == contract.PURPOSE_ANIMATE]
    if turns:
        problems.append("{} random base turn(s) after disabled".format(len(turns)))
    if problems:
        return Check(name, False, "; ".join(problems))
    returns = [entry for entry in observation.entries if entry.event == contract.BASE_COMMAND
               and entry_time(entry) >= observation.disable_sent - LOG_CLOCK_MARGIN
               and entry.fields.get("purpose") != contract.PURPOSE_ANIMATE]
    return Check(name, True, "return-to-centre goals: {}{}".format(
        _labels(key for key in PARTS if key in homes), "; base return turn(s): {}".format(len(returns))
        if returns else ""))


def settled_since(joints: Sequence[JointSample], headings: Sequence[HeadingSample], tolerance: float,
                  heading_tolerance: float, names: Optional[Sequence[str]] = None) -> Optional[float]:
    """The time from which every joint (of `names`, default all of JOINTS) and the heading stay
    within the tolerances of their last observed values; None without samples."""
    if not joints:
        return None
    names = tuple(names) if names is not None else tuple(JOINTS)
    last = joints[-1].positions
    since = joints[-1].time
    for sample in reversed(joints):
        if any(abs(sample.positions[name] - last[name]) > tolerance
               for name in names if name in sample.positions and name in last):
            break
        since = sample.time
    if headings:
        final = headings[-1].heading
        heading_since = headings[-1].time
        for sample in reversed(headings):
            if abs(_wrap(sample.heading - final)) > heading_tolerance:
                break
            heading_since = sample.time
        since = max(since, heading_since)
    return since


def return_tolerance(harness: HarnessConfiguration, config: Configuration, base_topic: str) -> float:
    """How far from its heading at enable the base may come to rest after its return turn."""
    allowed = harness.heading_tolerance
    # A velocity base (or one on an unknown topic) may brake through a turn under way.
    if not (base_topic and wheels_command_kind(base_topic) == RELATIVE):
        peak = config.rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY
        allowed += peak ** 2 / (2 * BASE_MAX_ANGULAR_ACCELERATION)
    return allowed


def check_motion_stopped(harness: HarnessConfiguration, config: Configuration, expected: ExpectedMotion,
                         observation: Observation) -> Check:
    """After disabled, the robot came to rest (joints at their centre when homeOnDisable) in time."""
    name = "Motion stopped after disabled"
    after = [sample for sample in observation.joints if sample.time >= observation.disable_sent]
    headings = [sample for sample in observation.headings if sample.time >= observation.disable_sent]
    since = settled_since(after, headings, harness.position_tolerance, harness.heading_tolerance)
    if since is None:
        return Check(name, False, "no /joint_states received after the disabled request")
    last = after[-1]
    limit = BASE_STOP_LIMIT if expected.base else JOINT_STOP_LIMIT
    problems = _stillness_problems(after, since, observation.disable_sent, limit, harness.position_tolerance)
    offsets: List[Tuple[float, str]] = []
    if config.home_on_disable:
        offsets = [(abs(last.positions[joint] - bound.centre), joint)
                   for joint, bound in expected.bounds.items() if joint in last.positions]
        problems.extend(_off_centre_problems(offsets, expected, last, harness.position_tolerance))
    returned = None
    if expected.base and config.home_on_disable and observation.headings:
        returned, allowed = _base_return(harness, config, observation)
        if returned > allowed:
            problems.append("the base rests {} rad from its heading at enable (allowed {}; homeOnDisable "
                            "true)".format(format_number(returned), format_number(allowed)))
    if problems and expected.base:
        problems.extend(_base_commands_after_disabled(observation))
    if problems:
        return Check(name, False, "; ".join(problems))
    return Check(name, True, _stopped_detail(since - observation.disable_sent, limit, offsets, returned))


def _stillness_problems(after: Sequence[JointSample], since: float, disable_sent: float, limit: float,
                        tolerance: float) -> List[str]:
    """The problem, if any, with when the robot came to rest: still moving at the end of the test
    (naming up to four joints that moved in the last quiet window), or at rest only after `limit`."""
    last = after[-1]
    if last.time - since < QUIET_WINDOW - 0.05:
        moving = [joint for joint in JOINTS if joint in last.positions and tolerance <
                  (_joint_range(after, joint, last.time - QUIET_WINDOW, last.time) or 0.0)]
        return ["still moving {:.2f} s after disabled ({})".format(
            last.time - disable_sent,
            ", ".join(moving[:4]) + (" ..." if len(moving) > 4 else "") if moving else "the base")]
    if since - disable_sent > limit:
        return ["came to rest {:.2f} s after disabled (limit {:g} s)".format(since - disable_sent, limit)]
    return []


def _off_centre_problems(offsets: Sequence[Tuple[float, str]], expected: ExpectedMotion, last: JointSample,
                         tolerance: float) -> List[str]:
    """The problem, if any, of the joint resting farthest from its centre (`offsets`: (offset, joint))."""
    if not offsets or max(offsets)[0] <= tolerance:
        return []
    offset, joint = max(offsets)
    return ["{} rests at {}, {} from its centre {} (homeOnDisable true)".format(
        joint, format_number(last.positions[joint]), format_number(offset),
        format_number(expected.bounds[joint].centre))]


def _base_return(harness: HarnessConfiguration, config: Configuration,
                 observation: Observation) -> Tuple[float, float]:
    """How far the base rests from its heading at enable, and how far it may."""
    # The node turns the base back to its heading at enable (homeOnDisable). A velocity base
    # stopped mid-turn brakes at its acceleration limit: that turn is allowed for.
    reference = heading_at(observation.headings, observation.enable_sent)
    returned = abs(_wrap(observation.headings[-1].heading - reference))  # type: ignore[operator]
    return returned, return_tolerance(harness, config, observation.base_topic)


def _base_commands_after_disabled(observation: Observation) -> List[str]:
    """The base commands the node logged after disabled, as one line, to explain a base that did not
    stop as expected; nothing when there are none."""
    commands = ["{} turn {} rad at +{:.2f} s".format(entry.fields.get("purpose"),
                                                     format_number(entry.fields.get("angle", 0.0)),
                                                     entry_time(entry) - observation.disable_sent)
                for entry in observation.entries if entry.event == contract.BASE_COMMAND
                and entry_time(entry) >= observation.disable_sent - LOG_CLOCK_MARGIN]
    return ["base commands logged after disabled: " + ", ".join(commands)] if commands else []


def _stopped_detail(still_after: float, limit: float, offsets: Sequence[Tuple[float, str]],
                    returned: Optional[float]) -> str:
    """What a passed stop check found: when the robot came to rest, and how close to its centre and
    heading."""
    detail = "still from +{:.2f} s after disabled (limit {:g} s)".format(still_after, limit)
    if offsets:
        detail += ", at the centre (largest offset {})".format(format_number(max(offsets)[0]))
    if returned is not None:
        detail += ", the base back at its heading at enable (off by {} rad)".format(format_number(returned))
    return detail


def _evenly(items: Sequence, count: int) -> list:
    """`count` items spread evenly over `items`, first and last included."""
    if not items:
        return []
    return [items[round(index * (len(items) - 1) / max(1, count - 1))] for index in range(count)]


def _sample_rows(observation: Observation, expected: ExpectedMotion, count: int) -> Dict[str, List[List[float]]]:
    """`count` evenly spaced observed rows per expected part while enabled; the base as turns."""
    window = [sample for sample in observation.joints
              if observation.enable_sent <= sample.time <= observation.disable_sent]
    chosen = _evenly(window, count)
    rows: Dict[str, List[List[float]]] = OrderedDict()
    for key in expected.parts:
        joints = PARTS[key].joints
        rows[key] = [[sample.positions.get(joint, float("nan")) for joint in joints] for sample in chosen]
    if expected.base and observation.headings:
        reference = heading_at(observation.headings, observation.enable_sent)
        turns = [sample for sample in observation.headings
                 if observation.enable_sent <= sample.time <= observation.disable_sent]
        picked = _evenly(turns, count)
        rows[BASE] = [[_wrap(sample.heading - reference)] for sample in picked]  # type: ignore[operator]
    return rows


def evaluate_test(test: str, iteration: int, harness: HarnessConfiguration,
                  observation: Observation) -> HarnessOutcome:
    """Every check of one test, in the order of the report."""
    spec = TESTS[test]
    config = node_configuration(harness, test)
    expected = expected_motion(test, config.platform, config)
    checks = [check_reply("Animate behaviour enabled", observation.enable_reply),
              check_started(spec, config, observation),
              check_configuration_applied(observation),
              check_goal_parts(expected, observation),
              check_goal_bounds(expected, observation),
              check_goal_positions(expected, observation)]
    if "Leg" in expected.parts and config.motion_style == "random":  # the breathing style has no chunk pattern
        checks.append(check_leg_pattern(config, expected, observation))
    checks.append(check_parts_moved(harness, config, expected, observation))
    checks.append(check_observed_within_bounds(harness, config, expected, observation))
    if expected.base:
        checks.append(check_heading_bounded(harness, config, observation))
        if observation.base_topic and wheels_command_kind(observation.base_topic) != RELATIVE:
            checks.append(check_base_speed(config, observation))
    checks.extend([check_ended(spec, observation),
                   check_reply("Animate behaviour disabled", observation.disable_reply),
                   check_nothing_after_disabled(expected, observation),
                   check_observed_within_bounds(harness, config, expected, observation, returning=True),
                   check_motion_stopped(harness, config, expected, observation)])
    random_positions: Dict[str, List[List[float]]] = OrderedDict()
    random_count: Dict[str, int] = {}
    for goal in _animation_goals(observation):
        key = goal.fields.get("part")
        if key in PARTS and key not in random_positions:
            rows = goal.fields.get("positions") or []
            order = [(goal.fields.get("joints") or []).index(joint) if joint in (goal.fields.get("joints") or [])
                     else None for joint in PARTS[key].joints]
            random_positions[key] = [[row[index] if index is not None else float("nan") for index in order]
                                     for row in rows[:harness.report_samples]]
            random_count[key] = len(rows)
    source = "/joint_states" + ("; base: {}".format(observation.heading_source) if expected.base else "")
    return HarnessOutcome(test, iteration, config.platform, configuration_items(config), expected, tuple(checks),
                          random_positions, random_count, _sample_rows(observation, expected, harness.report_samples),
                          source)


def failure_message(outcome: HarnessOutcome) -> str:
    """One line per failed check: what went wrong."""
    return "\n".join("{} (iteration {}): {}: FAILED: {}".format(TESTS[outcome.test].title, outcome.iteration,
                                                                check.name, check.detail)
                     for check in outcome.failures)


def headings_from_commands(commands: Sequence[BaseCommand], relative: bool, start: float, end: float,
                           step: float = 0.02, velocity_timeout: float = BASE_VELOCITY_COMMAND_TIMEOUT
                           ) -> List[HeadingSample]:
    """The heading the commands ask for, from 0 at `start`: a relative topic turns by each angle at
    once (an upper bound of what the robot does), a velocity topic is integrated (zero-order hold,
    stopped `velocity_timeout` after the last command)."""
    samples = [HeadingSample(start, 0.0)]
    heading = 0.0
    if relative:
        for command in commands:
            if start <= command.time <= end:
                heading += command.angular_z
                samples.append(HeadingSample(command.time, heading))
        samples.append(HeadingSample(end, heading))
        return samples
    ordered = sorted((command for command in commands if command.time <= end), key=lambda command: command.time)
    following = 0  # index of the first command after `moment`: the one before it is in force
    moment = start
    while moment < end:
        nxt = min(end, moment + step)
        while following < len(ordered) and ordered[following].time <= moment:
            following += 1
        latest = ordered[following - 1] if following else None
        velocity = latest.angular_z if latest is not None and moment - latest.time <= velocity_timeout else 0.0
        heading += velocity * (nxt - moment)
        moment = nxt
        samples.append(HeadingSample(moment, heading))
    return samples
