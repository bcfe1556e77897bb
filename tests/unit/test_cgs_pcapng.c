/* test_cgs_pcapng — UDP datagrams into pcapng (cgs_pcapng):
 *   - the blocks as the specification lays them out: a section header
 *     (byte-order magic, version 1.0), an interface of LINKTYPE_IPV4 with
 *     nanosecond time stamps, an enhanced packet block per datagram (its
 *     time stamp, lengths, and an IPv4 header whose checksum verifies, UDP
 *     ports and length, the payload);
 *   - tshark (Wireshark's reader, not ours) reads every datagram with its
 *     addresses, ports and time;
 *   - append: a file cut in the middle of a block gets the block cut off and
 *     a second section, which tshark reads whole; a file that is not pcapng
 *     is refused. */
#include "cgs_pcapng.h"
#include "test_util.h"

#include <arpa/inet.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char s_dir[512]; // under $TMPDIR

#define S_N 50

static struct sockaddr_in s_addr (const char *ip, int port)
{
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons ((uint16_t)port)};
    inet_pton (AF_INET, ip, &a.sin_addr);
    return a;
}

static void s_write (const char *path, int first, int n, bool append)
{
    char err[256] = "";
    cgs_pcapng_t *p = cgs_pcapng_open (path, "test", append, err, sizeof err);
    if (!p)
        fail_msg ("%s", err);
    struct sockaddr_in src = s_addr ("10.1.2.3", 40000), dst = s_addr ("127.0.0.1", 3000);
    for (int i = first; i < first + n; i++) {
        uint8_t pay[144];
        for (size_t k = 0; k < sizeof pay; k++)
            pay[k] = (uint8_t)(i + k);
        size_t len = 100 + (size_t)(i % 41); // odd lengths: padding
        assert_int_equal (cgs_pcapng_udp (p, 1700000000000000000ull + (uint64_t)i * 1000001, &src,
                                          &dst, pay, len),
                          0);
    }
    assert_int_equal (cgs_pcapng_udp (p, 0, &src, &dst, "x", 70000), -EMSGSIZE);
    assert_int_equal (cgs_pcapng_packets (p), (uint64_t)n);
    assert_string_equal (cgs_pcapng_error (p), "");
    assert_int_equal (cgs_pcapng_close (&p, err, sizeof err), 0);
    assert_null (p);
}

static uint8_t *s_slurp (const char *path, size_t *len)
{
    FILE *f = fopen (path, "rb");
    assert_non_null (f);
    fseek (f, 0, SEEK_END);
    *len = (size_t)ftell (f);
    fseek (f, 0, SEEK_SET);
    uint8_t *b = malloc (*len + 1);
    assert_int_equal (fread (b, 1, *len, f), *len);
    fclose (f);
    return b;
}

static uint32_t s_u32 (const uint8_t *p)
{
    uint32_t v;
    memcpy (&v, p, 4);
    return v;
}

/* Walk the blocks: the datagrams found (each checked), sections counted. */
static int s_walk (const uint8_t *f, size_t len, int *sections)
{
    size_t pos = 0;
    int packets = 0;
    *sections = 0;
    while (pos < len) {
        assert_true (pos + 12 <= len);
        uint32_t type = s_u32 (f + pos), blen = s_u32 (f + pos + 4);
        assert_true (blen >= 12 && blen % 4 == 0 && pos + blen <= len);
        assert_int_equal (s_u32 (f + pos + blen - 4), blen); // the length again
        if (type == 0x0A0D0D0A) {
            assert_int_equal (s_u32 (f + pos + 8), 0x1A2B3C4D);
            assert_int_equal (f[pos + 12] | f[pos + 13] << 8, 1); // version 1.0
            (*sections)++;
        } else if (type == 1) {
            assert_int_equal (f[pos + 8] | f[pos + 9] << 8, 228); // LINKTYPE_IPV4
            assert_int_equal (f[pos + 16] | f[pos + 17] << 8, 9); // if_tsresol ...
            assert_int_equal (f[pos + 20], 9);                    // ... nanoseconds
        } else {
            assert_int_equal (type, 6);
            uint64_t ts = (uint64_t)s_u32 (f + pos + 12) << 32 | s_u32 (f + pos + 16);
            uint32_t cap = s_u32 (f + pos + 20);
            assert_int_equal (s_u32 (f + pos + 24), cap);
            const uint8_t *ip = f + pos + 28;
            int i = (int)((ts - 1700000000000000000ull) / 1000001);
            assert_true (ts == 1700000000000000000ull + (uint64_t)i * 1000001);
            size_t plen = 100 + (size_t)(i % 41);
            assert_int_equal (cap, 28 + plen);
            assert_int_equal (ip[0], 0x45);
            assert_int_equal (ip[2] << 8 | ip[3], cap);
            assert_int_equal (ip[9], 17);
            uint32_t sum = 0;
            for (int k = 0; k < 20; k += 2)
                sum += (uint32_t)(ip[k] << 8 | ip[k + 1]);
            while (sum >> 16)
                sum = (sum & 0xffff) + (sum >> 16);
            assert_int_equal (sum, 0xffff); // the header checksum verifies
            assert_memory_equal (ip + 12, "\x0a\x01\x02\x03\x7f\x00\x00\x01", 8);
            assert_int_equal (ip[20] << 8 | ip[21], 40000);
            assert_int_equal (ip[22] << 8 | ip[23], 3000);
            assert_int_equal (ip[24] << 8 | ip[25], 8 + plen);
            for (size_t k = 0; k < plen; k++)
                assert_int_equal (ip[28 + k], (uint8_t)(i + k));
            packets++;
        }
        pos += blen;
    }
    return packets;
}

