"""animateBehaviourDemoSpeech on ROS 2: a stand-in speech node, the conversation of `make demo CONVERSATION=1 ROS=2`
(the twin of cssr_system.ros1.speech_player).

  python3 -m cssr_system.ros2.speech_player
  then: ros2 topic pub --once animateBehaviourDemoSpeech/play std_msgs/msg/Empty

On each message on its play topic it plays the script of `cssr_system.demo.speech`: ``true`` on the std_msgs/Bool
topic ``listening`` for 6 s, then ``false``; then an 8 s goal of its own rclpy action server ``tts``, sent by its own
client; then nothing. The action is of the node's Animate type, whose ``duration`` the server waits out: the
animateBehaviour node reads only ``tts/_action/status``. Names are relative: in its namespace, as the node resolves
its ``listeningTopic`` and ``speakingAction`` (README: "Modes").
"""
import sys
import threading
import time
from typing import List, Optional

from cssr_system_interfaces.action import Animate
from rclpy.action import ActionClient, ActionServer, CancelResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import Bool, Empty

from cssr_system.demo.speech import LISTENING_TOPIC, NODE_NAME, PLAY_TOPIC, SPEAKING_ACTION, Conversation, say
from cssr_system.ros2.program import on_signals, run_node
from cssr_system.ros2.trajectory_client import STATE_NAMES

SERVER_TIMEOUT = 5.0  # s for the client to find the server, which runs in this node
TICK = 0.1  # s between looks for a cancel while speaking


class SpeechPlayer(Conversation):
    """Every callback on the executor's threads; the server's goal waits out its duration on one of them, so the
    executor has several (and the callbacks a reentrant group)."""

    def __init__(self, node: Node, stop: threading.Event) -> None:
        super().__init__(stop)
        self.node = node
        group = ReentrantCallbackGroup()
        self._listening = node.create_publisher(Bool, LISTENING_TOPIC, 10)
        self._server = ActionServer(node, Animate, SPEAKING_ACTION, self._speaking, callback_group=group,
                                    cancel_callback=lambda _request: CancelResponse.ACCEPT)
        self._client = ActionClient(node, Animate, SPEAKING_ACTION, callback_group=group)
        node.create_subscription(Empty, PLAY_TOPIC, self._on_play, 1, callback_group=group)

    def _on_play(self, _message: Empty) -> None:
        threading.Thread(target=self.play, name="conversation", daemon=True).start()

    def _speaking(self, handle) -> Animate.Result:
        """The server's goal: executing for its duration, as a text to speech is while it talks."""
        end = time.monotonic() + handle.request.duration
        while time.monotonic() < end:
            if handle.is_cancel_requested or self.stop.is_set():
                handle.canceled()
                return Animate.Result(reason="cancelled")
            time.sleep(TICK)
        handle.succeed()
        return Animate.Result(animated=handle.request.duration, reason="duration elapsed")

    def set_listening(self, listening: bool) -> None:
        self._listening.publish(Bool(data=listening))

    def speak(self, seconds: float, done) -> None:
        if not self._client.wait_for_server(timeout_sec=SERVER_TIMEOUT):
            done("no server on %s within %g s" % (SPEAKING_ACTION, SERVER_TIMEOUT))
            return
        # rclpy's ActionClient registers a goal's future only after sending the goal: sent from this thread, an
        # answer the executor took first would be lost (ros2/rclpy#1123). The executor's thread sends it.
        self.node.executor.create_task(lambda: self._send(seconds, done))

    def _send(self, seconds: float, done) -> None:
        def accepted(future) -> None:
            handle = future.result()
            if not handle.accepted:
                done("REJECTED")
                return
            handle.get_result_async().add_done_callback(
                lambda result: done(STATE_NAMES.get(result.result().status, str(result.result().status))))

        self._client.send_goal_async(Animate.Goal(duration=seconds)).add_done_callback(accepted)


def play(node: Node, stop: threading.Event) -> int:
    SpeechPlayer(node, stop)
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    threading.Thread(target=executor.spin, name="executor", daemon=True).start()
    say("ready: the conversation plays on %s" % node.resolve_topic_name(PLAY_TOPIC))
    while not stop.wait(0.2):  # a signal sets it
        pass
    executor.shutdown()
    return 0


def main(args: Optional[List[str]] = None) -> int:
    stop = threading.Event()
    on_signals(lambda _name: stop.set())
    return run_node(NODE_NAME, args, lambda node: play(node, stop))


if __name__ == "__main__":
    sys.exit(main())
