/* observer — the fault tests' witness on the bus (tests/fault/; test code
 * only). It subscribes to every catalogue topic of every publisher in the
 * exercise and writes one line per event to --out, flushed at once, with
 * the wall time (Unix seconds, as `date +%s.%N` gives) first:
 *
 *   T msg SOURCE TOPIC SIM_TIME   a message (at most one per source and topic
 *                                 in any 50 ms, and always the first after a
 *                                 quiet 50 ms, so a resumption is seen to the
 *                                 millisecond)
 *   T epoch SOURCE EPOCH          a source's first message, or its first after
 *                                 a restart (a new publisher epoch)
 *   T gap SOURCE TOPIC N          N messages of that source and topic missed
 *                                 (sequence numbers skipped within an epoch)
 *   T icpt UAV STATE NUMBER TRACK an intercept changed state, designation
 *                                 number or track (STATE without its prefix)
 *   T health SOURCE GAPS DROPS    a service's own counts of messages missed
 *                                 (gaps) and refused at its high-water mark
 *                                 (drops), when they change
 *
 *   observer --exercise FILE --out FILE
 *
 * It stops on SIGTERM or SIGINT and then writes "T end RECEIVED GAPS". */
#include "cgs_bus.h"
#include "cgs_exercise.h"
#include "cgs_lifecycle.h"
#include "cgs_msg.h"
#include "cgs_topics.h"

#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

#define S_MAX_STREAMS 256
#define S_MAX_UAVS    16
#define S_QUIET_S     0.05

typedef struct {
    char source[CGS_NAME_MAX];
    char topic[CGS_TOPIC_MAX];
    uint64_t epoch, seq;
    double last_line;     // wall time of the last msg line
    uint64_t gaps, drops; // health streams: the counts last written
} s_stream_t;

typedef struct {
    uint32_t uav_id;
    int state;
    uint64_t number;
    uint32_t track_id;
} s_icpt_t;

typedef struct {
    FILE *out;
    s_stream_t streams[S_MAX_STREAMS];
    size_t nstreams;
    s_icpt_t icpts[S_MAX_UAVS];
    size_t nicpts;
    uint64_t received, gaps;
} s_obs_t;

static s_stream_t *s_stream (s_obs_t *o, const char *source, const char *topic)
{
    for (size_t i = 0; i < o->nstreams; i++)
        if (strcmp (o->streams[i].source, source) == 0 && strcmp (o->streams[i].topic, topic) == 0)
            return &o->streams[i];
    if (o->nstreams == S_MAX_STREAMS)
        return NULL;
    s_stream_t *s = &o->streams[o->nstreams++];
    snprintf (s->source, sizeof s->source, "%s", source);
    snprintf (s->topic, sizeof s->topic, "%s", topic);
    return s;
}

/* True when source has been heard with this epoch on some topic. */
static bool s_epoch_known (const s_obs_t *o, const char *source, uint64_t epoch)
{
    for (size_t i = 0; i < o->nstreams; i++)
        if (strcmp (o->streams[i].source, source) == 0 && o->streams[i].epoch == epoch)
            return true;
    return false;
}

static void s_on_intercept (s_obs_t *o, double now, const Cgs__Intercept *ic)
{
    s_icpt_t *k = NULL;
    for (size_t i = 0; i < o->nicpts && !k; i++)
        if (o->icpts[i].uav_id == ic->uav_id)
            k = &o->icpts[i];
    if (!k && o->nicpts < S_MAX_UAVS) {
        k = &o->icpts[o->nicpts++];
        *k = (s_icpt_t){.uav_id = ic->uav_id, .state = -1};
    }
    if (!k || (k->state == (int)ic->state && k->number == ic->designation_number &&
               k->track_id == ic->track_id))
        return;
    k->state = (int)ic->state;
    k->number = ic->designation_number;
    k->track_id = ic->track_id;
    fprintf (o->out, "%.6f icpt %" PRIu32 " %s %" PRIu64 " %" PRIu32 "\n", now, ic->uav_id,
             cgs_msg_enum_short (&cgs__intercept_state__descriptor, (int)ic->state, "?"),
             ic->designation_number, ic->track_id);
}

