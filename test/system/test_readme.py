"""The README documents what the package really has: every configuration key and private parameter, service,
status state, log event, launch file and its args, script, topic, make target and make option, and no path that does
not exist. It stays short enough to be read to the end; the performance internals and the benchmark's figures are
in doc/performance.md, which shows the table `make benchmark` writes (doc/benchmark-latest.md)."""
import os
import re

import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import KEYS
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.package_files import data_dir, package_dir

PACKAGE_DIR = package_dir()
README = open(os.path.join(PACKAGE_DIR, "README.md"), encoding="utf-8").read()
MAKEFILE = open(os.path.join(PACKAGE_DIR, "Makefile"), encoding="utf-8").read()
PERFORMANCE = os.path.join(PACKAGE_DIR, "doc", "performance.md")
DOC_PAGES = ("doc/performance.md", "doc/demo.md", "doc/simulated-pepper.md", "doc/harness.md", "doc/ros2.md",
             "doc/testing.md", "doc/soak.md", "doc/figure.md", "doc/modes.md")
# The README and the pages it links: the demo's and the simulated Pepper's details live there.
DOCUMENTATION = README + "".join(open(os.path.join(PACKAGE_DIR, page), encoding="utf-8").read() for page in DOC_PAGES)
MAX_README_LINES = 520


def event_names():
    return list(contract.LOG_EVENTS)


@pytest.mark.parametrize("key", list(KEYS))
def test_every_configuration_key_is_documented(key):
    assert "`{}`".format(key) in README


@pytest.mark.parametrize("parameter", contract.NODE_PARAMETERS)
def test_every_private_parameter_is_documented(parameter):
    assert "`{}`".format(parameter) in README


@pytest.mark.parametrize("name", [contract.SERVICE_PATH, "/" + contract.SET_ENABLED_SERVICE_NAME,
                                  "/" + contract.STATUS_TOPIC, contract.DIAGNOSTICS_TOPIC,
                                  "/" + contract.JOINT_STATES_TOPIC])
def test_every_service_and_topic_of_the_node_is_documented(name):
    assert "`{}`".format(name) in README


def part_states():
    """The states of a part on the status topic, as msg/PartStatus.msg lists them."""
    definition = open(os.path.join(PACKAGE_DIR, "msg", "PartStatus.msg"), encoding="utf-8").read()
    listed = re.search(r"^string state\s+#\s*(.*)$", definition, re.M).group(1)
    return re.findall(r"[a-z]+", listed.replace(" or ", ", "))


def test_the_part_states_are_read():
    assert "idle" in part_states() and "homing" in part_states()


@pytest.mark.parametrize("state", part_states() + list(contract.ACCEPTED_STATES))
def test_every_status_state_and_request_is_documented(state):
    assert "`{}`".format(state) in README


@pytest.mark.parametrize("event", event_names())
def test_every_log_event_is_documented(event):
    assert "`{}`".format(event) in README


@pytest.mark.parametrize("folder", ["launch", "scripts"])
def test_every_launch_file_and_script_is_documented(folder):
    for name in sorted(os.listdir(os.path.join(PACKAGE_DIR, folder))):
        assert name in DOCUMENTATION, "{}/{} is not in the README or its pages".format(folder, name)


def launch_args():
    folder = os.path.join(PACKAGE_DIR, "launch")
    return sorted({(name, arg) for name in os.listdir(folder)
                   for arg in re.findall(r'<arg name="(\w+)"', open(os.path.join(folder, name)).read())})


@pytest.mark.parametrize("launch_file,arg", launch_args())
def test_every_launch_arg_is_documented(launch_file, arg):
    assert re.search(r"`{}(`|:=)".format(arg), DOCUMENTATION), "{} of {} is not documented".format(arg, launch_file)


def make_targets():
    return re.search(r"^\.PHONY: (.*)$", MAKEFILE, re.M).group(1).split()


def make_options():
    return [option for line in re.findall(r"^\w+_OPTIONS := (.*)$", MAKEFILE, re.M) for option in line.split()]


def test_the_makefile_is_read():
    assert "demo" in make_targets() and "DURATION" in make_options() and "CYCLES" in make_options()


@pytest.mark.parametrize("target", make_targets())
def test_every_make_target_is_documented(target):
    assert "make {}".format(target) in README


@pytest.mark.parametrize("option", make_options())
def test_every_make_option_is_documented(option):
    assert re.search(r"`{}\b".format(option), DOCUMENTATION), option


@pytest.mark.parametrize("topic_file", ["pepperTopics.dat", "simulatorTopics.dat"])
def test_every_topic_is_documented(topic_file):
    for topic in load_topic_map(os.path.join(data_dir(), topic_file)).topics.values():
        assert "`{}`".format(topic) in README


@pytest.mark.parametrize("document", ("README.md",) + DOC_PAGES)
def test_every_path_a_document_names_exists(document):
    text = open(os.path.join(PACKAGE_DIR, document), encoding="utf-8").read()
    paths = set(re.findall(r"`((?:src|scripts|config|data|launch|test|tools|doc)/[\w./-]+)`", text))
    paths |= {os.path.normpath(os.path.join(os.path.dirname(document), link))
              for link in re.findall(r"\]\(([\w./-]+)\)", text)}
    assert paths, "the document names the package's files"
    written_at_run_time = {"data/animateBehaviourTestOutput.dat"}
    missing = [path for path in sorted(paths - written_at_run_time)
               if not os.path.exists(os.path.join(PACKAGE_DIR, path.rstrip("/")))]
    assert not missing, "named in {} but absent: {}".format(document, missing)


def test_the_readme_is_short_enough_to_read_to_the_end():
    lines = README.count("\n")
    assert lines <= MAX_README_LINES, "README.md has {} lines; at most {}".format(lines, MAX_README_LINES)


def test_the_readme_points_to_the_performance_page_which_shows_the_latest_benchmark():
    assert "](doc/performance.md)" in README
    performance = open(PERFORMANCE, encoding="utf-8").read()
    assert "](benchmark-latest.md)" in performance, "doc/performance.md links doc/benchmark-latest.md"
    assert os.path.exists(os.path.join(PACKAGE_DIR, "doc", "benchmark-latest.md"))
