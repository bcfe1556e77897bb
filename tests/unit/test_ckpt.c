/* Unit tests of cgs_ckpt, the common checkpoint frame: every field round
 * trips exactly (NaN and infinities too) in the documented layout; the CRC
 * is the standard CRC-32 (check value 0xCBF43926 of "123456789"); every
 * truncation, every flipped bit, a wrong magic, another version, bytes
 * past the end are refused with their own error and a reason; the reader
 * never reads past the payload and its failure is sticky. */
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint8_t *s_frame (size_t *ret_len)
{
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, "TEST", 3);
    cgs_ckpt_put_u8 (&w, 0xAB);
    cgs_ckpt_put_bool (&w, true);
    cgs_ckpt_put_u32 (&w, 0xDEADBEEF);
    cgs_ckpt_put_u64 (&w, 0x0123456789ABCDEFull);
    cgs_ckpt_put_f64 (&w, -1.5);
    cgs_ckpt_put_f64 (&w, NAN);
    cgs_ckpt_put_f64 (&w, INFINITY);
    cgs_ckpt_put_bytes (&w, "xyz", 3);
    cgs_ckpt_put_str (&w, "hello");
    cgs_ckpt_put_bytes (&w, NULL, 0);
    cgs_ckpt_put_str (&w, "");
    uint8_t *buf = NULL;
    assert_int_equal (cgs_ckpt_writer_finish (&w, &buf, ret_len), 0);
    assert_null (w.buf); // handed over: the writer is empty
    cgs_ckpt_writer_fini (&w);
    return buf;
}

static void test_round_trip (void **state)
{
    (void)state;
    size_t len = 0;
    uint8_t *buf = s_frame (&len);
    size_t payload = 1 + 1 + 4 + 8 + 3 * 8 + (8 + 3) + (4 + 5) + 8 + 4;
    assert_int_equal (len, CGS_CKPT_HEAD + payload + CGS_CKPT_TAIL);
    // The header as documented: magic, version, length, little-endian.
    assert_memory_equal (buf, "TEST", 4);
    assert_memory_equal (buf + 4, "\x03\x00\x00\x00", 4);
    assert_int_equal (buf[8], payload);
    assert_memory_equal (buf + 9, "\0\0\0\0\0\0\0", 7);
    assert_int_equal (buf[CGS_CKPT_HEAD], 0xAB);
    assert_memory_equal (buf + CGS_CKPT_HEAD + 2, "\xEF\xBE\xAD\xDE", 4);
    uint32_t crc = cgs_crc32 (buf + CGS_CKPT_HEAD, payload);
    for (int i = 0; i < 4; i++)
        assert_int_equal (buf[len - 4 + i], (uint8_t)(crc >> (8 * i)));

    cgs_ckpt_reader_t r;
    char err[256] = "";
    assert_int_equal (cgs_ckpt_open (&r, buf, len, "TEST", 3, "test checkpoint", err, sizeof err),
                      0);
    assert_int_equal (cgs_ckpt_left (&r), payload);
    assert_int_equal (cgs_ckpt_get_u8 (&r), 0xAB);
    assert_true (cgs_ckpt_get_bool (&r));
    assert_int_equal (cgs_ckpt_get_u32 (&r), 0xDEADBEEF);
    assert_true (cgs_ckpt_get_u64 (&r) == 0x0123456789ABCDEFull);
    assert_true (cgs_ckpt_get_f64 (&r) == -1.5);
    assert_true (isnan (cgs_ckpt_get_f64 (&r)));
    assert_true (isinf (cgs_ckpt_get_f64 (&r)));
    size_t n = 0;
    const uint8_t *b = cgs_ckpt_get_bytes (&r, &n);
    assert_int_equal (n, 3);
    assert_memory_equal (b, "xyz", 3);
    char s[8];
    cgs_ckpt_get_str (&r, s, sizeof s);
    assert_string_equal (s, "hello");
    b = cgs_ckpt_get_bytes (&r, &n);
    assert_int_equal (n, 0);
    cgs_ckpt_get_str (&r, s, sizeof s);
    assert_string_equal (s, "");
    assert_true (cgs_ckpt_ok (&r));
    assert_int_equal (cgs_ckpt_left (&r), 0);
    assert_int_equal (cgs_ckpt_end (&r, "test checkpoint", err, sizeof err), 0);
    free (buf);
}

