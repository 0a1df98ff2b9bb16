"""What a person will see: figures of each motion style on the ideal controller, on the robot's driver and on
naoqi_driver fed by the joint_angles actuation (`make motion-report`, README: "Motion styles").

A run is computed, not recorded: the style's planners (`styles.MotionStyle`) give each part's goals, chained as the
node chains them (the random style's next goal when the previous one ends, the breathing style's before it ends),
each starting from what the controller executes; the controller's interpolation
(`pepper.trajectory_interpolation`) gives the commanded joints at 50 Hz; with the driver, `NaoqiDcmDriver` (the
physical robot's naoqi_dcm_driver: 12 Hz writes past a 0.09 rad dead band, 20 % speed) turns them into what the
robot executes; with joint_angles, the node's stream (`joint_angle_stream.tick` at its send times) feeds
`NaoqiDriver` (naoqi_driver's setAngles). Deterministic for a seed; a minute takes about a second. Pure Python
and numpy.
"""
import argparse
import sys
from typing import Dict, List, NamedTuple, Sequence, Tuple

import numpy

from cssr_system.animate_behaviour.configuration import load_configuration, shipped_configuration_path
from cssr_system.figure.clearance import (HAND_MARGIN, band_clearance, largest_quiet_selected_range, per_arm_lines,
                                          recorded_clearances)
from cssr_system.motion import joint_angle_stream
from cssr_system.motion.base_rotation import BaseRotationPlanner
from cssr_system.motion.modes import IDLE, MODES, shaped_motions, turns_base
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.trajectory_timing import to_points
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import (DRIVER_JOINT_PRECISION, JOINTS, MIRRORED_JOINTS, PARTS, VELOCITY,
                                            short_name)
from cssr_system.pepper.simulated_pepper import NaoqiDcmDriver, NaoqiDriver
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

SAMPLE_RATE = 50.0  # Hz
MOVING_SPEED = 0.005  # rad/s (unit/s for a hand): a joint slower than this counts as still
PERIOD_RANGE = (1.0, 30.0)  # s: the periods a person reads as a rhythm
# Peak to peak (rad; a hand's opening) a person sees without a dead band in the way: about a centimetre at a hand.
VISIBLE_AMPLITUDE = 0.02
EASE_IN_OFFSETS = (0.03, 0.1, 0.2)  # rad off the centres the ease-in is measured from (README: "Motion styles")
EASE_IN_SECONDS = 8.0  # s of each ease-in run: past the slowest approach, from a joint limit
BAND_TOLERANCE = 1e-6  # rad: a joint at its band's edge, or held at its centre, is in it
# A stroke of an arm: its speed (the norm of its joints' velocities) rising above BEAT_SPEED after falling below
# BEAT_REST; a stroke and its return make a beat (README: "Modes").
BEAT_SPEED, BEAT_REST = 0.3, 0.15  # rad/s
# The targets of the modes in the default configuration (README: "Modes"), each part's amplitude against idle's.
LISTENING_MOST = 0.35  # arms and hands: at most this share of idle's amplitude
SPEAKING_LEAST, SPEAKING_BEATS = 1.5, 40.0  # arms: at least this many times idle's amplitude, and beats a minute
TITLES = {"ideal": "ideal controller", "naoqi_dcm": "robot's driver (naoqi_dcm)",
          "joint_angles": "robot via joint_angles (naoqi_driver)"}


class JointFigures(NamedTuple):
    joint: str
    peak_to_peak: float  # executed, rad (opening for a hand)
    moving: float  # fraction of the time it moves
    period: float  # s, the dominant period in PERIOD_RANGE
    autocorrelation: float  # at that period: 1 repeats itself, 0 does not
    rms_speed: float
    rms_jerk: float
    side_correlation: float  # with the same joint of the other side (mirrored where the limits are); nan: none
    visible: bool  # peak to peak >= what shows: the driver's dead band, or VISIBLE_AMPLITUDE without one


