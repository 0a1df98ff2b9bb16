"""The plot of a recorded run, and the plotAnimation command.

The plot (`plot_recording`, matplotlib's Agg backend, a PNG): one panel per animated part (each
joint a line, its allowed band [lower, upper] shaded in the line's colour, and, when the recording
has it, what the node commanded as a dashed line of the same colour), one panel of the base heading
with its bound around the heading at enable, the enable/disable instants as vertical lines in every
panel, and the recording's marks (e.g. another node's goal) as labelled grey spans in their part's
panel. Each panel's title says whether every measured sample stayed in its band.

Pure Python, numpy and matplotlib: no ROS import.
"""
import argparse
import datetime
import math
import os
import sys
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import numpy

from cssr_system.animate_behaviour.contract import ENABLED
from cssr_system.pepper.joint_table import PARTS, centre_of
from cssr_system.recording.recording import (BAND_TOLERANCE, Recording, heading_at_time,
                                             band_excess, enabled_intervals,
                                             heading_excess, mode_spans, plotted_parts,
                                             bands_from_configuration_file, bands_from_log,
                                             read_recording)


def _title_of(recording: Recording) -> str:
    moment = datetime.datetime.fromtimestamp(recording.start_epoch).strftime("%Y-%m-%d %H:%M:%S")
    details = ", ".join("%s %s" % (key, value) for key, value in recording.info.items()
                        if key in ("behaviour", "platform"))
    return "animateBehaviour: joints and base heading over time" + \
        ("  (%s; %s)" % (details, moment) if details else "  (%s)" % moment)


def _draw_activations(axis: Any, recording: Recording) -> None:
    for time, state in recording.activations:
        if state == ENABLED:
            axis.axvline(time, color="tab:green", linewidth=1.6)
        else:
            axis.axvline(time, color="tab:red", linewidth=1.6, linestyle="--")


def _darker(colour: str) -> Tuple[float, float, float]:
    from matplotlib.colors import to_rgb
    return tuple(0.55 * channel for channel in to_rgb(colour))


MARK_COLOUR = "tab:purple"
MARK_ALPHA = 0.14


def _draw_marks(axis: Any, recording: Recording, part_keys: Sequence[str]) -> None:
    """The marks of these parts (and those of every panel) as shaded spans, labelled at the top."""
    for mark in recording.marks:
        if mark.part and mark.part not in part_keys:
            continue
        axis.axvspan(mark.start, max(mark.end, mark.start + 0.05), color=MARK_COLOUR, alpha=MARK_ALPHA, linewidth=0)
        axis.axvline(mark.start, color=MARK_COLOUR, linewidth=1.0, alpha=0.8)
        axis.axvline(mark.end, color=MARK_COLOUR, linewidth=1.0, alpha=0.8, linestyle=":")
        axis.annotate(mark.label, xy=(mark.start, 0.0), xycoords=("data", "axes fraction"),
                      xytext=(3, 3), textcoords="offset points", ha="left", va="bottom", fontsize=8,
                      color=MARK_COLOUR, bbox=dict(boxstyle="round,pad=0.2", facecolor="white", alpha=0.8,
                                                   edgecolor="none"))


# The modes shaded: idle is the motion of every plot, the plain background.
MODE_COLOURS = {"listening": "tab:cyan", "speaking": "gold"}
MODE_ALPHA = 0.16


def _draw_modes(axis: Any, recording: Recording) -> None:
    """The spans of the shaded modes, behind the lines, labelled at the top of the panel."""
    for start, end, mode in mode_spans(recording):
        if mode not in MODE_COLOURS:
            continue
        axis.axvspan(start, end, color=MODE_COLOURS[mode], alpha=MODE_ALPHA, linewidth=0, zorder=0)
        axis.annotate(mode, xy=(start, 1.0), xycoords=("data", "axes fraction"), xytext=(3, -3),
                      textcoords="offset points", ha="left", va="top", fontsize=8, color=_darker(MODE_COLOURS[mode]))


