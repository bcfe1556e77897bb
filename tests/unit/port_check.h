/* port_check.h — for the adapters' tests (included by them, header only):
 * what a test port does with each message an adapter publishes. The topic
 * must be a catalogue topic and the message of its type; the message is
 * encoded and decoded back, so it is complete, valid protobuf, and the test
 * inspects the copy (freed with cgs_msg_free). Needs cmocka.h included
 * before it. */
#ifndef PORT_CHECK_H
#define PORT_CHECK_H

#include "cgs_msg.h"
#include "cgs_topics.h"

#include <stdlib.h>

/* The decoded copy of msg, published on topic (asserts on any mismatch). */
static ProtobufCMessage *port_check_roundtrip (const char *topic, const ProtobufCMessage *msg)
{
    const cgs_topic_t *tp = cgs_topics_find (topic);
    assert_non_null (tp);
    assert_ptr_equal (msg->descriptor, tp->message); // a catalogue topic's own type
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (cgs_msg_encode_alloc (msg, &buf, &len), 0);
    ProtobufCMessage *back = NULL;
    assert_int_equal (cgs_msg_decode (tp->message, buf, len, NULL, &back), 0);
    free (buf);
    return back;
}

#endif