class ChainedPlans:
    """A part's goals chained as the node chains them, each starting from the state of the previous one; sampled
    like one spline (`sample(t)` -> positions, velocities, accelerations)."""

    def __init__(self, plan, part: str, seconds: float, start=None) -> None:
        count = len(PARTS[part].joints)
        start = PARTS[part].centre if start is None else start
        state = (numpy.array(start, dtype=float), numpy.zeros(count), numpy.zeros(count))
        now, self.pieces = 0.0, []
        while now < seconds:
            timed = plan(now, *state)
            spline = JointTrajectorySpline(*state, to_points(timed), start_time=now)
            self.pieces.append(spline)
            replaced_after = plan.replacement_time(timed)
            now = spline.end_time if replaced_after is None else now + replaced_after
            state = tuple(numpy.asarray(values, dtype=float) for values in spline.sample(now))
        self._starts = numpy.array([spline.start_time for spline in self.pieces])

    def sample(self, t: float):
        return self.pieces[max(0, int(numpy.searchsorted(self._starts, t, side="right")) - 1)].sample(t)


def planned_run(config, seconds: float, seed: int, mode: str = IDLE) -> List[Tuple[Tuple[str, ...], ChainedPlans]]:
    """(joints, their chained plans) of each part the configuration animates, in `mode`."""
    style = MotionStyle(config, make_rng(seed), mode)
    return [(motion.joints, ChainedPlans(style.planner(motion), motion.part, seconds))
            for motion in shaped_motions(animated_parts(config, tuple(PARTS)), config, mode)]


def commanded_run(config, seconds: float, seed: int,
                  mode: str = IDLE) -> Tuple[numpy.ndarray, Tuple[str, ...], numpy.ndarray]:
    """(times, joint names, commanded positions (times x joints)) of the parts the configuration animates."""
    times = numpy.arange(0.0, seconds, 1.0 / SAMPLE_RATE)
    plans = planned_run(config, seconds, seed, mode)
    columns = [numpy.array([plan.sample(moment)[0] for moment in times]) for _, plan in plans]
    return times, tuple(name for joints, _ in plans for name in joints), numpy.hstack(columns)


def executed_by_joint_angles(times: numpy.ndarray, plans: List[Tuple[Tuple[str, ...], ChainedPlans]]) -> numpy.ndarray:
    """What naoqi_driver executes of each part's stream (the node's send times, its calls at once), at `times`."""
    columns = []
    for joints, plan in plans:
        driver = NaoqiDriver(joints, plan.sample(times[0])[0], times[0])
        origins, rows, sample = driver.state(times[0])[0], [], 0
        for now in joint_angle_stream.send_times(times[0], times[-1] + joint_angle_stream.PERIOD):
            while sample < len(times) and times[sample] < now:
                rows.append(driver.state(times[sample])[0])
                sample += 1
            tick = joint_angle_stream.tick(joints, plan, now, origins)
            for call in tick.messages:
                driver.set_angles(call.joint_names, call.joint_angles, call.speed, now)
            origins = tick.arrivals
        rows += [driver.state(moment)[0] for moment in times[sample:]]
        columns.append(numpy.array(rows))
    return numpy.hstack(columns)


def band_entry_times(times: numpy.ndarray, positions: numpy.ndarray, lower, upper,
                     tolerance: float = BAND_TOLERANCE) -> numpy.ndarray:
    """Per joint (a column of `positions`), the first of `times` from which it stays in [lower, upper]: when it
    entered its band for good (inf: still outside at the end)."""
    outside = (positions < numpy.asarray(lower) - tolerance) | (positions > numpy.asarray(upper) + tolerance)
    entry = numpy.zeros(positions.shape[1])
    for column in range(positions.shape[1]):
        late = numpy.flatnonzero(outside[:, column])
        if late.size:
            entry[column] = times[late[-1] + 1] if late[-1] + 1 < len(times) else float("inf")
    return entry


def off_centre_starts(motion, offsets: Sequence[float] = EASE_IN_OFFSETS):
    """(offset, positions): the part's joints all `offset` from their centres, on one side, then on the other
    (alternating between joints, so that a part's joints start on both sides of their bands), within the limits."""
    lower = [JOINTS[name].lower for name in motion.joints]
    upper = [JOINTS[name].upper for name in motion.joints]
    pattern = numpy.resize([1.0, -1.0], len(motion.joints))
    for offset in offsets:
        for side in (1.0, -1.0):
            yield side * offset, numpy.clip(numpy.array(PARTS[motion.part].centre) + side * offset * pattern,
                                            lower, upper)


def far_starts(motion):
    """The part's joints at the limit farthest from each joint's centre (the longest approach of all)."""
    centre = numpy.array(PARTS[motion.part].centre)
    lower = numpy.array([JOINTS[name].lower for name in motion.joints])
    upper = numpy.array([JOINTS[name].upper for name in motion.joints])
    return numpy.where(centre - lower > upper - centre, lower, upper)