def time_origin(recording: Recording) -> float:
    """Time shown as 0 in the plot: the first enable, else the start of the recording."""
    enables = [time for time, state in recording.activations if state == ENABLED]
    return enables[0] if enables else 0.0


def plot_recording(recording: Recording, output_path: str, title: Optional[str] = None) -> str:
    """Plot `recording` into the PNG `output_path` (module docstring); returns its absolute path."""
    import matplotlib
    matplotlib.use("Agg")  # no display needed; safe when pyplot was not imported before
    import matplotlib.pyplot as pyplot
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    origin = time_origin(recording)
    commanded = recording.commanded
    shifted = recording._replace(times=recording.times - origin,
                                 heading_times=recording.heading_times - origin,
                                 activations=tuple((time - origin, state) for time, state in recording.activations),
                                 commanded=None if commanded is None else commanded._replace(
                                     times=commanded.times - origin),
                                 marks=tuple(mark._replace(start=mark.start - origin, end=mark.end - origin)
                                             for mark in recording.marks),
                                 band_changes=tuple(change._replace(time=change.time - origin)
                                                    for change in recording.band_changes),
                                 modes=tuple((time - origin, mode) for time, mode in recording.modes))
    parts = plotted_parts(shifted)
    panels = len(parts) + 1  # the base heading last
    columns = 2 if panels > 3 else 1
    rows = int(math.ceil(panels / float(columns)))
    figure, axes = pyplot.subplots(rows, columns, figsize=(8.0 * columns, 3.4 * rows + 1.0),
                                   sharex=True, squeeze=False)
    flat_axes = [axis for row in axes for axis in row]
    colours = pyplot.rcParams["axes.prop_cycle"].by_key()["color"]
    for index, (label, joints) in enumerate(parts):
        part_keys = [key for key, part in PARTS.items() if part.joints == joints]
        _plot_part(flat_axes[index], shifted, label, joints, colours, part_keys)
        _draw_marks(flat_axes[index], shifted, part_keys)
        _draw_modes(flat_axes[index], shifted)
    _plot_heading(flat_axes[len(parts)], shifted)
    _draw_modes(flat_axes[len(parts)], shifted)
    for axis in flat_axes[panels:]:
        axis.set_visible(False)
    enabled = any(state == ENABLED for _, state in recording.activations)
    x_label = "time since enabled (s)" if enabled else "time since the recording started (s)"
    for column in range(columns):  # x labels under the lowest visible panel of each column
        for row in reversed(range(rows)):
            if row * columns + column < panels:
                axes[row][column].set_xlabel(x_label)
                axes[row][column].tick_params(labelbottom=True)
                break
    figure.suptitle(title or _title_of(recording), fontsize=13)
    key = [Line2D([], [], color="tab:green", linewidth=1.6, label="enabled"),
           Line2D([], [], color="tab:red", linewidth=1.6, linestyle="--", label="disabled"),
           Patch(facecolor="grey", alpha=0.25, label="allowed band of the joint of the same colour"),
           Line2D([], [], color="grey", linewidth=0.8, linestyle=":", label="band edges; alone: joint held")]
    if recording.commanded is not None:
        source = recording.commanded.source or "the node"
        key.append(Line2D([], [], color="grey", linewidth=1.1, linestyle="--",
                          label="commanded by %s (dashed, darker shade of the joint's colour)" % source))
    if changing_bands(recording):
        key.append(Line2D([], [], color="grey", linewidth=1.0, linestyle="-.",
                          label="band edges as the settings change"))
    if recording.marks:
        key.append(Patch(facecolor=MARK_COLOUR, alpha=MARK_ALPHA,
                         label="another node's goal (label: sender, result), or a change of settings"))
    shown_modes = {mode for _, _, mode in mode_spans(recording)}
    key += [Patch(facecolor=colour, alpha=2 * MODE_ALPHA, label="%s (the node's mode)" % mode)
            for mode, colour in MODE_COLOURS.items() if mode in shown_modes]
    key_rows = 1 if len(key) <= 4 else 2
    figure.legend(handles=key, loc="upper center", ncol=int(math.ceil(len(key) / float(key_rows))), fontsize=9,
                  frameon=False, bbox_to_anchor=(0.5, 0.965))
    figure.tight_layout(rect=(0, 0, 1, 0.94 - 0.02 * (key_rows - 1)))
    output_path = os.path.abspath(output_path)
    os.makedirs(os.path.dirname(output_path), exist_ok=True)
    figure.savefig(output_path, dpi=100)
    pyplot.close(figure)
    return output_path


