/* test_seal — cgs_seal: a payload sealed under the group key opens to the
 * same bytes and header; a changed byte anywhere (header, nonce, ciphertext,
 * tag), another topic, another key, a truncation or an unsealed payload is
 * refused; the key file's errors name the file and line. The replay rules
 * (an (epoch, seq) seen before) are the subscriber's: test_bus. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_seal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const cgs_seal_header_t s_h = {.exercise_id = 7,
                                      .epoch = 0x1122334455667788ull,
                                      .seq = 42,
                                      .wall_time_s = 1.5e9,
                                      .source = "mtid.uav1"};

static const char s_plain[] = "\x0a\x05hello, a protobuf-ish payload";

/* s_plain sealed under key on topic "mti"; returns its size. */
static size_t s_sealed (const cgs_seal_key_t *key, uint8_t *buf, size_t cap)
{
    size_t len = 0;
    assert_int_equal (cgs_seal (key, "mti", &s_h, s_plain, sizeof s_plain, buf, cap, &len), 0);
    assert_int_equal (len, cgs_seal_size (sizeof s_plain, s_h.source));
    assert_int_equal (len, sizeof s_plain + CGS_SEAL_FIXED + strlen (s_h.source));
    return len;
}

static void test_round_trip (void **state)
{
    (void)state;
    cgs_seal_key_t key;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    uint8_t buf[512], out[512];
    size_t len = s_sealed (&key, buf, sizeof buf);
    assert_true (cgs_seal_is_sealed (buf, len));
    assert_false (cgs_seal_is_sealed (s_plain, sizeof s_plain));
    // The plaintext appears nowhere in the sealed bytes.
    assert_null (memmem (buf, len, "hello", 5));
    cgs_seal_header_t h;
    size_t n = 0;
    assert_int_equal (cgs_seal_open (&key, "mti", buf, len, &h, out, sizeof out, &n), 0);
    assert_int_equal (n, sizeof s_plain);
    assert_memory_equal (out, s_plain, n);
    assert_int_equal (h.exercise_id, 7);
    assert_true (h.epoch == s_h.epoch && h.seq == 42 && h.wall_time_s == 1.5e9);
    assert_string_equal (h.source, "mtid.uav1");
    // Two seals of one message differ (random nonce) and both open.
    uint8_t buf2[512];
    size_t len2 = s_sealed (&key, buf2, sizeof buf2);
    assert_int_equal (len2, len);
    assert_memory_not_equal (buf, buf2, len);
    assert_int_equal (cgs_seal_open (&key, "mti", buf2, len2, &h, out, sizeof out, &n), 0);
}

// Every single changed byte fails authentication (or the format check).
static void test_tampered_byte (void **state)
{
    (void)state;
    cgs_seal_key_t key;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    uint8_t buf[512], out[512];
    size_t len = s_sealed (&key, buf, sizeof buf);
    for (size_t i = 0; i < len; i++) {
        for (int bit = 0; bit < 8; bit += 7) {
            buf[i] ^= (uint8_t)(1u << bit);
            cgs_seal_header_t h;
            size_t n = 0;
            int rc = cgs_seal_open (&key, "mti", buf, len, &h, out, sizeof out, &n);
            if (rc != -EBADMSG && rc != -EPROTO)
                fail_msg ("byte %zu bit %d changed: %d", i, bit, rc);
            // The magic and version are checked before the tag.
            if (i >= 5 && rc != -EBADMSG && !(i == 33))
                fail_msg ("byte %zu: %d, not -EBADMSG", i, rc);
            buf[i] ^= (uint8_t)(1u << bit);
        }
    }
    cgs_seal_header_t h;
    size_t n = 0;
    assert_int_equal (cgs_seal_open (&key, "mti", buf, len, &h, out, sizeof out, &n), 0);
}

static void test_wrong_key_or_topic (void **state)
{
    (void)state;
    cgs_seal_key_t key, other;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    assert_int_equal (cgs_seal_key_new (&other), 0);
    uint8_t buf[512], out[512];
    size_t len = s_sealed (&key, buf, sizeof buf);
    cgs_seal_header_t h;
    size_t n = 0;
    assert_int_equal (cgs_seal_open (&other, "mti", buf, len, &h, out, sizeof out, &n), -EBADMSG);
    // The topic is authenticated: the same bytes under another topic fail.
    assert_int_equal (cgs_seal_open (&key, "mti.scan", buf, len, &h, out, sizeof out, &n),
                      -EBADMSG);
    assert_int_equal (cgs_seal_open (&key, "track", buf, len, &h, out, sizeof out, &n), -EBADMSG);
}

