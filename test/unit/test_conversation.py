"""Unit tests of the mode in force (core/conversation.py): the sources of the conversation, their priorities and
time-outs, and a mode set by hand, on an injected clock."""
from types import SimpleNamespace

from cssr_system.core.conversation import (Conversation, HeardFilter, HeardMessages, PRESENCE_PERIOD,
                                           configured_sources)
from cssr_system.core.events import ConversationHeard
from conftest import default_configuration

SOURCES = [("speakingTopic", "/speaking", "speaking"), ("listeningTopic", "/listening", "listening"),
           ("speakingAction", "/tts", "speaking"), ("listeningAction", "/speech_recognition", "listening")]
TIMEOUT = 3.0


def conversation(setting="auto"):
    return Conversation(SOURCES, TIMEOUT, setting)


def test_only_the_named_sources_are_watched():
    config = default_configuration(speaking_action="/tts", listening_topic="listening")
    assert configured_sources(config) == [("listeningTopic", "listening", "listening", "topic"),
                                          ("speakingAction", "/tts", "speaking", "action")]
    assert configured_sources(default_configuration()) == []


def test_speaking_wins_over_listening_and_listening_over_idle():
    talk = conversation()
    assert talk.mode == "idle"
    change = talk.heard("listeningAction", True, 10.0)
    assert change == ("idle", "listening", "listeningAction /speech_recognition", "auto")
    assert talk.heard("speakingTopic", True, 10.5).new == "speaking"
    assert talk.heard("listeningTopic", True, 11.0) is None, "listening does not override speaking"
    change = talk.heard("speakingTopic", False, 12.0)
    assert (change.new, change.by) == ("listening", "listeningTopic /listening")
    talk.heard("listeningTopic", False, 12.1)
    change = talk.heard("listeningAction", False, 12.2)
    assert (change.new, change.by) == ("idle", "listeningAction /speech_recognition ended")


def test_a_silent_source_falls_back_to_idle_after_the_time_out_and_a_present_publisher_keeps_it():
    talk = conversation()
    talk.heard("speakingAction", True, 0.0)
    assert talk.next_deadline() == TIMEOUT
    for now in (1.0, 2.0, 3.0, 4.0, 5.0):  # its publisher is there: alive, though it says nothing new
        assert talk.present("speakingAction", now) is None
    assert talk.look(5.0 + TIMEOUT) is None, "still within the time-out of its last sign of life"
    change = talk.look(5.0 + TIMEOUT + 0.01)  # the publisher died: no sign of life since 5.0
    assert (change.new, change.by) == ("idle", "speakingAction /tts silent")
    assert talk.heard("speakingAction", True, 20.0).new == "speaking", "it speaks again when it comes back"


def test_a_mode_set_by_hand_holds_until_the_next_conversation_event_which_puts_the_setting_back_to_auto():
    talk = conversation()
    talk.heard("listeningTopic", True, 0.0)
    change = talk.set_mode("speaking", "/tree", 1.0)
    assert change == ("listening", "speaking", "/tree", "speaking")
    assert talk.present("listeningTopic", 2.0) is None and talk.mode == "speaking", "no event: the hand holds"
    assert talk.heard("listeningTopic", True, 2.5) is None, "the same again is no event"
    change = talk.heard("speakingAction", True, 3.0)  # the conversation moves on: speaking, now heard
    assert talk.setting == "auto" and talk.mode == "speaking" and change is None
    change = talk.heard("speakingAction", False, 4.0)
    assert (change.new, change.setting) == ("listening", "auto")


def test_auto_takes_the_conversations_mode_at_once():
    talk = conversation("idle")
    talk.heard("speakingTopic", True, 0.0)
    assert talk.mode == "speaking", "the configuration's idle is set by hand: the event overrides it"
    talk.set_mode("listening", "dynamic_reconfigure", 1.0)
    change = talk.set_mode("auto", "dynamic_reconfigure", 1.5)
    assert change == ("listening", "speaking", "dynamic_reconfigure", "auto")


def test_an_unknown_source_changes_nothing():
    talk = Conversation([], TIMEOUT)
    assert talk.heard("speakingTopic", True, 0.0) is None and talk.next_deadline() is None


def test_repeated_messages_pass_at_most_every_presence_period_and_changes_at_once():
    heard = HeardFilter()
    assert heard.passes("speakingAction", False, 0.0)
    assert not heard.passes("speakingAction", False, 0.2)
    assert heard.passes("speakingAction", True, 0.3)
    assert not heard.passes("speakingAction", True, 0.3 + PRESENCE_PERIOD / 2)
    assert heard.passes("speakingAction", True, 0.3 + PRESENCE_PERIOD)
    assert heard.passes("listeningTopic", True, 0.31)


def test_heard_messages_post_a_change_at_once_and_the_same_again_only_after_the_presence_period():
    posted = []
    ears = HeardMessages(posted.append, active_states=(2, 3))

    def status_list(*codes):  # an action's GoalStatusArray, as either front-end's watch reads it
        return SimpleNamespace(status_list=[SimpleNamespace(status=code) for code in codes])
    ears.bool_message(SimpleNamespace(data=True), "speakingTopic")
    ears.bool_message(SimpleNamespace(data=True), "speakingTopic")
    ears.status_message(status_list(4, 2), "listeningAction")
    ears.status_message(status_list(4), "listeningAction")
    assert posted == [ConversationHeard("speakingTopic", True), ConversationHeard("listeningAction", True),
                      ConversationHeard("listeningAction", False)]
