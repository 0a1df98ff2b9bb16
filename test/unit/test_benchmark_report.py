"""Unit tests of the benchmark's report (test/benchmark/report.py): the line that sets the node's timed figures beside
the reference's of the same run."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmark"))

from report import floor_line  # noqa: E402


def figure(p90):
    return {"p50": p90 / 2, "p90": p90, "max": p90 * 2, "mean": p90 / 2, "samples": 10}


def test_the_floor_line_counts_the_timed_figures_within_the_references_p90_and_names_the_others():
    results = {"node": {"setActivation disabled reply": figure(10.8), "stop of every part after disabled": figure(30.0),
                        "CPU while disabled": figure(5.0), "first goal of every part after enabled": figure(50.0)},
               "reference": {"setActivation disabled reply": figure(13.4),
                             "stop of every part after disabled": figure(20.0), "CPU while disabled": figure(0.1)}}
    # CPU has no p90 target; a figure the reference lacks is not compared.
    assert floor_line(results, 2) == ("p90 at or under the reference's: 1 of 2; above: stop of every part after "
                                      "disabled (30.0, the reference 20.0)")


def test_the_floor_line_without_a_figure_above():
    results = {"node": {"set_enabled true reply": figure(3.0)}, "reference": {"set_enabled true reply": figure(3.0)}}
    assert floor_line(results, 1) == "p90 at or under the reference's: 1 of 1"
