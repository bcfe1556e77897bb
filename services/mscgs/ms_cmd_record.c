/* ms_cmd_record — `mscgs record [--out FILE] [--topics T,T..] [--duration S]
 * [--no-compress]`: subscribes to every topic of the catalogue (cgs_topics)
 * from every service of the exercise, and writes each message as it came
 * (its header inside: source, sequence, simulation and wall time) to an MCAP
 * file (cgs_mcap.h): one channel per topic, its schema the message's full
 * name in the FileDescriptorSet of proto/ (cgs_schemas.h), the log time the
 * recorder's receive time, the publish time the publisher's wall time, the
 * sequence the publisher's. Open chunks are written out every 0.5 s, so a
 * recorder killed loses at most that; Ctrl-C or SIGTERM closes the file
 * with its index. Progress on stderr every 10 s. */
#include "ms_cmd_record.h"

#include "cgs_lifecycle.h"
#include "cgs_loop.h"
#include "cgs_mcap.h"
#include "cgs_schemas.h"
#include "cgs_topics.h"
#include "ms_opts.h"
#include "ms_tool.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <zmq.h>

#define S_FLUSH_S    0.5
#define S_PROGRESS_S 10.0

typedef struct {
    cgs_mcap_writer_t *w;
    const char *path;
    uint16_t channel[64]; // per catalogue topic (0: not recorded)
    uint64_t count[64];
    uint8_t *buf;
    size_t cap;
    uint64_t dropped; // messages that could not be written
    bool failed;
} s_rec_t;

static uint64_t s_now_ns (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_REALTIME, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* A topic's handler argument: the recording and the topic's index. */
typedef struct {
    s_rec_t *r;
    size_t i;
} s_topic_arg_t;

static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    (void)topic;
    const s_topic_arg_t *a = arg;
    s_rec_t *r = a->r;
    size_t i = a->i;
    if (!r->channel[i] || r->failed)
        return;
    size_t n = protobuf_c_message_get_packed_size (msg);
    if (n > r->cap) {
        uint8_t *b = realloc (r->buf, n);
        if (!b) {
            r->dropped++;
            return;
        }
        r->buf = b, r->cap = n;
    }
    protobuf_c_message_pack (msg, r->buf);
    double pub = hdr && isfinite (hdr->wall_time_s) && hdr->wall_time_s > 0 ? hdr->wall_time_s : 0;
    uint64_t now = s_now_ns ();
    int rc = cgs_mcap_writer_message (r->w, r->channel[i], hdr ? (uint32_t)hdr->seq : 0, now,
                                      pub > 0 ? (uint64_t)llround (pub * 1e9) : now, r->buf, n);
    if (rc == -EIO) {
        fprintf (stderr, "mscgs record: %s\n", cgs_mcap_writer_error (r->w));
        r->failed = true;
    } else if (rc < 0) {
        r->dropped++;
    } else {
        r->count[i]++;
    }
}

/* Is topic in the comma-separated list (NULL: every topic)? */
static bool s_chosen (const char *list, const char *topic)
{
    if (!list)
        return true;
    size_t n = strlen (topic);
    for (const char *p = list; *p;) {
        const char *e = strchr (p, ',');
        size_t len = e ? (size_t)(e - p) : strlen (p);
        if (len == n && strncmp (p, topic, n) == 0)
            return true;
        p += len + (e ? 1 : 0);
    }
    return false;
}