def changing_bands(recording: Recording) -> Dict[str, list]:
    """The band changes of each joint whose band changed during the run (a change of live settings)."""
    by_joint: Dict[str, list] = {}
    for change in recording.band_changes:
        by_joint.setdefault(change.joint, []).append(change)
    return {name: changes for name, changes in by_joint.items() if len(changes) > 1}


def _draw_band_changes(axis: Any, recording: Recording, name: str, colour: str) -> None:
    """A joint's band edges over time, as steps, where its band changed during the run."""
    changes = changing_bands(recording).get(name)
    if not changes:
        return
    end = float(recording.times[-1]) if len(recording.times) else changes[-1].time
    times = [change.time for change in changes] + [max(end, changes[-1].time)]
    for edge in ("lower", "upper"):
        values = [getattr(change, edge) for change in changes]
        axis.step(times, values + values[-1:], where="post", color=colour, linewidth=1.0, alpha=0.9,
                  linestyle="-.")


def _plot_part(axis: Any, recording: Recording, label: str, joints: Sequence[str],
               colours: Sequence[str], part_keys: Sequence[str]) -> None:
    worst_joint, worst = "", 0.0
    for index, name in enumerate(joints):
        colour = colours[index % len(colours)]
        band = recording.bands.get(name)
        if band is not None and band.moving:
            axis.axhspan(band.lower, band.upper, color=colour, alpha=0.13, linewidth=0)
            axis.axhline(band.lower, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
            axis.axhline(band.upper, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
        elif band is not None:
            axis.axhline(band.centre, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
        _draw_band_changes(axis, recording, name, colour)
        if name in recording.joint_names:
            values = recording.positions[:, recording.joint_names.index(name)]
            shown = name + ("" if band is None or band.moving else " (held)")
            axis.plot(recording.times, values, color=colour, linewidth=1.3, label=shown)
        commanded = recording.commanded
        if commanded is not None and name in commanded.joint_names:
            # Darker than the measured line, so it stays visible where the two coincide.
            axis.plot(commanded.times, commanded.positions[:, commanded.joint_names.index(name)],
                      color=_darker(colour), linewidth=1.0, linestyle=(0, (4, 3)))
        excess = band_excess(recording, name)
        if excess > worst:
            worst_joint, worst = name, excess
    _draw_activations(axis, recording)
    verdict = "every joint within its band" if worst <= BAND_TOLERANCE else \
        "%s %.3f beyond its band" % (worst_joint, worst)
    if any(mark.part in part_keys for mark in recording.marks):
        verdict += " (another node's goals aside)"
    axis.set_title("%s: %s" % (label, verdict), fontsize=11,
                   color="black" if worst <= BAND_TOLERANCE else "tab:red")
    hand = all(name.endswith("Hand") for name in joints)
    axis.set_ylabel("opening (0 closed, 1 open)" if hand else "angle (rad)")
    axis.grid(True, alpha=0.3)
    _leave_room_for_legend(axis)
    axis.legend(loc="upper left", fontsize=8, ncol=min(len(joints), 5), framealpha=0.85,
                handlelength=1.5, columnspacing=1.0)


def _leave_room_for_legend(axis: Any) -> None:
    bottom, top = axis.get_ylim()
    axis.set_ylim(bottom, top + 0.22 * (top - bottom))


def _plot_heading(axis: Any, recording: Recording) -> None:
    if len(recording.headings):
        axis.plot(recording.heading_times, recording.headings, color="tab:blue", linewidth=1.4,
                  label="heading")
    if recording.heading_bound is not None:
        labelled = False
        for start, end in enabled_intervals(recording):
            reference = heading_at_time(recording, start)
            if reference is None:
                continue
            axis.fill_between([start, end], reference - recording.heading_bound,
                              reference + recording.heading_bound, color="tab:blue", alpha=0.12,
                              linewidth=0,
                              label=None if labelled else "bound: heading at enable \u00b1 %.2f rad"
                              % recording.heading_bound)
            labelled = True
        excess = heading_excess(recording)
        verdict = "within its bound" if excess <= BAND_TOLERANCE else "%.3f rad beyond its bound" % excess
    else:
        verdict = "base not animated (no bound)"
    _draw_activations(axis, recording)
    topic = " (%s)" % recording.heading_topic if recording.heading_topic else ""
    axis.set_title("base heading%s: %s" % (topic, verdict), fontsize=11)
    axis.set_ylabel("heading (rad)")
    axis.grid(True, alpha=0.3)
    bottom, top = axis.get_ylim()
    if top - bottom < 0.2:  # a still base: show a readable scale, not float noise
        middle = (top + bottom) / 2.0
        axis.set_ylim(middle - 0.1, middle + 0.1)
    _leave_room_for_legend(axis)
    axis.legend(loc="upper left", fontsize=8, ncol=2, framealpha=0.85)


def robots_timeline(recordings: Mapping[str, Recording]) -> Dict[str, Tuple[numpy.ndarray, numpy.ndarray, list]]:
    """Per robot: (times, each joint's offset from its centre, the activations), on one clock whose 0 is the first
    enable of any robot (else the earliest recording's start), for robots recorded side by side."""
    starts = [recording.start_epoch + time_origin(recording) for recording in recordings.values()]
    origin = min(starts) if starts else 0.0
    animated = {joint for part in PARTS.values() for joint in part.joints}
    timeline = {}
    for robot, recording in recordings.items():
        shift = recording.start_epoch - origin
        centres = numpy.array([centre_of(name) if name in animated else numpy.nan for name in recording.joint_names])
        offsets = recording.positions - centres if len(recording.times) else recording.positions
        timeline[robot] = (recording.times + shift, offsets,
                           [(time + shift, state) for time, state in recording.activations])
    return timeline


def plot_robots(recordings: Mapping[str, Recording], output_path: str) -> str:
    """The robots' motion over time in one PNG, a panel per robot on a shared time axis: every animated joint's
    offset from its centre, and that robot's own enables and disables. Returns the plot's absolute path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot

    timeline = robots_timeline(recordings)
    figure, axes = pyplot.subplots(len(timeline), 1, figsize=(12.0, 3.0 * len(timeline) + 1.0), sharex=True,
                                   squeeze=False)
    for axis, (robot, (times, offsets, activations)) in zip(axes[:, 0], sorted(timeline.items())):
        for column in range(offsets.shape[1] if offsets.ndim == 2 else 0):
            if numpy.any(numpy.isfinite(offsets[:, column])):
                axis.plot(times, offsets[:, column], linewidth=0.8)
        for time, state in activations:
            axis.axvline(time, color="tab:green" if state == ENABLED else "tab:red",
                         linestyle="-" if state == ENABLED else "--", linewidth=1.6)
        axis.set_ylabel("%s\noffset from centre (rad)" % robot)
    axes[-1][0].set_xlabel("time since the first enable (s); green: enabled, red dashed: disabled")
    figure.suptitle("animateBehaviour on %d robots: every joint, each robot with its own enable and disable"
                    % len(timeline), fontsize=13)
    figure.tight_layout(rect=(0, 0, 1, 0.95))
    output_path = os.path.abspath(output_path)
    os.makedirs(os.path.dirname(output_path), exist_ok=True)
    figure.savefig(output_path, dpi=100)
    pyplot.close(figure)
    return output_path


PLOT_COMMAND_USAGE = """plotAnimation: plots a recorded animateBehaviour run (joints, their bands, base heading).

rosrun cssr_system plotAnimation.py RECORDING [--log LOGFILE] [--config FILE] [-o OUT.png]
rosrun cssr_system plotAnimation.py RECORDING RECORDING ... -o OUT.png   (robots side by side, README "Several robots")

RECORDING is a recording file (format: cssr_system.recording.recording), e.g. the demo's
<workspace>/demo/animation.json. The allowed band of each joint comes from the node's log file when
--log is given (its goal_sent entries during the run), else from the recording itself, else from
the configuration (--config, default the package's, with the recording's platform and behaviour).
The plot goes to OUT.png (default: RECORDING with the extension .png); its path is printed.
"""


def main(argv):
    parser = argparse.ArgumentParser(prog="plotAnimation.py", description=PLOT_COMMAND_USAGE.split("\n\n")[0])
    parser.add_argument("recording", nargs="+", help="recording file (.json) of a run; several: one per robot, "
                        "plotted on one time axis (named after their folders)")
    parser.add_argument("--log", help="the node's log file of that run: bands from its goal_sent entries")
    parser.add_argument("--config", help="configuration file for the bands when neither --log nor the "
                                         "recording has them (default: the package's)")
    parser.add_argument("-o", "--output", help="PNG to write (default: RECORDING with .png)")
    arguments = parser.parse_args([argument for argument in argv if not argument.startswith("__")])
    if len(arguments.recording) > 1:
        return plot_robots_command(arguments.recording, arguments.output)
    arguments.recording = arguments.recording[0]
    try:
        recording = read_recording(arguments.recording)
        if arguments.log:
            from cssr_system.animate_behaviour.event_log import read_log
            end = recording.start_epoch + max(
                [0.0] + list(recording.times[-1:]) + list(recording.heading_times[-1:]))
            bands, heading_bound = bands_from_log(read_log(arguments.log), since=recording.start_epoch - 1.0,
                                                  until=end + 1.0)
            if not bands:
                raise ValueError("%s: no goal_sent entries during the recorded run" % arguments.log)
            recording = recording._replace(bands=bands, heading_bound=heading_bound)
        elif arguments.config or not recording.bands:
            from cssr_system.animate_behaviour.configuration import shipped_configuration_path
            config_file = arguments.config or shipped_configuration_path()
            overrides = {key: recording.info[key] for key in ("platform", "behaviour") if recording.info.get(key)}
            bands, heading_bound = bands_from_configuration_file(config_file, overrides)
            recording = recording._replace(bands=bands, heading_bound=heading_bound)
        output = arguments.output or os.path.splitext(arguments.recording)[0] + ".png"
        print(plot_recording(recording, output))
    except (OSError, ValueError) as error:
        print("plotAnimation: error: %s" % error, file=sys.stderr)
        return 1
    return 0


def plot_robots_command(paths: Sequence[str], output: Optional[str]) -> int:
    """plotAnimation with several recordings: each robot named after its recording's folder (robot1/animation.json)."""
    try:
        recordings = {os.path.basename(os.path.dirname(os.path.abspath(path))) or path: read_recording(path)
                      for path in paths}
        print(plot_robots(recordings, output or os.path.join(os.path.dirname(os.path.abspath(paths[0])), "..",
                                                             "robots.png")))
    except (OSError, ValueError) as error:
        print("plotAnimation: error: %s" % error, file=sys.stderr)
        return 1
    return 0
