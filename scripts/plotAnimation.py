#!/usr/bin/env python3
"""plotAnimation: plots a recorded animateBehaviour run (joints, their bands, base heading).

rosrun cssr_system plotAnimation.py RECORDING [--log LOGFILE] [--config FILE] [-o OUT.png]

RECORDING is a recording file (format: cssr_system.animation_plot), e.g. the demo's
<workspace>/demo/animation.json. The allowed band of each joint comes from the node's log file when
--log is given (its goal_sent entries during the run), else from the recording itself, else from
the configuration (--config, default the package's, with the recording's platform and behaviour).
The plot goes to OUT.png (default: RECORDING with the extension .png); its path is printed.
"""
import argparse
import os
import sys

from cssr_system.animation_plot import (
    bands_from_configuration_file,
    bands_from_log,
    plot_recording,
    read_recording,
)


def main(argv):
    parser = argparse.ArgumentParser(prog="plotAnimation.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("recording", help="recording file (.json) of a run")
    parser.add_argument("--log", help="the node's log file of that run: bands from its goal_sent entries")
    parser.add_argument("--config", help="configuration file for the bands when neither --log nor the "
                                         "recording has them (default: the package's)")
    parser.add_argument("-o", "--output", help="PNG to write (default: RECORDING with .png)")
    arguments = parser.parse_args([argument for argument in argv if not argument.startswith("__")])
    try:
        recording = read_recording(arguments.recording)
        if arguments.log:
            from cssr_system.event_log import read_log
            end = recording.start_epoch + max(
                [0.0] + list(recording.times[-1:]) + list(recording.heading_times[-1:]))
            bands, heading_bound = bands_from_log(read_log(arguments.log), since=recording.start_epoch - 1.0,
                                                  until=end + 1.0)
            if not bands:
                raise ValueError("%s: no goal_sent entries during the recorded run" % arguments.log)
            recording = recording._replace(bands=bands, heading_bound=heading_bound)
        elif arguments.config or not recording.bands:
            from cssr_system.configuration import shipped_configuration_path
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


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
