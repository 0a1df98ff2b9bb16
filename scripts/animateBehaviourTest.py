#!/usr/bin/env python3
"""animateBehaviourTest: the test harness of the animateBehaviour node (README: "Test harness").

roslaunch cssr_system animateBehaviourLaunchTestHarness.launch platform:=robot|simulator
"""
import sys

from cssr_system.ros1.harness_runner import main

if __name__ == "__main__":
    sys.exit(main())