/* The frame's CRC is CRC-32/IEEE: "123456789" as the payload gives the
 * standard check value 0xCBF43926. */
static void test_crc_check_value (void **state)
{
    (void)state;
    assert_int_equal (cgs_crc32 ("123456789", 9), 0xCBF43926u);
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, "CRC3", 1);
    for (const char *c = "123456789"; *c; c++)
        cgs_ckpt_put_u8 (&w, (uint8_t)*c);
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (cgs_ckpt_writer_finish (&w, &buf, &len), 0);
    assert_int_equal (len, CGS_CKPT_HEAD + 9 + CGS_CKPT_TAIL);
    assert_memory_equal (buf + len - 4, "\x26\x39\xF4\xCB", 4);
    free (buf);
}

/* Every prefix of a frame is refused as truncated; bytes past its end too. */
static void test_truncated_at_every_length (void **state)
{
    (void)state;
    size_t len = 0;
    uint8_t *buf = s_frame (&len);
    cgs_ckpt_reader_t r = {.len = 12345};
    for (size_t l = 0; l < len; l++) {
        char err[256] = "";
        int rc = cgs_ckpt_open (&r, buf, l, "TEST", 3, "test checkpoint", err, sizeof err);
        if (rc != -EINVAL)
            fail_msg ("%zu of %zu bytes: %d, expected -EINVAL", l, len, rc);
        assert_non_null (strstr (err, "test checkpoint"));
        assert_int_equal (r.len, 12345); // not written on failure
    }
    uint8_t *longer = malloc (len + 1);
    memcpy (longer, buf, len);
    longer[len] = 0;
    char err[256] = "";
    assert_int_equal (
        cgs_ckpt_open (&r, longer, len + 1, "TEST", 3, "test checkpoint", err, sizeof err),
        -EINVAL);
    assert_non_null (strstr (err, "past its end"));
    assert_int_equal (cgs_ckpt_open (&r, NULL, 0, "TEST", 3, "x", err, sizeof err), -EINVAL);
    free (longer);
    free (buf);
}

/* A flipped bit is caught wherever it is: in the magic (-EPROTO), the
 * version (-ENOTSUP), the length (-EINVAL), the payload or the CRC
 * (-EBADMSG). */
static void test_flipped_bits (void **state)
{
    (void)state;
    size_t len = 0;
    uint8_t *buf = s_frame (&len);
    cgs_ckpt_reader_t r;
    for (size_t i = 0; i < len; i++)
        for (int bit = 0; bit < 8; bit++) {
            buf[i] ^= (uint8_t)(1u << bit);
            char err[256] = "";
            int want = i < 4 ? -EPROTO : i < 8 ? -ENOTSUP : i < 16 ? -EINVAL : -EBADMSG;
            int rc = cgs_ckpt_open (&r, buf, len, "TEST", 3, "test checkpoint", err, sizeof err);
            if (rc != want)
                fail_msg ("byte %zu bit %d: %d, expected %d (%s)", i, bit, rc, want, err);
            assert_true (strlen (err) > 0);
            buf[i] ^= (uint8_t)(1u << bit);
        }
    char err[256] = "";
    assert_int_equal (cgs_ckpt_open (&r, buf, len, "TEST", 3, "x", err, sizeof err), 0);
    buf[len / 2] ^= 1;
    assert_int_equal (cgs_ckpt_open (&r, buf, len, "TEST", 3, "x", err, sizeof err), -EBADMSG);
    assert_non_null (strstr (err, "checksum"));
    free (buf);
}

