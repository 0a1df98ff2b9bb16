"""The README documents what the package really has: every configuration key, log event, launch
file, script and topic, and no path that does not exist."""
import os
import re

import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import KEYS
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.package_files import data_dir, package_dir

PACKAGE_DIR = package_dir()
README = open(os.path.join(PACKAGE_DIR, "README.md"), encoding="utf-8").read()


def event_names():
    return list(contract.LOG_EVENTS)


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
    for topic in load_topic_map(os.path.join(data_dir(), topic_file)).topics.values():
        assert "`{}`".format(topic) in README


def test_every_path_the_readme_names_exists():
    paths = set(re.findall(r"`((?:src|scripts|config|data|launch|test|tools)/[\w./-]+)`", README))
    assert paths, "the README names the package's files"
    written_at_run_time = {"data/animateBehaviourTestOutput.dat"}
    missing = [path for path in sorted(paths - written_at_run_time)
               if not os.path.exists(os.path.join(PACKAGE_DIR, path.rstrip("/")))]
    assert not missing, "named in the README but absent: {}".format(missing)
