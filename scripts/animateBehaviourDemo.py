#!/usr/bin/env python3
"""animateBehaviourDemo: shows animateBehaviour on the simulated Pepper and plots what it did (`make demo`).

python3 scripts/animateBehaviourDemo.py --help   (README: "Demo")
"""
import sys

from cssr_system.animate_behaviour.demo import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
