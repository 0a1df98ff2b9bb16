"""`catkin_make run_tests` runs the pytest suites too (CMakeLists.txt registers them), and `catkin_test_results`
sees their results: checked on the unit suite, in the workspace `make test` built."""
import os
import subprocess
import xml.etree.ElementTree as ElementTree

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def workspace_dir() -> str:
    return subprocess.check_output(["bash", "-c", "source tools/common.sh && printf %s \"$WORKSPACE_DIR\""],
                                   cwd=REPO_DIR, universal_newlines=True)


def test_catkin_make_run_tests_runs_the_unit_suite_and_reports_it():
    workspace = workspace_dir()
    results = os.path.join(workspace, "build", "test_results", "cssr_system")
    result_file = os.path.join(results, "pytest-unit.xml")
    if os.path.exists(result_file):
        os.remove(result_file)
    build = subprocess.run(["catkin_make", "-C", workspace, "-DPYTHON_EXECUTABLE=/usr/bin/python3",
                            "run_tests_cssr_system_pytest_unit"], cwd=REPO_DIR, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert build.returncode == 0, build.stdout[-3000:]
    suite = ElementTree.parse(result_file).getroot()
    suite = suite if suite.tag == "testsuite" else suite.find("testsuite")
    assert int(suite.get("tests")) > 400, "the unit suite ran"
    assert int(suite.get("failures")) == 0 and int(suite.get("errors")) == 0
    summary = subprocess.run(["catkin_test_results", results], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True)
    assert summary.returncode == 0, summary.stdout
    assert "pytest-unit.xml" in summary.stdout or "0 errors, 0 failures" in summary.stdout