def ease_in(config, seed: int, actuation: str, starts=off_centre_starts) -> Dict[str, float]:
    """Per moving joint, the latest time (s after the enable) at which it enters its band for good, over the
    `starts` of its part, on the ideal controller ("ideal") or through naoqi_driver ("joint_angles")."""
    times = numpy.arange(0.0, EASE_IN_SECONDS, 1.0 / SAMPLE_RATE)
    worst: Dict[str, float] = {}
    for motion in animated_parts(config, tuple(PARTS)):
        for _, start in _starts_of(starts, motion):
            plan = ChainedPlans(MotionStyle(config, make_rng(seed)).planner(motion), motion.part, EASE_IN_SECONDS,
                                start)
            if actuation == "joint_angles":
                positions = executed_by_joint_angles(times, [(motion.joints, plan)])
            else:
                positions = numpy.array([plan.sample(moment)[0] for moment in times])
            entry = band_entry_times(times, positions, [b.lower for b in motion.bounds],
                                     [b.upper for b in motion.bounds])
            for name, moving, seconds in zip(motion.joints, motion.moving, entry):
                if moving:
                    worst[name] = max(worst.get(name, 0.0), float(seconds))
    return worst


def _starts_of(starts, motion):
    """`starts(motion)` as (label, positions) pairs: a generator of them, or one array of positions."""
    chosen = starts(motion)
    return [(None, chosen)] if isinstance(chosen, numpy.ndarray) else chosen


def format_ease_in(style: str, rows: Dict[str, Dict[str, float]]) -> str:
    """One line per actuation: the latest entry into the bands from the off-centre starts and its joint; then the
    farthest starts' (a joint at a limit), bound by the speed cap."""
    lines = ["== style %s, ease-in: s after an enable (or a resume) until every joint is in its band, from %s rad "
             "off the centres" % (style, "/".join("%g" % offset for offset in EASE_IN_OFFSETS))]
    for label, worst in rows.items():
        joint = max(worst, key=worst.get)
        lines.append("%-40s %5.2f s (%s)" % (label, worst[joint], joint))
    return "\n".join(lines)


def executed_by_driver(times: numpy.ndarray, names: Sequence[str], commanded: numpy.ndarray) -> numpy.ndarray:
    driver = NaoqiDcmDriver(names, commanded[0], times[0])
    return numpy.array([driver.update(row, moment)[0] for moment, row in zip(times, commanded)])


def _dominant_period(signal: numpy.ndarray) -> Tuple[float, float]:
    """(period, autocorrelation at that lag) of the strongest rhythm in PERIOD_RANGE; (nan, nan) for a still joint."""
    centred = signal - signal.mean()
    if numpy.ptp(signal) < 1e-9:
        return float("nan"), float("nan")
    frequencies = numpy.fft.rfftfreq(len(centred), d=1.0 / SAMPLE_RATE)
    spectrum = numpy.abs(numpy.fft.rfft(centred))
    usable = (frequencies >= 1.0 / PERIOD_RANGE[1]) & (frequencies <= 1.0 / PERIOD_RANGE[0])
    if not usable.any():
        return float("nan"), float("nan")
    period = 1.0 / frequencies[usable][numpy.argmax(spectrum[usable])]
    lag = int(round(period * SAMPLE_RATE))
    if lag >= len(centred) - 2:
        return period, float("nan")
    return period, float(numpy.corrcoef(centred[:-lag], centred[lag:])[0, 1])


