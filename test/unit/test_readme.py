"""The README documents what the package really has: every configuration key, log event, launch
file, script and topic, and no path that does not exist."""
import os
import re

import pytest

from cssr_system import log_events
from cssr_system.configuration import KEYS, package_data_dir
from cssr_system.topics import load_topic_map

PACKAGE_DIR = os.path.dirname(package_data_dir())
README = open(os.path.join(PACKAGE_DIR, "README.md"), encoding="utf-8").read()


def event_names():
    return [value for name, value in vars(log_events).items()
            if name.isupper() and not name.startswith("PURPOSE_") and isinstance(value, str)]


@pytest.mark.parametrize("key", list(KEYS))
def test_every_configuration_key_is_documented(key):
    assert "`{}`".format(key) in README


@pytest.mark.parametrize("event", event_names())
def test_every_log_event_is_documented(event):
    assert "`{}`".format(event) in README


@pytest.mark.parametrize("folder", ["launch", "scripts"])
def test_every_launch_file_and_script_is_documented(folder):
    for name in sorted(os.listdir(os.path.join(PACKAGE_DIR, folder))):
        assert name in README, "{}/{} is not in the README".format(folder, name)


@pytest.mark.parametrize("topic_file", ["pepperTopics.dat", "simulatorTopics.dat"])
def test_every_topic_is_documented(topic_file):
    for topic in load_topic_map(os.path.join(package_data_dir(), topic_file)).topics.values():
        assert "`{}`".format(topic) in README


def test_every_path_the_readme_names_exists():
    paths = set(re.findall(r"`((?:src|scripts|config|data|launch|test|tools)/[\w./-]+)`", README))
    assert paths, "the README names the package's files"
    written_at_run_time = {"data/animateBehaviourTestOutput.dat"}
    missing = [path for path in sorted(paths - written_at_run_time)
               if not os.path.exists(os.path.join(PACKAGE_DIR, path.rstrip("/")))]
    assert not missing, "named in the README but absent: {}".format(missing)