/* tshark's count of UDP datagrams from 10.1.2.3:40000 to port 3000, or -1
 * when tshark is not there. */
static int s_tshark (const char *path)
{
    if (system ("command -v tshark >/dev/null 2>&1") != 0)
        return -1;
    char cmd[512];
    snprintf (cmd, sizeof cmd,
              "tshark -r '%s' -Y 'ip.src == 10.1.2.3 && udp.srcport == 40000 && udp.dstport == "
              "3000' 2>/dev/null | wc -l",
              path);
    FILE *p = popen (cmd, "r");
    assert_non_null (p);
    int n = -1;
    assert_int_equal (fscanf (p, "%d", &n), 1);
    pclose (p);
    return n;
}

static void test_write (void **state)
{
    (void)state;
    char path[128];
    snprintf (path, sizeof path, "%s/a.pcapng", s_dir);
    s_write (path, 0, S_N, false);
    size_t len;
    uint8_t *f = s_slurp (path, &len);
    int sections;
    assert_int_equal (s_walk (f, len, &sections), S_N);
    assert_int_equal (sections, 1);
    free (f);
    int t = s_tshark (path);
    if (t < 0)
        fail_msg ("no tshark (scripts/install-deps installs it)");
    assert_int_equal (t, S_N);
    unlink (path);
}

static void test_append (void **state)
{
    (void)state;
    char path[128];
    snprintf (path, sizeof path, "%s/b.pcapng", s_dir);
    s_write (path, 0, S_N, false);
    size_t len;
    uint8_t *f = s_slurp (path, &len);
    // Cut in the middle of the last block: a writer killed.
    assert_int_equal (truncate (path, (off_t)(len - 37)), 0);
    free (f);
    s_write (path, S_N, 20, true);
    f = s_slurp (path, &len);
    int sections;
    assert_int_equal (s_walk (f, len, &sections), S_N - 1 + 20);
    assert_int_equal (sections, 2);
    free (f);
    assert_int_equal (s_tshark (path), S_N - 1 + 20);
    // Not pcapng: refused, left alone.
    FILE *o = fopen (path, "w");
    fputs ("not a capture\n", o);
    fclose (o);
    char err[256] = "";
    assert_null (cgs_pcapng_open (path, "test", true, err, sizeof err));
    assert_non_null (strstr (err, "not a pcapng file: refused"));
    f = s_slurp (path, &len);
    assert_int_equal (len, 14);
    free (f);
    unlink (path);
    assert_null (cgs_pcapng_open ("/nonexistent-dir/x.pcapng", "t", false, err, sizeof err));
    assert_non_null (strstr (err, "cannot create"));
}

static int s_setup (void **state)
{
    (void)state;
    const char *t = getenv ("TMPDIR");
    snprintf (s_dir, sizeof s_dir, "%s/cgs-pcapng-XXXXXX", t && *t ? t : "/tmp");
    return mkdtemp (s_dir) ? 0 : -1;
}

static int s_teardown (void **state)
{
    (void)state;
    return rmdir (s_dir);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_write),
        cmocka_unit_test (test_append),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