static void test_truncated (void **state)
{
    (void)state;
    cgs_seal_key_t key;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    uint8_t buf[512], out[512];
    size_t len = s_sealed (&key, buf, sizeof buf);
    for (size_t cut = 0; cut < len; cut++) {
        cgs_seal_header_t h;
        size_t n = 0;
        int rc = cgs_seal_open (&key, "mti", buf, cut, &h, out, sizeof out, &n);
        if (rc != -EPROTO && rc != -EBADMSG)
            fail_msg ("truncated to %zu: %d", cut, rc);
    }
    // An extra byte fails too.
    buf[len] = 0;
    cgs_seal_header_t h;
    size_t n = 0;
    assert_int_equal (cgs_seal_open (&key, "mti", buf, len + 1, &h, out, sizeof out, &n), -EBADMSG);
    // Too small an output buffer is said, not overrun.
    assert_int_equal (cgs_seal_open (&key, "mti", buf, len, &h, out, 3, &n), -ENOBUFS);
    size_t l2 = 0;
    assert_int_equal (cgs_seal (&key, "mti", &s_h, s_plain, sizeof s_plain, buf, len - 1, &l2),
                      -ENOBUFS);
}

static void test_refuses_bad_input (void **state)
{
    (void)state;
    cgs_seal_key_t key;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    uint8_t buf[512], out[512];
    size_t len = 0;
    cgs_seal_header_t h = s_h;
    memset (h.source, 'x', CGS_SEAL_SOURCE_MAX);
    h.source[CGS_SEAL_SOURCE_MAX] = '\0';
    assert_int_equal (cgs_seal (&key, "mti", &h, "", 0, buf, sizeof buf, &len), 0);
    assert_int_equal (cgs_seal_open (&key, "mti", buf, len, &h, out, sizeof out, &len), 0);
    assert_int_equal (len, 0);
    // An unsealed protobuf payload is no sealed payload.
    assert_int_equal (
        cgs_seal_open (&key, "mti", s_plain, sizeof s_plain, &h, out, sizeof out, &len), -EPROTO);
}

static void s_write (const char *path, const char *text)
{
    FILE *f = fopen (path, "w");
    assert_non_null (f);
    fputs (text, f);
    assert_int_equal (fclose (f), 0);
}

static void test_key_file (void **state)
{
    (void)state;
    char path[] = "/tmp/test_seal_XXXXXX";
    int fd = mkstemp (path);
    assert_true (fd >= 0);
    close (fd);
    cgs_seal_key_t key, back;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    char text[CGS_SEAL_KEY_TEXT_MAX];
    cgs_seal_key_format (&key, text, sizeof text);
    s_write (path, text);
    char err[512];
    assert_int_equal (cgs_seal_key_load (path, &back, err, sizeof err), 0);
    assert_memory_equal (key.k, back.k, sizeof key.k);

    s_write (path, "# a comment\n\n0123\n");
    assert_int_equal (cgs_seal_key_load (path, &back, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, ":3: a key is 64 hexadecimal digits"));
    s_write (path, "# c\n0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdeZ\n");
    assert_int_equal (cgs_seal_key_load (path, &back, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, ":2: not a hexadecimal digit at column 64"));
    s_write (path, "# nothing\n");
    assert_int_equal (cgs_seal_key_load (path, &back, err, sizeof err), -ENODATA);
    assert_non_null (strstr (err, "no key in it"));
    unlink (path);
    assert_int_equal (cgs_seal_key_load (path, &back, err, sizeof err), -ENOENT);
    assert_non_null (strstr (err, path));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_round_trip),         cmocka_unit_test (test_tampered_byte),
        cmocka_unit_test (test_wrong_key_or_topic), cmocka_unit_test (test_truncated),
        cmocka_unit_test (test_refuses_bad_input),  cmocka_unit_test (test_key_file),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
