/* cgs_topics — the catalogue of bus topics. */
#include "cgs_topics.h"

#include "health.pb-c.h"
#include "intercept.pb-c.h"
#include "replay.pb-c.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include <string.h>

static const cgs_topic_t s_topics[] = {
    {"clock", &cgs__clock__descriptor, "uavsim", "simulation time, scale, pause"},
    {"entity", &cgs__entity_batch__descriptor, "uavsim gateway",
     "ground truth of entities, batched per tick"},
    {"uav", &cgs__uav__descriptor, "uavsim", "one UAV's state and task"},
    {"mti", &cgs__mti__descriptor, "mtid", "MTI radar hits of a dwell"},
    {"mti.scan", &cgs__mti_scan__descriptor, "mtid", "an MTI radar scan has ended"},
    {"mti.truth", &cgs__mti_truth__descriptor, "mtid", "what the radar saw of each entity"},
    {"bcis", &cgs__bcis__descriptor, "bcisd", "BCIS replies and scan markers"},
    {"track", &cgs__track_batch__descriptor, "trackerd",
     "every track of a radar after its scan, batched"},
    {"track.turn", &cgs__track_turn__descriptor, "trackerd", "a tracked target turned"},
    {"intercept", &cgs__intercept__descriptor, "guidanced", "the designation and intercept"},
    {"image", &cgs__image__descriptor, "imagerd", "one imaging sensor frame"},
    {"video", &cgs__video_frame__descriptor, "imagerd",
     "one frame of the imaging sensor's video: MPEG-TS with H.264 and KLV"},
    {"health", &cgs__health__descriptor, "*", "a service's health, 1 Hz"},
    {"replay", &cgs__replay_state__descriptor, "replay",
     "a replay's position, speed and marks (mscgs replay)"},
};

size_t cgs_topics_count (void)
{
    return sizeof s_topics / sizeof s_topics[0];
}

const cgs_topic_t *cgs_topics_at (size_t i)
{
    return i < cgs_topics_count () ? &s_topics[i] : NULL;
}

const cgs_topic_t *cgs_topics_find (const char *name)
{
    for (size_t i = 0; i < cgs_topics_count (); i++)
        if (strcmp (s_topics[i].name, name) == 0)
            return &s_topics[i];
    return NULL;
}

bool cgs_topics_published_by (const cgs_topic_t *topic, const char *program)
{
    if (!topic || !program)
        return false;
    if (strcmp (topic->publishers, "*") == 0)
        return true;
    size_t n = strlen (program);
    const char *p = topic->publishers;
    while (*p) {
        const char *end = strchr (p, ' ');
        size_t len = end ? (size_t)(end - p) : strlen (p);
        if (len == n && strncmp (p, program, n) == 0)
            return true;
        p += len;
        while (*p == ' ')
            p++;
    }
    return false;
}