/* Another kind, or a file from before the format: refused naming what it
 * begins with; another version: refused naming both versions. */
static void test_wrong_magic_and_version (void **state)
{
    (void)state;
    size_t len = 0;
    uint8_t *buf = s_frame (&len);
    cgs_ckpt_reader_t r;
    char err[256] = "";
    assert_int_equal (
        cgs_ckpt_open (&r, buf, len, "TRKS", 3, "trackerd checkpoint", err, sizeof err), -EPROTO);
    assert_string_equal (err, "not a trackerd checkpoint: it begins \"TEST\", not \"TRKS\" "
                              "(another kind of file, or one saved before mscgs's common "
                              "checkpoint format)");
    const char old[] = "MSCGSTRK\x02\x00\x00\x00\x01\x00\x00\x00\x00\x00\x00\x00";
    assert_int_equal (
        cgs_ckpt_open (&r, old, sizeof old - 1, "TRKS", 1, "trackerd checkpoint", err, sizeof err),
        -EPROTO);
    assert_non_null (strstr (err, "it begins \"MSCG\""));
    const uint8_t binary[] = {0x55, 0x00, 0xff, 0x01, 1, 0, 0, 0};
    assert_int_equal (cgs_ckpt_open (&r, binary, sizeof binary, "TRKS", 1, "x", err, sizeof err),
                      -EPROTO);
    assert_non_null (strstr (err, "it begins 0x5500ff01"));
    assert_int_equal (cgs_ckpt_open (&r, "U", 1, "TRKS", 1, "x", err, sizeof err), -EPROTO);
    assert_int_equal (cgs_ckpt_open (&r, buf, len, "TEST", 4, "test checkpoint", err, sizeof err),
                      -ENOTSUP);
    assert_string_equal (err, "a test checkpoint saved by another version of mscgs (format 3; "
                              "this one reads format 4)");
    // The unchecked open (salvage) checks magic and version only.
    assert_int_equal (cgs_ckpt_open_unchecked (&r, buf, len - 9, "TEST", 3), 0);
    assert_int_equal (cgs_ckpt_get_u8 (&r), 0xAB);
    assert_int_equal (cgs_ckpt_open_unchecked (&r, buf, len, "TEST", 4), -ENOTSUP);
    assert_int_equal (cgs_ckpt_open_unchecked (&r, buf, len, "TRKS", 3), -EPROTO);
    assert_int_equal (cgs_ckpt_open_unchecked (&r, buf, 7, "TEST", 3), -EINVAL);
    free (buf);
}

/* Reads past the payload fail, return 0 and stay failed; so do a bad flag,
 * a non-finite value read as finite, a string too long or holding a NUL,
 * and a byte string longer than what is left. */
