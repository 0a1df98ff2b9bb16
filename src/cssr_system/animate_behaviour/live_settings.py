"""The live settings (README: "Live settings"): configuration keys that may change while the node animates, from
rqt_reconfigure (dynamic_reconfigure) or from the animate action. The configuration file gives their starting values;
each `enabled` request starts from the configuration again (the last command wins). dynamic_reconfigure knows them by
names of their own (`SETTING_KEYS`), which are private parameters of the server, not overrides of configuration keys.
Pure Python: no ROS.
"""
from typing import Dict, List, Sequence, Tuple

from cssr_system.animate_behaviour.configuration import KEYS, Configuration, configuration_items

# dynamic_reconfigure's name of each live setting -> its configuration key.
SETTING_KEYS = {"intensity": "intensity", "tempo": "breathsPerMinute", "style": "motionStyle", "arms": "moveArms",
                "hands": "moveHands", "leg": "moveLeg", "base": "turnBase",
                "mode": "mode"}
LIVE_KEYS = tuple(SETTING_KEYS.values())
# Two settings for an interaction (README: "Keeping the robot alive through a visit"), by dynamic_reconfigure's
# names: moving a little, with the base still, while the robot speaks to someone; moving fully while it waits.
PRESETS = {"engaged": {"intensity": 0.5, "base": False}, "waiting": {"intensity": 1.0, "base": True}}
# The animate action's names of the parts it switches (its goal's `parts`), and their keys.
PART_SWITCHES = (("arms", "moveArms"), ("hands", "moveHands"), ("leg", "moveLeg"), ("base", "turnBase"))


def setting_values(config: Configuration) -> Dict[str, object]:
    """The live settings of `config` by dynamic_reconfigure's names, as its values."""
    return {name: getattr(config, KEYS[key].attribute) for name, key in SETTING_KEYS.items()}


def setting_overrides(values: Dict[str, object]) -> Dict[str, object]:
    """Configuration overrides from dynamic_reconfigure's values (other entries, such as its groups, left out)."""
    return {key: values[name] for name, key in SETTING_KEYS.items() if name in values}


def changed_settings(old: Configuration, new: Configuration) -> List[Tuple[str, str, str]]:
    """(key, old value, new value) of every live setting that differs, as the configuration file writes them."""
    before, after = configuration_items(old), configuration_items(new)
    return [(key, before[key], after[key]) for key in LIVE_KEYS if before[key] != after[key]]


def moving_parts(config: Configuration) -> List[str]:
    """The parts the switches let move: of arms, hands, leg and base (the status topic's `moving_parts`)."""
    return [name for name, key in PART_SWITCHES if getattr(config, KEYS[key].attribute)]


def goal_overrides(parts: Sequence[str], style: str, intensity: float, tempo: float,
                   mode: str = "") -> Dict[str, object]:
    """The configuration overrides an animate goal asks for (the action's fields; README: "The animate action"):
    the parts it names move, the others are switched off; no part named: every part the behaviour moves; no mode: the
mode setting in force stays (the supervisor keeps it).
    Raises ValueError naming what is wrong when a part is unknown; the values themselves are checked as every
    configuration value is, by `load_configuration`."""
    unknown = sorted(set(parts) - {name for name, _ in PART_SWITCHES})
    if unknown:
        raise ValueError("unknown part %s; expected any of: %s" % (
            ", ".join(repr(name) for name in unknown), ", ".join(name for name, _ in PART_SWITCHES)))
    overrides: Dict[str, object] = {key: not parts or name in parts for name, key in PART_SWITCHES}
    overrides["intensity"] = float(intensity)
    if style:
        overrides["motionStyle"] = style
    if tempo:
        overrides["breathsPerMinute"] = float(tempo)
    if mode:
        overrides["mode"] = mode
    return overrides
