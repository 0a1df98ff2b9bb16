"""The node's parameters: its private parameters (~configFile, ~logFile, and overrides of configuration keys; README:
"Configuration file and parameters"), read again at every ``enabled`` so that a harness can point the node at a
configuration of its own; and the live settings on dynamic_reconfigure (README: "Live settings"), a server in the
node's namespace, so that `rosrun rqt_reconfigure rqt_reconfigure` shows them and
`dynamic_reconfigure.client.Client("/animateBehaviour")` sets them. A live change is checked as a configuration is (a
value the configuration refuses, such as an unknown style, is refused with the reason and nothing is applied) and
posted to the supervisor; what the services and the animate action bring is shown back through `show`.

ROS 2's twin is cssr_system.ros2.parameters, where ROS 2's parameters play both roles."""
import os
import threading
from typing import Callable, Dict, Optional, Tuple

import rospy
from dynamic_reconfigure.server import Server

from cssr_system.animate_behaviour.configuration import Configuration, ConfigurationError, shipped_configuration_path
from cssr_system.animate_behaviour.contract import NODE_NAME, NODE_PARAMETERS
from cssr_system.animate_behaviour.live_settings import SETTING_KEYS, setting_overrides, setting_values
from cssr_system.cfg import AnimateBehaviourConfig
from cssr_system.core.configure import configure
from cssr_system.core.events import Reconfigure

BY = "dynamic_reconfigure"  # who set a live setting, in the log and on the status topic


def private_parameters() -> Dict[str, object]:
    """Every private parameter, in one call to the master (the service reads them at every `enabled`)."""
    try:
        values = rospy.get_param("~")
    except KeyError:  # no private parameter at all
        return {}
    return values if isinstance(values, dict) else {}


def parameter_overrides(parameters: Optional[Dict[str, object]] = None) -> Dict[str, object]:
    """Private parameters other than the node's own: overrides of configuration keys. A nested
    namespace (``~a/b``) is not a configuration key and is left out."""
    parameters = private_parameters() if parameters is None else parameters
    return {key: value for key, value in parameters.items()
            if key not in NODE_PARAMETERS and not isinstance(value, dict)}


def config_file_parameter(parameters: Optional[Dict[str, object]] = None) -> str:
    """~configFile as it is now; a relative path is relative to the working directory."""
    parameters = private_parameters() if parameters is None else parameters
    return os.path.abspath(str(parameters.get("configFile", shipped_configuration_path())))


def load_node_configuration(settings: Optional[Dict[str, object]] = None) -> Tuple[str, Configuration, Dict[str, str]]:
    """(configuration file, configuration, topics of the selected platform), with live `settings` (configuration
    keys) over the private parameters; raises ConfigurationError."""
    parameters = private_parameters()
    overrides = parameter_overrides(parameters)
    overrides.update(settings or {})
    return configure(config_file_parameter(parameters), overrides, rospy.resolve_name)


class LiveSettingsServer:
    """`configure(settings)` gives (configuration file, configuration, topics) with these configuration keys over
    the node's, or raises ConfigurationError; `post` puts an event on the supervisor's queue."""

    def __init__(self, configure: Callable[[dict], tuple], post: Callable[[object], None]) -> None:
        self._configure = configure
        self._post = post
        self._server: Optional[Server] = None
        self._accepted: Optional[dict] = None  # the values in force
        self._showing = threading.local()  # `on` while this thread's `show` updates the server: nothing to apply

    def start(self, config: Configuration) -> None:
        self._showing.on = True  # the server calls back once at its start
        try:
            self._server = Server(AnimateBehaviourConfig, self._on_change)
        finally:
            self._showing.on = False
        self.show(config)

    def show(self, config: Configuration) -> None:
        """The settings in force, brought by a service or the action: rqt_reconfigure and the parameters show them."""
        values = setting_values(config)
        if self._server is None or self._shown(values):
            return  # nothing new to show: no parameter writes at every enable
        self._showing.on = True
        try:
            self._server.update_configuration(values)
        finally:
            self._showing.on = False

    def _shown(self, values: dict) -> bool:
        accepted = self._accepted or {}
        return all(accepted.get(name) == value for name, value in values.items())

    def _on_change(self, values: dict, level: int) -> dict:
        if getattr(self._showing, "on", False):
            self._accepted = values
            return values
        try:
            config_file, config, topics = self._configure(setting_overrides(values))
        except ConfigurationError as error:
            rospy.logwarn("%s: live settings refused, nothing applied: %s", NODE_NAME, error)
            return self._accepted
        accepted, self._accepted = self._accepted or {}, values
        changed = frozenset(key for name, key in SETTING_KEYS.items() if values.get(name) != accepted.get(name))
        self._post(Reconfigure(config_file, config, topics, BY, changed))
        return values
