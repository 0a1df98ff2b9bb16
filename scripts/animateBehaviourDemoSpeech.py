#!/usr/bin/env python3
"""animateBehaviourDemoSpeech: a stand-in speech node that listens 6 s, then speaks 8 s through its action
(`make demo CONVERSATION=1`).

rosrun cssr_system animateBehaviourDemoSpeech.py, then publish std_msgs/Empty on
/animateBehaviourDemoSpeech/play   (README: "Demo")
"""
import sys

from cssr_system.ros1.speech_player import main

if __name__ == "__main__":
    sys.exit(main())
