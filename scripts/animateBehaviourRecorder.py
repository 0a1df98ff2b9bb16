#!/usr/bin/env python3
"""animateBehaviourRecorder: records a run of animateBehaviour; when stopped, writes the recording and its plot.

rosrun cssr_system animateBehaviourRecorder.py [_output_dir:=DIR] [_node:=/animateBehaviour]   (README: "Demo")
"""
import sys

from cssr_system.ros1.recorder_node import main

if __name__ == "__main__":
    sys.exit(main())