def figures(times: numpy.ndarray, names: Sequence[str], positions: numpy.ndarray,
            visible_from: float = DRIVER_JOINT_PRECISION) -> List[JointFigures]:
    dt = 1.0 / SAMPLE_RATE
    velocities = numpy.gradient(positions, dt, axis=0)
    jerks = numpy.gradient(numpy.gradient(velocities, dt, axis=0), dt, axis=0)
    index = {name: column for column, name in enumerate(names)}
    result = []
    for column, name in enumerate(names):
        signal = positions[:, column]
        period, autocorrelation = _dominant_period(signal)
        other = ("L" if name.startswith("R") else "R") + name[1:] if name[0] in "LR" else None
        side = float("nan")
        if other in index and numpy.ptp(signal) > 1e-9 and numpy.ptp(positions[:, index[other]]) > 1e-9:
            sign = -1.0 if short_name(name) in MIRRORED_JOINTS else 1.0
            side = float(numpy.corrcoef(signal, sign * positions[:, index[other]])[0, 1])
        peak_to_peak = float(numpy.ptp(signal))
        moving = float(numpy.mean(numpy.abs(velocities[:, column]) > MOVING_SPEED))
        result.append(JointFigures(name, peak_to_peak, moving,
                                   period, autocorrelation, float(numpy.sqrt(numpy.mean(velocities[:, column] ** 2))),
                                   float(numpy.sqrt(numpy.mean(jerks[:, column] ** 2))), side,
                                   peak_to_peak >= visible_from))
    return result


def format_table(title: str, rows: Sequence[JointFigures]) -> str:
    lines = [title, "%-15s %8s %7s %8s %8s %9s %10s %6s %8s" % (
        "joint", "p2p", "moving", "period", "autocor", "rms speed", "rms jerk", "sides", "visible")]
    for row in rows:
        lines.append("%-15s %8.3f %6.0f%% %7.1fs %8.2f %9.3f %10.1f %6.2f %8s" % (
            row.joint, row.peak_to_peak, 100 * row.moving, row.period, row.autocorrelation, row.rms_speed,
            row.rms_jerk, row.side_correlation, "yes" if row.visible else "no"))
    return "\n".join(lines)


def report(config_file: str, seconds: float, seed: int) -> Dict[Tuple[str, str], List[JointFigures]]:
    result = {}
    for style in ("random", "breathing"):
        config = load_configuration(config_file, {"behaviour": "body", "platform": "robot", "motionStyle": style,
                                                  "randomSeed": seed})
        times, names, commanded = commanded_run(config, seconds, seed)
        result[(style, "ideal")] = figures(times, names, commanded)
        result[(style, "naoqi_dcm")] = figures(times, names, executed_by_driver(times, names, commanded))
        result[(style, "joint_angles")] = figures(times, names, executed_by_joint_angles(
            times, planned_run(config, seconds, seed)), VISIBLE_AMPLITUDE)
    return result


class PartFigures(NamedTuple):
    """What a person sees of one part in a mode (README: "Modes")."""

    part: str
    amplitude: float  # the mean peak to peak of its moving joints (rad; a hand: its opening); the base: its turns, rad
    speed: float  # typical speed: the mean RMS speed of its moving joints (rad/s); the base: its peak, rad/s
    beats: float  # beats a minute (the arms; nan for the other parts)


def arm_beats(times: numpy.ndarray, positions: numpy.ndarray) -> float:
    """Beats a minute of an arm (`positions`: its joints' columns): half its strokes, each its speed rising above
    BEAT_SPEED after falling below BEAT_REST."""
    speed = numpy.linalg.norm(numpy.gradient(positions, 1.0 / SAMPLE_RATE, axis=0), axis=1)
    strokes, resting = 0, True
    for value in speed:
        if resting and value > BEAT_SPEED:
            strokes, resting = strokes + 1, False
        elif value < BEAT_REST:
            resting = True
    return 60.0 * strokes / 2.0 / (times[-1] - times[0])


def base_turns(config, seconds: float, seed: int, mode: str) -> PartFigures:
    """The base's turns a minute in `mode` (where the behaviour has rotation; on a velocity topic): how many, as
    `amplitude` the largest, as `speed` the peak angular speed."""
    if not (turns_base(mode) and "rotation" in config.behaviour and config.turn_base):
        return PartFigures("base", 0.0, 0.0, float("nan"))
    style = MotionStyle(config, make_rng(seed), mode)
    planner = BaseRotationPlanner(VELOCITY, config.rot_maximum_range * style.base_speed_share, config.heading_bound,
                                  make_rng(seed), pause_range=style.base_pauses)
    elapsed, turns, largest, peak = 0.0, 0, 0.0, 0.0
    while elapsed < seconds:
        step = planner.next_step()
        if step is None:
            break
        elapsed, turns = elapsed + step.duration, turns + 1
        largest, peak = max(largest, abs(step.angle)), max([peak] + [abs(v) for v in step.velocities])
    return PartFigures("base", largest, peak, 60.0 * turns / seconds)


