/* cgs_topics — the catalogue of bus topics: each topic's name, the message
 * type its payload carries, and which programs publish it. Named once here;
 * every service and the mscgs tool uses this table. */
#ifndef CGS_TOPICS_H
#define CGS_TOPICS_H

#include <protobuf-c/protobuf-c.h>
#include <stdbool.h>
#include <stddef.h>

typedef struct {
    const char *name;                          // topic string, frame 1
    const ProtobufCMessageDescriptor *message; // payload type, frame 2
    const char *publishers;                    // space-separated programs; "*" = every service
    const char *what;                          // one line for help text
} cgs_topic_t;

/* Number of topics. */
size_t cgs_topics_count (void);
/* Topic i. */
const cgs_topic_t *cgs_topics_at (size_t i);
/* The topic of that exact name, or NULL. */
const cgs_topic_t *cgs_topics_find (const char *name);
/* True when program publishes topic. */
bool cgs_topics_published_by (const cgs_topic_t *topic, const char *program);

#endif