static void s_on_msg (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    s_obs_t *o = arg;
    double now = cgs_bus_wall_time ();
    o->received++;
    const char *source = hdr->source && *hdr->source ? hdr->source : "?";
    bool known = s_epoch_known (o, source, hdr->epoch);
    s_stream_t *s = s_stream (o, source, topic);
    if (!s)
        return;
    if (!known)
        fprintf (o->out, "%.6f epoch %s %" PRIu64 "\n", now, source, hdr->epoch);
    if (s->epoch == hdr->epoch && hdr->seq > s->seq + 1) {
        o->gaps += hdr->seq - s->seq - 1;
        fprintf (o->out, "%.6f gap %s %s %" PRIu64 "\n", now, source, topic, hdr->seq - s->seq - 1);
    }
    if (s->epoch != hdr->epoch || hdr->seq > s->seq) {
        s->epoch = hdr->epoch;
        s->seq = hdr->seq;
    }
    if (now - s->last_line >= S_QUIET_S) {
        fprintf (o->out, "%.6f msg %s %s %.3f\n", now, source, topic, hdr->sim_time_s);
        s->last_line = now;
    }
    if (strcmp (topic, "intercept") == 0)
        s_on_intercept (o, now, (const Cgs__Intercept *)msg);
    if (strcmp (topic, "health") == 0) {
        const Cgs__Health *h = (const Cgs__Health *)msg;
        if (h->gaps != s->gaps || h->drops != s->drops)
            fprintf (o->out, "%.6f health %s %" PRIu64 " %" PRIu64 "\n", now, source, h->gaps,
                     h->drops);
        s->gaps = h->gaps;
        s->drops = h->drops;
    }
}

int main (int argc, char **argv)
{
    const char *exercise = NULL, *out = NULL;
    static const struct option opts[] = {{"exercise", required_argument, NULL, 'e'},
                                         {"out", required_argument, NULL, 'o'},
                                         {NULL, 0, NULL, 0}};
    int c;
    while ((c = getopt_long (argc, argv, "", opts, NULL)) != -1) {
        if (c == 'e')
            exercise = optarg;
        else if (c == 'o')
            out = optarg;
        else
            return 2;
    }
    if (!exercise || !out) {
        fprintf (stderr, "usage: observer --exercise FILE --out FILE\n");
        return 2;
    }
    char err[1024];
    cgs_exercise_t *ex = NULL;
    if (cgs_exercise_load (exercise, &ex, err, sizeof err) < 0) {
        fprintf (stderr, "observer: %s\n", err);
        return 1;
    }
    static s_obs_t obs;
    obs.out = fopen (out, "a");
    if (!obs.out) {
        fprintf (stderr, "observer: %s: %s\n", out, strerror (errno));
        cgs_exercise_destroy (&ex);
        return 1;
    }
    setvbuf (obs.out, NULL, _IOLBF, 0);
    void *ctx = zmq_ctx_new ();
    cgs_sub_t *sub = cgs_sub_new (ctx);
    cgs_sub_set_exercise (sub, cgs_exercise_id (ex));
    // Every publishing instance once, every catalogue topic.
    const cgs_instance_t *seen[64];
    size_t nseen = 0;
    for (size_t t = 0; t < cgs_topics_count (); t++) {
        const char *topic = cgs_topics_at (t)->name;
        cgs_sub_on (sub, topic, s_on_msg, &obs);
        const cgs_instance_t *pubs[64];
        size_t n = cgs_exercise_publishers_of (ex, topic, pubs, 64);
        for (size_t i = 0; i < n && i < 64; i++) {
            bool dup = false;
            for (size_t k = 0; k < nseen; k++)
                dup |= seen[k] == pubs[i];
            if (dup || nseen == 64)
                continue;
            seen[nseen++] = pubs[i];
            if (cgs_sub_connect (sub, pubs[i]->publish) < 0)
                fprintf (stderr, "observer: cannot connect to %s\n", pubs[i]->publish);
        }
    }
    cgs_lifecycle_init ();
    while (!cgs_lifecycle_stopping ()) {
        int rc = cgs_sub_poll (sub, 100);
        if (rc < 0 && rc != -EINTR)
            break;
    }
    fprintf (obs.out, "%.6f end %" PRIu64 " %" PRIu64 "\n", cgs_bus_wall_time (), obs.received,
             obs.gaps);
    fclose (obs.out);
    cgs_sub_destroy (&sub);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&ex);
    return 0;
}
