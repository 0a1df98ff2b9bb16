#!/usr/bin/env python3
"""animateBehaviourDemoGesture: plays a 4 s gesture on the right arm as another node would (`make demo GESTURE=1`).

rosrun cssr_system animateBehaviourDemoGesture.py, then publish std_msgs/Empty on
/animateBehaviourDemoGesture/play   (README: "Demo")
"""
import sys

from cssr_system.ros1.gesture_player import main

if __name__ == "__main__":
    sys.exit(main())
