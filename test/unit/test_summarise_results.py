"""The closing line of the test command (tools/summarise_results.py): every failure counts, also one that rosunit
records under no test case (a failing unittest subTest, a class's set-up), so that no failure passes unseen."""
import os
import subprocess
import sys

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "summarise_results.py")


def summarise(folder):
    finished = subprocess.run([sys.executable, SCRIPT, str(folder)], stdout=subprocess.PIPE, universal_newlines=True)
    return finished.returncode, finished.stdout.strip().splitlines()


def test_a_failure_under_no_test_case_counts_and_is_named(tmp_path):
    (tmp_path / "rosunit-x.xml").write_text(
        '<testsuite errors="0" failures="1" name="s" tests="2"><testcase classname="T" name="a"/>'
        '<testcase classname="T" name="b"/></testsuite>')
    status, lines = summarise(tmp_path)
    assert status == 1 and lines[-1] == "2 passed, 1 failed"
    assert lines[0].startswith("FAILED rosunit-x.xml: 1 failure(s) under no test case")


def test_failures_shown_in_their_cases_count_once(tmp_path):
    (tmp_path / "unit.xml").write_text(
        '<testsuites><testsuite errors="0" failures="1" name="s" tests="2"><testcase classname="T" name="a"/>'
        '<testcase classname="T" name="b"><failure message="boom">x</failure></testcase>'
        '<testcase classname="T" name="c"><skipped/></testcase></testsuite></testsuites>')
    status, lines = summarise(tmp_path)
    assert status == 1 and lines == ["FAILED T.b (unit.xml): boom", "1 passed, 1 failed, 1 skipped"]
