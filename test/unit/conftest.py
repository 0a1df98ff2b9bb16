"""Helpers shared by the unit tests."""
from cssr_system.animate_behaviour.configuration import BEHAVIOURS, Configuration
from cssr_system.pepper.joint_table import PARTS

ROBOT_PARTS = tuple(PARTS)  # pepperTopics.dat names every part
SIMULATOR_PARTS = ("RArm", "LArm", "Leg")  # simulatorTopics.dat: no hands


def default_configuration(**overrides) -> Configuration:
    """The shipped configuration (README: "Configuration file and parameters"), with `overrides` applied."""
    configuration = Configuration(
        platform="robot",
        behaviour=frozenset(BEHAVIOURS),
        robot_topics="pepperTopics.dat",
        simulator_topics="simulatorTopics.dat",
        verbose_mode=False,
        rot_maximum_range=0.3,
        selected_range=0.5,
        arm_maximum_range=(0.2, 0.2, 0.2, 0.35, 0.2),
        hand_maximum_range=0.7,
        leg_maximum_range=(0.1, 0.1, 0.08),
        gesture_duration=1.0,
        num_points=100,
        num_points_leg=2,
        leg_repeat_factor=8,
        random_seed=None,
    )
    return configuration._replace(**overrides)
