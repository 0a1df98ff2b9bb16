"""The node's private parameters: ~configFile, ~logFile, and overrides of configuration keys (README: "Configuration
file and parameters"). Read again at every ``enabled``, so a harness can point the node at a configuration of its
own."""
import os
from typing import Dict, Optional, Tuple

import rospy

from cssr_system.animate_behaviour.configuration import Configuration, shipped_configuration_path
from cssr_system.animate_behaviour.contract import NODE_PARAMETERS
from cssr_system.animate_behaviour.core.configure import configure


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
    return configure(config_file_parameter(parameters), overrides)