static void test_reader_bounds (void **state)
{
    (void)state;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, "RDR1", 1);
    cgs_ckpt_put_u8 (&w, 2);
    cgs_ckpt_put_f64 (&w, NAN);
    cgs_ckpt_put_str (&w, "toolong");
    cgs_ckpt_put_u32 (&w, 3);
    cgs_ckpt_put_u8 (&w, 'a');
    cgs_ckpt_put_u8 (&w, 0);
    cgs_ckpt_put_u8 (&w, 'b');
    cgs_ckpt_put_u64 (&w, 1000);
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (cgs_ckpt_writer_finish (&w, &buf, &len), 0);
    char err[256] = "";
    cgs_ckpt_reader_t r, start;
    assert_int_equal (cgs_ckpt_open (&start, buf, len, "RDR1", 1, "x", err, sizeof err), 0);

    r = start;
    assert_false (cgs_ckpt_get_bool (&r)); // 2 is no flag
    assert_false (cgs_ckpt_ok (&r));
    assert_int_equal (cgs_ckpt_get_u8 (&r), 0); // sticky: nothing more is read
    assert_int_equal (cgs_ckpt_end (&r, "x", err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "does not decode"));

    r = start;
    (void)cgs_ckpt_get_u8 (&r);
    assert_true (cgs_ckpt_get_finite (&r) == 0); // NaN refused
    assert_false (cgs_ckpt_ok (&r));

    r = start;
    (void)cgs_ckpt_get_u8 (&r);
    (void)cgs_ckpt_get_f64 (&r);
    char s[8] = "x";
    cgs_ckpt_get_str (&r, s, 7); // "toolong" needs 8 bytes
    assert_false (cgs_ckpt_ok (&r));
    assert_string_equal (s, "");

    r = start;
    (void)cgs_ckpt_get_u8 (&r);
    (void)cgs_ckpt_get_f64 (&r);
    cgs_ckpt_get_str (&r, s, sizeof s);
    assert_string_equal (s, "toolong");
    cgs_ckpt_get_str (&r, s, sizeof s); // "a\0b": a NUL inside
    assert_false (cgs_ckpt_ok (&r));

    r = start;
    (void)cgs_ckpt_get_u8 (&r);
    (void)cgs_ckpt_get_f64 (&r);
    cgs_ckpt_get_str (&r, s, sizeof s);
    (void)cgs_ckpt_get_u32 (&r);
    (void)cgs_ckpt_get_u8 (&r);
    (void)cgs_ckpt_get_u8 (&r);
    (void)cgs_ckpt_get_u8 (&r);
    size_t n = 99;
    assert_null (cgs_ckpt_get_bytes (&r, &n)); // claims 1000 bytes, none left
    assert_int_equal (n, 0);
    assert_false (cgs_ckpt_ok (&r));

    r = start; // fields left unread
    (void)cgs_ckpt_get_u8 (&r);
    assert_int_equal (cgs_ckpt_end (&r, "x", err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "bytes past its fields"));
    r = start;
    (void)cgs_ckpt_get_u8 (&r);
    cgs_ckpt_fail (&r);
    assert_false (cgs_ckpt_ok (&r));

    r = start; // past the end: every get fails, returns 0
    while (cgs_ckpt_left (&r) > 0)
        (void)cgs_ckpt_get_u8 (&r);
    assert_true (cgs_ckpt_ok (&r));
    assert_int_equal (cgs_ckpt_end (&r, "x", err, sizeof err), 0);
    assert_int_equal (cgs_ckpt_get_u64 (&r), 0);
    assert_false (cgs_ckpt_ok (&r));
    free (buf);
}

/* An abandoned writer frees what it holds; fini is safe twice and on a
 * zeroed writer. */
static void test_writer_fini (void **state)
{
    (void)state;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, "FINI", 1);
    for (int i = 0; i < 1000; i++)
        cgs_ckpt_put_u64 (&w, (uint64_t)i);
    cgs_ckpt_writer_fini (&w);
    cgs_ckpt_writer_fini (&w);
    cgs_ckpt_writer_t z = {0};
    cgs_ckpt_writer_fini (&z);
    cgs_ckpt_writer_fini (NULL);
    // A failed writer hands nothing over.
    cgs_ckpt_writer_init (&w, "FAIL", 1);
    w.failed = true;
    cgs_ckpt_put_u32 (&w, 1);
    uint8_t *buf = (uint8_t *)&w;
    size_t len = 77;
    assert_int_equal (cgs_ckpt_writer_finish (&w, &buf, &len), -ENOMEM);
    assert_true (buf == (uint8_t *)&w && len == 77);
    assert_null (w.buf);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_round_trip),
        cmocka_unit_test (test_crc_check_value),
        cmocka_unit_test (test_truncated_at_every_length),
        cmocka_unit_test (test_flipped_bits),
        cmocka_unit_test (test_wrong_magic_and_version),
        cmocka_unit_test (test_reader_bounds),
        cmocka_unit_test (test_writer_fini),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
