"""animateBehaviourDemoSpeech: a stand-in speech node, the conversation of `make demo CONVERSATION=1`.

rosrun cssr_system animateBehaviourDemoSpeech.py
then: rostopic pub -1 /animateBehaviourDemoSpeech/play std_msgs/Empty

On each message on its play topic it plays the script of `cssr_system.demo.speech`: ``true`` on the std_msgs/Bool
topic ``listening`` for 6 s, then ``false``; then an 8 s goal of its own actionlib server ``tts``, sent by its own
client; then nothing. The action is of the node's Animate type, whose ``duration`` the server waits out: the
animateBehaviour node reads only ``tts/status``. Names are relative: in the demo's namespace, as the node resolves
its ``listeningTopic`` and ``speakingAction`` (README: "Modes").
"""
import threading

import actionlib
import rospy
from std_msgs.msg import Bool, Empty

from cssr_system.demo.speech import LISTENING_TOPIC, NODE_NAME, PLAY_TOPIC, SPEAKING_ACTION, Conversation, say
from cssr_system.msg import AnimateAction, AnimateGoal, AnimateResult
from cssr_system.ros1.trajectory_client import goal_state_name

SERVER_TIMEOUT = 5.0  # s for the client to find the server, which runs in this node
TICK = 0.1  # s between looks for a cancel while speaking


class SpeechPlayer(Conversation):
    def __init__(self) -> None:
        super().__init__(threading.Event())
        # Latched: a subscriber that connects late still learns whether it listens.
        self._listening = rospy.Publisher(LISTENING_TOPIC, Bool, queue_size=1, latch=True)
        self._server = actionlib.SimpleActionServer(SPEAKING_ACTION, AnimateAction, self._speaking, auto_start=False)
        self._server.start()
        self._client = actionlib.SimpleActionClient(SPEAKING_ACTION, AnimateAction)
        rospy.on_shutdown(self.stop.set)

    def _speaking(self, goal: AnimateGoal) -> None:
        """The server's goal: active for its duration, as a text to speech is while it talks."""
        end = rospy.get_time() + goal.duration
        while rospy.get_time() < end:
            if self._server.is_preempt_requested() or rospy.is_shutdown():
                self._server.set_preempted(AnimateResult(reason="cancelled"))
                return
            rospy.sleep(TICK)
        self._server.set_succeeded(AnimateResult(animated=goal.duration, reason="duration elapsed"))

    def set_listening(self, listening: bool) -> None:
        self._listening.publish(Bool(data=listening))

    def speak(self, seconds: float, done) -> None:
        if not self._client.wait_for_server(rospy.Duration(SERVER_TIMEOUT)):
            done("no server on %s within %g s" % (SPEAKING_ACTION, SERVER_TIMEOUT))
            return
        self._client.send_goal(AnimateGoal(duration=seconds), done_cb=lambda state, _result: done(
            goal_state_name(state)))


def main() -> int:
    rospy.init_node(NODE_NAME)
    player = SpeechPlayer()
    # rospy runs each subscription's callbacks on a thread of its own: the script may block this one.
    rospy.Subscriber(PLAY_TOPIC, Empty, lambda _message: player.play(), queue_size=1)
    say("ready: the conversation plays on %s" % rospy.resolve_name(PLAY_TOPIC))
    rospy.spin()
    return 0
