#!/usr/bin/env python3
"""animateBehaviourDemo: the demo's driver: enables animateBehaviour, prints what moves, disables it (`make demo`).

roslaunch cssr_system animateBehaviourDemo.launch starts it with the rest of the demo   (README: "Demo")
"""
import sys

from cssr_system.ros1.demo_driver import main

if __name__ == "__main__":
    sys.exit(main())
