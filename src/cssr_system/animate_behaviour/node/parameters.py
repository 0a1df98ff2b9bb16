"""The node's private parameters: ~configFile, ~logFile, and overrides of configuration keys (README: "Parameters").
Read again at every ``enabled``, so a harness can point the node at a configuration of its own."""
import os
from typing import Dict, Tuple

import rospy

from cssr_system.animate_behaviour.configuration import (Configuration, ConfigurationError, load_configuration,
                                                         shipped_configuration_path, topic_file_path)
from cssr_system.animate_behaviour.contract import NODE_PARAMETERS
from cssr_system.animate_behaviour.topics import TopicFileError, load_topic_map
from cssr_system.package_files import data_dir


def parameter_overrides() -> Dict[str, object]:
    """Private parameters other than the node's own: overrides of configuration keys."""
    prefix = rospy.get_name() + "/"
    overrides = {}
    for name in rospy.get_param_names():
        if name.startswith(prefix) and "/" not in name[len(prefix):]:
            key = name[len(prefix):]
            if key not in NODE_PARAMETERS:
                overrides[key] = rospy.get_param(name)
    return overrides


def config_file_parameter() -> str:
    """~configFile as it is now; a relative path is relative to the working directory."""
    return os.path.abspath(rospy.get_param("~configFile", shipped_configuration_path()))


def load_node_configuration() -> Tuple[str, Configuration, Dict[str, str]]:
    """(configuration file, configuration, topics of the selected platform); raises ConfigurationError."""
    config_file = config_file_parameter()
    folder = data_dir()
    config = load_configuration(config_file, parameter_overrides(), data_dir=folder)
    try:  # validated by load_configuration; read again only if the file changed since
        topics = load_topic_map(topic_file_path(config, folder)).topics
    except TopicFileError as error:
        raise ConfigurationError(error.problems)
    return config_file, config, dict(topics)
