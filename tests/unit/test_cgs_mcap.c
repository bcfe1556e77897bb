/* test_cgs_mcap — the MCAP writer and reader (cgs_mcap):
 *   - a recording of real messages (health, of the catalogue's schema, with
 *     the build's FileDescriptorSet) over many chunks, compressed and not,
 *     reads back record for record: the schemas, the channels before their
 *     first message, every message's channel, sequence, times and bytes; the
 *     file ends with its footer and magic; the layout's fixed parts (magic,
 *     header, footer, DataEnd before the summary, the summary's CRC) are
 *     checked byte by byte against the specification;
 *   - a file cut anywhere (a recorder killed) reads its whole chunks and
 *     stops without an error, not complete;
 *   - a flipped byte in a chunk is refused with the offset; a length that
 *     overruns a file with its footer is damage, not a cut; a chunk that
 *     claims 2^40 bytes is refused before memory is given to it;
 *   - ids, a bad channel, a file that cannot be created.
 * tests/integration/record.sh reads recordings with @mcap/core. */
#include "cgs_mcap.h"
#include "cgs_schemas.h"
#include "health.pb-c.h"
#include "header.pb-c.h"
#include "test_util.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

static char s_dir[512]; // under $TMPDIR

static uint64_t s_le (const uint8_t *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

static uint8_t *s_slurp (const char *path, size_t *len)
{
    FILE *f = fopen (path, "rb");
    assert_non_null (f);
    fseek (f, 0, SEEK_END);
    *len = (size_t)ftell (f);
    fseek (f, 0, SEEK_SET);
    uint8_t *b = malloc (*len + 1);
    assert_non_null (b);
    assert_int_equal (fread (b, 1, *len, f), *len);
    fclose (f);
    return b;
}

/* Message i: a health of instance "svc<i % 3>" packed, into buf. */
static size_t s_msg (int i, uint8_t *buf, size_t cap)
{
    Cgs__Header h = CGS__HEADER__INIT;
    Cgs__Health m = CGS__HEALTH__INIT;
    char inst[32], detail[64];
    snprintf (inst, sizeof inst, "svc%d", i % 3);
    snprintf (detail, sizeof detail, "message %d of the test", i);
    h.source = inst;
    h.seq = (uint64_t)i;
    h.sim_time_s = i * 0.1;
    m.header = &h;
    m.program = "svc";
    m.instance = inst;
    m.last_error = detail;
    size_t n = protobuf_c_message_get_packed_size (&m.base);
    assert_true (n <= cap);
    protobuf_c_message_pack (&m.base, buf);
    return n;
}

#define S_N 3000

/* Write S_N messages over three channels into path. */
static void s_write (const char *path, bool compress, size_t chunk_bytes)
{
    char err[256] = "";
    cgs_mcap_options_t o = {.compress = compress, .chunk_bytes = chunk_bytes};
    cgs_mcap_writer_t *w = cgs_mcap_writer_open (path, &o, err, sizeof err);
    if (!w)
        fail_msg ("%s", err);
    size_t fl = 0;
    const uint8_t *fds = cgs_schemas_fds (&fl);
    assert_true (fl > 1000);
    assert_int_equal (cgs_mcap_writer_schema (w, "cgs.Health", "protobuf", fds, fl), 1);
    const char *k[] = {"publishers"}, *v[] = {"*"};
    assert_int_equal (cgs_mcap_writer_channel (w, 1, "health", "protobuf", k, v, 1), 1);
    assert_int_equal (cgs_mcap_writer_channel (w, 1, "health.b", "protobuf", NULL, NULL, 0), 2);
    assert_int_equal (cgs_mcap_writer_channel (w, 0, "raw", "", NULL, NULL, 0), 3);
    assert_int_equal (cgs_mcap_writer_channel (w, 9, "bad", "protobuf", NULL, NULL, 0), -EINVAL);
    assert_int_equal (cgs_mcap_writer_message (w, 4, 0, 0, 0, (const uint8_t *)"x", 1), -EINVAL);
    uint8_t buf[256];
    for (int i = 0; i < S_N; i++) {
        size_t n = s_msg (i, buf, sizeof buf);
        // Log times not in order within a chunk on channel 2 (the reader takes them as written).
        uint64_t t = 1000000000ull * 1700000000 + (uint64_t)i * 1000000 + (i % 7 == 3 ? 500 : 0);
        assert_int_equal (
            cgs_mcap_writer_message (w, (uint16_t)(1 + i % 3), (uint32_t)i, t, t - 7, buf, n), 0);
        if (i == S_N / 2)
            assert_int_equal (cgs_mcap_writer_flush (w), 0);
    }
    assert_int_equal (cgs_mcap_writer_messages (w), S_N);
    assert_true (cgs_mcap_writer_chunks (w) > 2);
    assert_string_equal (cgs_mcap_writer_error (w), "");
    assert_int_equal (cgs_mcap_writer_close (&w, err, sizeof err), 0);
    assert_null (w);
    assert_int_equal (cgs_mcap_writer_close (&w, err, sizeof err), 0); // NULL accepted
}

/* Read path: returns the messages read; complete says whether it ended
 * with its footer. Every message must be message i of s_msg, in order. */
static int s_read (const char *path, bool *complete)
{
    char err[256] = "";
    cgs_mcap_reader_t *r = cgs_mcap_reader_open (path, err, sizeof err);
    if (!r)
        fail_msg ("%s", err);
    cgs_mcap_record_t rec;
    int got = 0, rc;
    bool schema = false, chan[4] = {false};
    uint8_t buf[256];
    while ((rc = cgs_mcap_reader_next (r, &rec, err, sizeof err)) == 1) {
        if (rec.kind == CGS_MCAP_SCHEMA) {
            assert_int_equal (rec.id, 1);
            assert_string_equal (rec.name, "cgs.Health");
            assert_string_equal (rec.encoding, "protobuf");
            size_t fl;
            const uint8_t *fds = cgs_schemas_fds (&fl);
            assert_int_equal (rec.len, fl);
            assert_memory_equal (rec.data, fds, fl);
            schema = true;
        } else if (rec.kind == CGS_MCAP_CHANNEL) {
            assert_true (rec.id >= 1 && rec.id <= 3);
            assert_string_equal (rec.name, rec.id == 1   ? "health"
                                           : rec.id == 2 ? "health.b"
                                                         : "raw");
            assert_int_equal (rec.schema_id, rec.id == 3 ? 0 : 1);
            if (rec.id != 3)
                assert_true (schema);
            chan[rec.id] = true;
        } else {
            assert_int_equal (rec.kind, CGS_MCAP_MESSAGE);
            int i = got++;
            assert_int_equal (rec.id, 1 + i % 3);
            assert_true (chan[rec.id]); // its channel came first
            assert_int_equal (rec.sequence, i);
            uint64_t t =
                1000000000ull * 1700000000 + (uint64_t)i * 1000000 + (i % 7 == 3 ? 500 : 0);
            assert_true (rec.log_time_ns == t);
            assert_true (rec.publish_time_ns == t - 7);
            size_t n = s_msg (i, buf, sizeof buf);
            assert_int_equal (rec.len, n);
            assert_memory_equal (rec.data, buf, n);
        }
    }
    if (rc < 0)
        fail_msg ("%s", err);
    *complete = cgs_mcap_reader_complete (r);
    if (*complete)
        assert_int_equal (cgs_mcap_reader_unread (r), 0);
    cgs_mcap_reader_destroy (&r);
    assert_null (r);
    return got;
}

static void test_round_trip (void **state)
{
    (void)state;
    for (int z = 0; z < 2; z++) {
        char path[128];
        snprintf (path, sizeof path, "%s/a%d.mcap", s_dir, z);
        s_write (path, z == 1, 16384);
        bool complete = false;
        assert_int_equal (s_read (path, &complete), S_N);
        assert_true (complete);
        // The fixed parts, from the specification.
        size_t len;
        uint8_t *f = s_slurp (path, &len);
        assert_memory_equal (f, "\x89MCAP0\r\n", 8);
        assert_memory_equal (f + len - 8, "\x89MCAP0\r\n", 8);
        assert_int_equal (f[8], 0x01); // Header
        const uint8_t *foot = f + len - 8 - 29;
        assert_int_equal (foot[0], 0x02); // Footer, content 20 bytes
        assert_true (s_le (foot + 1, 8) == 20);
        uint64_t summary = s_le (foot + 9, 8), offsets = s_le (foot + 17, 8);
        uint32_t scrc = (uint32_t)s_le (foot + 25, 4);
        assert_true (summary > 0 && offsets > summary && offsets < len);
        assert_int_equal (f[summary - 13], 0x0F); // DataEnd right before the summary
        uint32_t dcrc = (uint32_t)s_le (f + summary - 4, 4);
        assert_int_equal (dcrc, (uint32_t)crc32 (0, f, (uInt)(summary - 13)));
        assert_int_equal (scrc, (uint32_t)crc32 (0, f + summary, (uInt)(len - 8 - 4 - summary)));
        assert_int_equal (f[summary], 0x03); // the summary: schemas first
        // Compressed chunks say so.
        bool zstd = memmem (f, len, "zstd", 4) != NULL;
        assert_true (zstd == (z == 1));
        printf ("# %s: %zu bytes for %d messages\n", z ? "zstd" : "uncompressed", len, S_N);
        free (f);
    }
}

static void test_cut_short (void **state)
{
    (void)state;
    char path[128], cut[160];
    snprintf (path, sizeof path, "%s/b.mcap", s_dir);
    snprintf (cut, sizeof cut, "%s/b-cut.mcap", s_dir);
    s_write (path, true, 8192);
    size_t len;
    uint8_t *f = s_slurp (path, &len);
    int last = -1, seen_partial = 0;
    for (size_t at = 16; at < len; at += len / 37 + 1) {
        FILE *o = fopen (cut, "wb");
        assert_non_null (o);
        assert_int_equal (fwrite (f, 1, at, o), at);
        fclose (o);
        bool complete = true;
        int got = s_read (cut, &complete);
        assert_false (complete);
        assert_true (got >= last); // more of the file, no fewer messages
        assert_true (got <= S_N);
        seen_partial += got > 0 && got < S_N;
        last = got;
    }
    assert_true (seen_partial > 10);
    // A flipped byte inside the first chunk: refused with where.
    size_t chunk_at = 0;
    for (size_t i = 8; i < len; i++)
        if (f[i] == 0x06 && s_le (f + i + 1, 8) < len) {
            chunk_at = i;
            break;
        }
    assert_true (chunk_at > 0);
    f[chunk_at + 9 + 60] ^= 0x5a;
    FILE *o = fopen (cut, "wb");
    assert_non_null (o);
    assert_int_equal (fwrite (f, 1, len, o), len);
    fclose (o);
    char err[256] = "";
    cgs_mcap_reader_t *r = cgs_mcap_reader_open (cut, err, sizeof err);
    assert_non_null (r);
    cgs_mcap_record_t rec;
    int rc;
    while ((rc = cgs_mcap_reader_next (r, &rec, err, sizeof err)) == 1)
        ;
    assert_int_equal (rc, -EINVAL);
    char want[64];
    snprintf (want, sizeof want, "damaged MCAP at byte %zu:", chunk_at);
    assert_non_null (strstr (err, want));
    cgs_mcap_reader_destroy (&r);
    f[chunk_at + 9 + 60] ^= 0x5a; // mended
    // A length that overruns a file which has its footer: damage, not a cut.
    // A chunk claiming 2^40 bytes is refused before any memory is given.
    for (int k = 0; k < 2; k++) {
        uint8_t *g = malloc (len);
        assert_non_null (g);
        memcpy (g, f, len);
        size_t field = k == 0 ? chunk_at + 1 : chunk_at + 9 + 16;
        for (int b = 0; b < 8; b++)
            g[field + b] = (uint8_t)((k == 0 ? (uint64_t)len : (uint64_t)1 << 40) >> (8 * b));
        o = fopen (cut, "wb");
        assert_int_equal (fwrite (g, 1, len, o), len);
        fclose (o);
        free (g);
        r = cgs_mcap_reader_open (cut, err, sizeof err);
        assert_non_null (r);
        while ((rc = cgs_mcap_reader_next (r, &rec, err, sizeof err)) == 1)
            ;
        assert_int_equal (rc, -EINVAL);
        assert_non_null (strstr (err, k == 0 ? "overruns the file, which has its footer"
                                             : "a chunk of 1099511627776 bytes (at most"));
        cgs_mcap_reader_destroy (&r);
    }
    free (f);
    unlink (cut);
    unlink (path);
}

/* Rewound part way through a chunk, the reader reads every record again,
 * in the same order (a replay that seeks back). */
static void test_rewind (void **state)
{
    (void)state;
    for (int z = 0; z < 2; z++) {
        char path[128], err[256] = "";
        snprintf (path, sizeof path, "%s/a%d.mcap", s_dir, z);
        cgs_mcap_reader_t *r = cgs_mcap_reader_open (path, err, sizeof err);
        assert_non_null (r);
        cgs_mcap_record_t rec;
        uint32_t first[2][40];
        for (int pass = 0; pass < 2; pass++) {
            int got = 0, rc;
            while (got < 40 && (rc = cgs_mcap_reader_next (r, &rec, err, sizeof err)) == 1)
                if (rec.kind == CGS_MCAP_MESSAGE)
                    first[pass][got++] = rec.sequence;
            assert_int_equal (got, 40);
            cgs_mcap_reader_rewind (r);
        }
        assert_memory_equal (first[0], first[1], sizeof first[0]);
        int messages = 0, schemas = 0, rc;
        while ((rc = cgs_mcap_reader_next (r, &rec, err, sizeof err)) == 1) {
            messages += rec.kind == CGS_MCAP_MESSAGE;
            schemas += rec.kind == CGS_MCAP_SCHEMA;
        }
        assert_int_equal (rc, 0);
        assert_int_equal (messages, S_N);
        assert_int_equal (schemas, 1); // the summary's copies are not read again
        assert_true (cgs_mcap_reader_complete (r));
        cgs_mcap_reader_destroy (&r);
    }
}

static void test_refusals (void **state)
{
    (void)state;
    char err[256] = "";
    assert_null (cgs_mcap_writer_open ("/nonexistent-dir/x.mcap", NULL, err, sizeof err));
    assert_non_null (strstr (err, "/nonexistent-dir/x.mcap: cannot create"));
    assert_null (cgs_mcap_reader_open ("/nonexistent-dir/x.mcap", err, sizeof err));
    char path[128];
    snprintf (path, sizeof path, "%s/not.mcap", s_dir);
    FILE *f = fopen (path, "w");
    fputs ("not an mcap file\n", f);
    fclose (f);
    assert_null (cgs_mcap_reader_open (path, err, sizeof err));
    assert_non_null (strstr (err, "not an MCAP file"));
    f = fopen (path, "w"); // empty: nothing to map
    fclose (f);
    assert_null (cgs_mcap_reader_open (path, err, sizeof err));
    assert_non_null (strstr (err, "not an MCAP file"));
    unlink (path);
}

static int s_setup (void **state)
{
    (void)state;
    const char *t = getenv ("TMPDIR");
    snprintf (s_dir, sizeof s_dir, "%s/cgs-mcap-XXXXXX", t && *t ? t : "/tmp");
    return mkdtemp (s_dir) ? 0 : -1;
}

static int s_teardown (void **state)
{
    (void)state;
    if (getenv ("CGS_KEEP")) { // for a look with other readers
        printf ("# kept %s\n", s_dir);
        return 0;
    }
    char path[160];
    for (int z = 0; z < 2; z++) {
        snprintf (path, sizeof path, "%s/a%d.mcap", s_dir, z);
        unlink (path);
    }
    return rmdir (s_dir);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_round_trip),
        cmocka_unit_test (test_cut_short),
        cmocka_unit_test (test_rewind),
        cmocka_unit_test (test_refusals),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
