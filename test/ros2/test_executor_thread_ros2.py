"""The thread that spins the ROS 2 node's executor (ros2/animate_behaviour_node.py's ExecutorThread) and the main
thread's watch of it (ros2/animate_behaviour_main.py's run): work handed over before the executor spins waits for
it, and runs on its thread, in the order handed over; once that thread has ended, work runs at once on the caller's
(a stop still goes out), and the main thread ends the node with status 1.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2 -q
"""
import threading
import types

import pytest

rclpy = pytest.importorskip("rclpy")

from rclpy.executors import SingleThreadedExecutor  # noqa: E402

from cssr_system.ros2 import animate_behaviour_main  # noqa: E402
from cssr_system.ros2.animate_behaviour_node import ExecutorThread  # noqa: E402
from processes import fail_on_error, wait_until  # noqa: E402


def test_work_waits_for_the_spin_runs_on_its_thread_and_runs_at_once_after_it_ended(node):
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    spinning = ExecutorThread(node, fail_on_error)
    ran_on = []
    spinning.run(lambda: ran_on.append(threading.current_thread().name))
    assert ran_on == [] and not spinning.ended()
    spinning.spin(executor)
    assert wait_until(lambda: ran_on == ["executor"], 5.0)
    executor.shutdown(timeout_sec=2.0)
    assert wait_until(spinning.ended, 5.0)
    spinning.run(lambda: ran_on.append(threading.current_thread().name))
    assert ran_on == ["executor", threading.current_thread().name]


def test_work_runs_in_the_order_it_was_handed_over(node):
    """rclpy runs the tasks it holds newest first; a goal and the one that replaces it must leave in order."""
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    spinning = ExecutorThread(node, fail_on_error)
    order = []
    for number in range(20):  # before the spin: all wait together
        spinning.run(lambda number=number: order.append(number))
    spinning.spin(executor)
    for number in range(20, 200):  # while it spins
        spinning.run(lambda number=number: order.append(number))
    assert wait_until(lambda: len(order) == 200, 5.0)
    assert order == list(range(200))
    executor.shutdown(timeout_sec=2.0)


def test_a_callback_of_the_executor_runs_the_work_handed_over_so_far_at_once_and_other_threads_do_not(node):
    """A service's answer to `disabled` comes after the stop's goals have left: the service, a callback on the
    executor's thread, runs what the supervisor handed over before it answers (ros2/services.py)."""
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    spinning = ExecutorThread(node, fail_on_error)
    order = []
    spinning.spin(executor)

    def callback():  # as a service's: work handed over from another thread, then run_pending, then the answer
        handing = threading.Thread(target=lambda: [spinning.run(lambda n=n: order.append(n)) for n in range(3)])
        handing.start()
        handing.join()
        spinning.run_pending()
        order.append("answer")
    spinning.run(callback)
    assert wait_until(lambda: "answer" in order, 5.0)
    assert order == [0, 1, 2, "answer"]
    spinning.run(lambda: order.append("later"))
    spinning.run_pending()  # not the executor's thread: the executor runs it, as handed over
    assert wait_until(lambda: order[-1] == "later", 5.0) and order.count("later") == 1
    executor.shutdown(timeout_sec=2.0)


def test_the_main_thread_ends_the_node_with_status_1_when_the_executor_has_ended(monkeypatch, capsys):
    monkeypatch.setattr(animate_behaviour_main, "ALIVE_CHECK_PERIOD", 0.01)
    alive = types.SimpleNamespace(is_alive=lambda: True)
    wiring = types.SimpleNamespace(supervisor=types.SimpleNamespace(thread=alive, stopped=threading.Event()),
                                   executor_thread=types.SimpleNamespace(ended=lambda: True))
    reasons = []
    assert animate_behaviour_main.run(wiring, threading.Event(), reasons) == 1
    assert reasons == ["executor ended"]
    assert "the executor thread has ended" in capsys.readouterr().err
