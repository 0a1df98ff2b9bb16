"""The node's ROS 2 parameters (README: "ROS 2"): ``configFile`` and ``logFile`` (read at start-up), and every key of
the configuration file as a parameter of the same name, whose value overrides the file's.

Each key is declared with the file's value (a launch file's or the command line's value wins), typed as ROS 2
parameters are: booleans, integers and numbers as such, the other keys as the text the file holds; any type is
accepted later, and checked as the file's values are. A change is refused, with the configuration's reason, when
the configuration it makes is invalid; the live settings (intensity, breathsPerMinute, motionStyle, moveArms,
moveHands, moveLeg, turnBase, mode) apply at once, the other keys at the next ``enabled``, but START_UP_KEYS, which
are read at start-up: they name the controllers, whose clients the node makes before it spins (an rclpy action client
made while the executor spins may be waited on before it is complete), and the conversation's sources, which the node
subscribes to at start-up."""
from typing import Callable, Dict, Optional

from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult

from cssr_system.animate_behaviour.configuration import (CONVERSATION_SOURCES, KEYS, ConfigurationError,
                                                         configuration_items, load_configuration,
                                                         shipped_configuration_path)
from cssr_system.animate_behaviour.live_settings import LIVE_KEYS
from cssr_system.core.configure import configure
from cssr_system.core.events import Reconfigure
from cssr_system.package_files import data_dir

BY = "parameters"
START_UP_KEYS = ("platform", "robotTopics", "simulatorTopics", "actuation") + tuple(
    key for key, _, _ in CONVERSATION_SOURCES)
READ_AT_START = ParameterDescriptor(read_only=True, description="read at start-up")


def declared_value(config, key: str):
    """A key's value as a ROS 2 parameter: booleans, integers and numbers typed, the rest as the file's text."""
    value = getattr(config, KEYS[key].attribute)
    if isinstance(value, (bool, int, float)):
        return value
    return configuration_items(config)[key]


class NodeParameters:
    """`post`: the supervisor's queue, for live settings changed while the node runs."""

    def __init__(self, node, post: Callable[[object], None]) -> None:
        self._node = node
        self._post = post
        self.config_file = node.declare_parameter("configFile", shipped_configuration_path(),
                                                  READ_AT_START).value
        self.log_file: Optional[str] = node.declare_parameter("logFile", "", READ_AT_START).value or None

    def declare_keys(self) -> None:
        """Every configuration key, with the file's value; raises ConfigurationError when the file is unusable."""
        file_config = load_configuration(self.config_file, {}, data_dir=data_dir())
        for key in KEYS:
            self._node.declare_parameter(key, declared_value(file_config, key),
                                         ParameterDescriptor(dynamic_typing=True, read_only=key in START_UP_KEYS))
        self._node.add_on_set_parameters_callback(self._on_set)

    def overrides(self, changes: Optional[Dict[str, object]] = None) -> Dict[str, object]:
        """Every key's parameter (`declare_keys` first), then `changes`."""
        values = {key: self._node.get_parameter(key).value for key in KEYS}
        values.update(changes or {})
        return values

    def load(self, settings: Optional[Dict[str, object]] = None) -> tuple:
        """(configuration file, configuration, topics) as the parameters, then `settings`, say; raises
        ConfigurationError."""
        return configure(self.config_file, self.overrides(settings), self._node.resolve_topic_name)

    def _on_set(self, parameters) -> SetParametersResult:
        changes = {parameter.name: parameter.value for parameter in parameters if parameter.name in KEYS}
        if not changes:
            return SetParametersResult(successful=True)
        try:
            config_file, config, topics = self.load(changes)
        except ConfigurationError as error:
            return SetParametersResult(successful=False, reason=str(error))
        if any(key in LIVE_KEYS for key in changes):
            self._post(Reconfigure(config_file, config, topics, BY, frozenset(changes)))
        return SetParametersResult(successful=True)