int ms_record_main (int argc, char **argv)
{
    const char *exercise = NULL, *out = "recording.mcap", *topics = NULL;
    double duration_s = 0;
    bool no_compress = false;
    const ms_opt_t opts[] = {
        {.name = "out",
         .letter = 'o',
         .value = "FILE",
         .help = "the MCAP file to write (default recording.mcap)",
         .str = &out},
        {.name = "topics",
         .value = "T,T..",
         .help = "record only these topics (default: every topic)",
         .str = &topics},
        {.name = "duration",
         .value = "S",
         .help = "stop after S seconds of wall time (default: Ctrl-C)",
         .fn = ms_opts_read_positive,
         .arg = &duration_s},
        {.name = "no-compress", .help = "chunks uncompressed (default zstd)", .flag = &no_compress},
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "record",
        .about = "Record every topic of the exercise (or --topics) from every service into an\n"
                 "MCAP file with the protobuf schemas inside (Foxglove, the mcap tools and\n"
                 "@mcap/core open it): a channel per topic, each message as published, with\n"
                 "its header, the receive time as log time and the publisher's wall time as\n"
                 "publish time. Chunks go to disk every 0.5 s (a recorder killed loses at\n"
                 "most that); Ctrl-C, SIGTERM or --duration close the file with its index.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (topics)
        for (const char *p = topics; *p;) {
            const char *e = strchr (p, ',');
            size_t len = e ? (size_t)(e - p) : strlen (p);
            char name[64];
            snprintf (name, sizeof name, "%.*s", (int)(len < 63 ? len : 63), p);
            if (!cgs_topics_find (name)) {
                fprintf (stderr, "mscgs record: unknown topic '%s' (`mscgs topics` lists them)\n",
                         name);
                return 2;
            }
            p += len + (e ? 1 : 0);
        }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    cgs_lifecycle_init (); // a SIGTERM from now on closes the file with its index
    char err[512] = "";
    cgs_mcap_options_t mo = {.library = "mscgs record", .compress = !no_compress};
    static s_rec_t r;
    r.path = out;
    if (!(r.w = cgs_mcap_writer_open (out, &mo, err, sizeof err))) {
        fprintf (stderr, "mscgs record: %s\n", err);
        cgs_exercise_destroy (&ex);
        return 1;
    }
    void *ctx = NULL;
    cgs_sub_t *sub = ms_tool_open_sub (ex, &ctx);
    if (!sub) {
        cgs_mcap_writer_close (&r.w, NULL, 0);
        cgs_exercise_destroy (&ex);
        return 1;
    }
    // One schema per message type, one channel per topic.
    size_t fds_len = 0;
    const uint8_t *fds = cgs_schemas_fds (&fds_len);
    const ProtobufCMessageDescriptor *types[64];
    int schema_of[64];
    static s_topic_arg_t targs[64];
    size_t ntypes = 0, ntopics = 0;
    for (size_t i = 0; i < cgs_topics_count () && i < 64; i++) {
        const cgs_topic_t *t = cgs_topics_at (i);
        if (!s_chosen (topics, t->name))
            continue;
        size_t k = 0;
        while (k < ntypes && types[k] != t->message)
            k++;
        if (k == ntypes) {
            types[ntypes] = t->message;
            schema_of[ntypes++] =
                cgs_mcap_writer_schema (r.w, t->message->name, "protobuf", fds, fds_len);
        }
        const char *keys[] = {"publishers"}, *vals[] = {t->publishers};
        int ch = schema_of[k] > 0 ? cgs_mcap_writer_channel (r.w, (uint16_t)schema_of[k], t->name,
                                                             "protobuf", keys, vals, 1)
                                  : schema_of[k];
        if (ch < 0) {
            fprintf (stderr, "mscgs record: %s: %s\n", out, strerror (-ch));
            cgs_sub_destroy (&sub);
            zmq_ctx_term (ctx);
            cgs_mcap_writer_close (&r.w, NULL, 0);
            cgs_exercise_destroy (&ex);
            return 1;
        }
        r.channel[i] = (uint16_t)ch;
        targs[i] = (s_topic_arg_t){&r, i};
        cgs_sub_on (sub, t->name, s_on_message, &targs[i]);
        ntopics++;
    }
    size_t npub = ms_tool_connect_publishers (sub, ex, "health"); // every service publishes health
    fprintf (stderr, "mscgs record: %zu topics from %zu services of %s into %s%s\n", ntopics, npub,
             cgs_exercise_name (ex), out, no_compress ? " (uncompressed)" : "");
    double start = cgs_loop_now (), next_flush = start + S_FLUSH_S,
           next_progress = start + S_PROGRESS_S;
    double end = duration_s > 0 ? start + duration_s : INFINITY;
    while (!cgs_lifecycle_stopping () && !r.failed && cgs_loop_now () < end) {
        cgs_sub_poll (sub, 100);
        double now = cgs_loop_now ();
        if (now >= next_flush) {
            if (cgs_mcap_writer_flush (r.w) < 0) {
                fprintf (stderr, "mscgs record: %s\n", cgs_mcap_writer_error (r.w));
                r.failed = true;
            }
            next_flush = now + S_FLUSH_S;
        }
        if (now >= next_progress) {
            fprintf (stderr, "mscgs record: %.0f s, %llu messages, %.1f MB\n", now - start,
                     (unsigned long long)cgs_mcap_writer_messages (r.w),
                     (double)cgs_mcap_writer_bytes (r.w) / 1e6);
            next_progress = now + S_PROGRESS_S;
        }
    }
    // What is still queued: the services' last words.
    for (int k = 0; k < 100 && !r.failed && cgs_sub_dispatch (sub, 1000) > 0; k++)
        ;
    uint64_t messages = cgs_mcap_writer_messages (r.w);
    uint64_t gaps = cgs_sub_gaps (sub), malformed = cgs_sub_malformed (sub);
    cgs_sub_destroy (&sub);
    zmq_ctx_term (ctx);
    int rc = r.failed ? 1 : 0;
    uint32_t chunks = cgs_mcap_writer_chunks (r.w);
    if (cgs_mcap_writer_close (&r.w, err, sizeof err) < 0) {
        fprintf (stderr, "mscgs record: %s\n", err);
        rc = 1;
    }
    fprintf (stderr, "mscgs record: %llu messages in %u chunks to %s", (unsigned long long)messages,
             chunks, out);
    for (size_t i = 0; i < cgs_topics_count () && i < 64; i++)
        if (r.count[i])
            fprintf (stderr, "%s %s %llu", i ? "," : ":", cgs_topics_at (i)->name,
                     (unsigned long long)r.count[i]);
    fprintf (stderr, "\n");
    struct rusage ru;
    double wall = cgs_loop_now () - start;
    if (getrusage (RUSAGE_SELF, &ru) == 0 && wall > 0)
        fprintf (stderr, "mscgs record: cpu %.1f %% of one core over %.0f s (%.0f messages/s)\n",
                 100.0 *
                     ((double)ru.ru_utime.tv_sec + ru.ru_utime.tv_usec / 1e6 +
                      (double)ru.ru_stime.tv_sec + ru.ru_stime.tv_usec / 1e6) /
                     wall,
                 wall, (double)messages / wall);
    if (gaps || malformed || r.dropped)
        fprintf (stderr, "mscgs record: %llu missed (gaps), %llu malformed, %llu not written\n",
                 (unsigned long long)gaps, (unsigned long long)malformed,
                 (unsigned long long)r.dropped);
    free (r.buf);
    cgs_exercise_destroy (&ex);
    return rc;
}
