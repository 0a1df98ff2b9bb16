#!/usr/bin/env python3
"""plotAnimation: plots a recorded animateBehaviour run (joints, their bands, base heading).

rosrun cssr_system plotAnimation.py RECORDING [--log LOGFILE] [--config FILE] [-o OUT.png]   (README: "Demo")
"""
import sys

from cssr_system.recording.plot import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