def mode_figures(config, seconds: float, seed: int, mode: str) -> List[PartFigures]:
    """Each part's figures in `mode` on the ideal controller (the base: `base_turns`, its turns a minute as beats)."""
    times, names, commanded = commanded_run(config, seconds, seed, mode)
    rows = []
    for motion in animated_parts(config, tuple(PARTS)):
        columns = [names.index(name) for name, moving in zip(motion.joints, motion.moving) if moving]
        joints = figures(times, [names[column] for column in columns], commanded[:, columns])
        beats = arm_beats(times, commanded[:, columns]) if motion.part in ("RArm", "LArm") else float("nan")
        rows.append(PartFigures(motion.part, float(numpy.mean([row.peak_to_peak for row in joints])),
                                float(numpy.mean([row.rms_speed for row in joints])), beats))
    return rows + [base_turns(config, seconds, seed, mode)]


def modes_report(config_file: str, seconds: float, seed: int) -> Dict[Tuple[str, str], List[PartFigures]]:
    """Per style and mode: `mode_figures` (behaviour all, robot)."""
    result = {}
    for style in ("random", "breathing"):
        config = load_configuration(config_file, {"behaviour": "all", "platform": "robot", "motionStyle": style,
                                                  "randomSeed": seed})
        for mode in MODES:
            result[(style, mode)] = mode_figures(config, seconds, seed, mode)
    return result


def _ratio(value: float, idle: float) -> str:
    if numpy.isnan(value) or numpy.isnan(idle):
        return "     "
    return "%4.2fx" % (value / idle) if idle > 0 else ("   0x" if value == 0 else "  new")


COLUMNS = ("mode", "part", "p2p", "ratio", "speed", "ratio", "beats", "ratio")


def format_modes(style: str, tables: Dict[str, List[PartFigures]], seconds: float, seed: int) -> str:
    """One table of a style: per mode and part, each figure and its ratio to idle's (the base: turns a minute, the
    largest turn and the peak speed)."""
    lines = ["== style %s, modes on the ideal controller (%.0f s, seed %d): peak to peak (base: largest turn), "
             "typical speed (base: peak), arm beats a minute (base: turns a minute), each with its ratio to idle's"
             % (style, seconds, seed),
             "%-10s %-6s %8s %6s %9s %6s %7s %6s" % COLUMNS]
    idle = {row.part: row for row in tables[IDLE]}
    for mode, rows in tables.items():
        for row in rows:
            base = idle[row.part]
            lines.append("%-10s %-6s %8.3f %6s %9.3f %6s %7.1f %6s" % (
                mode, row.part, row.amplitude, _ratio(row.amplitude, base.amplitude), row.speed,
                _ratio(row.speed, base.speed), row.beats, _ratio(row.beats, base.beats)))
    return "\n".join(lines).replace(" nan", "   -")


def mode_targets(tables: Dict[str, List[PartFigures]]) -> List[Tuple[str, bool]]:
    """(target, met) of each mode's targets (README: "Modes") in one style's tables."""
    idle = {row.part: row for row in tables[IDLE]}
    listening = {row.part: row for row in tables["listening"]}
    speaking = {row.part: row for row in tables["speaking"]}
    arms = [part for part in ("RArm", "LArm") if part in idle]
    hands = [part for part in ("RHand", "LHand") if part in idle]
    return [
        ("listening: arm and hand amplitude <= %.0f %% of idle's" % (100 * LISTENING_MOST),
         all(listening[part].amplitude <= LISTENING_MOST * idle[part].amplitude for part in arms + hands)),
        ("listening: no base turn", listening["base"].beats == 0 or numpy.isnan(listening["base"].beats)),
        ("speaking: arm amplitude >= %.1f x idle's" % SPEAKING_LEAST,
         all(speaking[part].amplitude >= SPEAKING_LEAST * idle[part].amplitude for part in arms)),
        ("speaking: >= %.0f arm beats a minute" % SPEAKING_BEATS,
         all(speaking[part].beats >= SPEAKING_BEATS for part in arms)),
        ("speaking: no base turn", speaking["base"].beats == 0 or numpy.isnan(speaking["base"].beats)),
    ]


