"""The configuration a front-end's parameters ask for: the file, the overrides of its keys, and the topics of the
platform it selects (README: "Configuration file and parameters")."""
from typing import Callable, Dict, Mapping, Tuple

from cssr_system.animate_behaviour.configuration import (Configuration, ConfigurationError, load_configuration,
                                                         topic_file_path)
from cssr_system.animate_behaviour.topics import TopicFileError, load_topic_map, resolved_topics
from cssr_system.package_files import data_dir


def configure(config_file: str, overrides: Mapping[str, object],
              resolve: Callable[[str], str]) -> Tuple[str, Configuration, Dict[str, str]]:
    """(configuration file, configuration, topics of the selected platform, each name resolved by `resolve`: the
    front-end's client library, in the node's namespace and with its remapping); raises ConfigurationError."""
    folder = data_dir()
    config = load_configuration(config_file, overrides, data_dir=folder)
    try:  # validated by load_configuration; read again only if the file changed since
        topics = resolved_topics(load_topic_map(topic_file_path(config, folder)), resolve)
    except TopicFileError as error:
        raise ConfigurationError(error.problems)
    return config_file, config, dict(topics)
