#!/usr/bin/env python3
"""simulatedPepper: a kinematic Pepper on the ROS interfaces of the robot or of the Gazebo simulator.

rosrun cssr_system simulatedPepper.py [_platform:=robot|simulator]   (README: "On the simulated Pepper")
"""
import sys

from cssr_system.ros1.simulated_pepper_node import main

if __name__ == "__main__":
    sys.exit(main())