def ease_in_report(config_file: str, seed: int) -> Dict[str, Dict[str, Dict[str, float]]]:
    """Per style, per actuation (and from the joint limits, on the ideal controller): `ease_in`."""
    result = {}
    for style in ("random", "breathing"):
        config = load_configuration(config_file, {"behaviour": "body", "platform": "robot", "motionStyle": style,
                                                  "randomSeed": seed})
        result[style] = {TITLES["ideal"]: ease_in(config, seed, "ideal"),
                         TITLES["joint_angles"]: ease_in(config, seed, "joint_angles"),
                         "from a joint limit (ideal controller)": ease_in(config, seed, "ideal", far_starts)}
    return result


def style_clearances(config, seconds: float, seed: int, mode: str = IDLE):
    """(times, each arm's smallest clearance) of the style's commanded run in `mode` at intensity 1
    (`figure.clearance`)."""
    times, names, commanded = commanded_run(config._replace(intensity=1.0), seconds, seed, mode)
    return times, recorded_clearances(names, commanded)


def clearance_configurations(config_file: str) -> List[Tuple[str, Dict[str, object]]]:
    """(title, overrides) of the configurations the clearance report measures: the shipped ranges, the largest the
    configuration check accepts without a warning, and every range at its largest (1)."""
    base = {"behaviour": "body", "platform": "robot"}
    quiet = largest_quiet_selected_range(load_configuration(config_file, base))
    widest = dict(base, selectedRange=1.0, armMaximumRange="1,1,1,1,1", legMaximumRange="1,1,1")
    return [("the file's ranges", base), ("largest without a warning: selectedRange %g" % quiet,
                                          dict(base, selectedRange=quiet)), ("every range at 1", widest)]


def clearance_report(config_file: str, seconds: float, seed: int) -> List[str]:
    """Lines: per configuration, the hands' closest approach anywhere in their bands and, per style and mode, each
    arm's smallest clearance over the commanded run, with the pair of solids and the instant."""
    lines = ["== clearance of the arms (body model of doc/figure.md; intensity 1; %.0f s, seed %d; warning under "
             "%.0f cm)" % (seconds, seed, 100 * HAND_MARGIN)]
    for title, overrides in clearance_configurations(config_file):
        config = load_configuration(config_file, overrides)
        band = band_clearance(config._replace(intensity=1.0)).closest
        lines.append("%s: a hand anywhere in its band %.1f cm (%s - %s)" % (title, 100 * band.distance, band.solid,
                                                                            band.other))
        for style, mode in [(style, mode) for style in ("random", "breathing") for mode in MODES]:
            times, found = style_clearances(config._replace(motion_style=style), seconds, seed, mode)
            lines.extend("  %-9s %-9s %s" % (style, mode, line) for line in per_arm_lines(found, times))
    return lines


def print_modes(config_file: str, seconds: float, seed: int) -> None:
    """The modes' tables and whether each target is met (README: "Modes")."""
    tables = modes_report(config_file, seconds, seed)
    for style in ("random", "breathing"):
        by_mode = {mode: tables[(style, mode)] for mode in MODES}
        print(format_modes(style, by_mode, seconds, seed))
        print("\n".join("  %s: %s" % ("met" if met else "NOT MET", target) for target, met in mode_targets(by_mode)))
        print()


def main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(prog="motion report", description="What a person sees of each motion style, "
                                     "on the ideal controller, on the robot's driver and on naoqi_driver fed by the "
                                     "joint_angles actuation (behaviour body, robot).")
    parser.add_argument("--config", default=None, help="configuration file (default: the shipped one)")
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=1)
    arguments = parser.parse_args(argv)
    try:
        tables = report(arguments.config or shipped_configuration_path(), arguments.seconds, arguments.seed)
    except (OSError, ValueError) as error:
        print("motion report: error: %s" % error, file=sys.stderr)
        return 1
    for (style, driver), rows in tables.items():
        print(format_table("== style %s, %s (%.0f s, seed %d)" % (style, TITLES[driver], arguments.seconds,
                                                                  arguments.seed), rows))
        print()
    print_modes(arguments.config or shipped_configuration_path(), arguments.seconds, arguments.seed)
    for style, rows in ease_in_report(arguments.config or shipped_configuration_path(), arguments.seed).items():
        print(format_ease_in(style, rows))
        print()
    try:
        print("\n".join(clearance_report(arguments.config or shipped_configuration_path(), arguments.seconds,
                                         arguments.seed)))
    except (OSError, ValueError) as error:
        print("motion report: error: %s" % error, file=sys.stderr)
        return 1
    return 0
