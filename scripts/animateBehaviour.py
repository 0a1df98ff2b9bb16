#!/usr/bin/env python3
"""animateBehaviour: makes the Pepper robot look alive with small random movements.

rosrun cssr_system animateBehaviour.py [_configFile:=...] [_logFile:=...] [_<configuration key>:=...]
then: rosservice call /animateBehaviour/setActivation "state: 'enabled'"   (or 'disabled')
"""
import sys

from cssr_system.ros1.animate_behaviour_main import main

if __name__ == "__main__":
    sys.exit(main())
