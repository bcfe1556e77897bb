/* cgs_seal — XChaCha20-Poly1305 sealing of bus payloads. */
#include "cgs_seal.h"

#include <ctype.h>
#include <errno.h>
#include <sodium.h>
#include <stdio.h>
#include <string.h>

#define S_MAGIC_LEN 4
#define S_VERSION   1
#define S_CLEAR     34 // clear header without the source
#define S_NONCE     crypto_aead_xchacha20poly1305_ietf_NPUBBYTES
#define S_TAG       crypto_aead_xchacha20poly1305_ietf_ABYTES

_Static_assert(CGS_SEAL_KEY_BYTES == crypto_aead_xchacha20poly1305_ietf_KEYBYTES, "key size");
_Static_assert(CGS_SEAL_FIXED == S_CLEAR + S_NONCE + S_TAG, "overhead");

static const uint8_t s_magic[S_MAGIC_LEN] = {0x00, 'C', 'G', 'S'};

int cgs_seal_init (void)
{
    return sodium_init () < 0 ? -EIO : 0;
}

int cgs_seal_key_new (cgs_seal_key_t *key)
{
    if (cgs_seal_init () < 0)
        return -EIO;
    crypto_aead_xchacha20poly1305_ietf_keygen (key->k);
    return 0;
}

void cgs_seal_key_format (const cgs_seal_key_t *key, char *buf, size_t len)
{
    char hex[2 * CGS_SEAL_KEY_BYTES + 1];
    for (size_t i = 0; i < CGS_SEAL_KEY_BYTES; i++)
        snprintf (hex + 2 * i, 3, "%02x", key->k[i]);
    snprintf (buf, len, "# mscgs exercise group key (XChaCha20-Poly1305); keep it secret\n%s\n",
              hex);
}

static int s_hex (int c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    c = tolower (c);
    return c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

int cgs_seal_key_load (const char *path, cgs_seal_key_t *key, char *err, size_t errlen)
{
    FILE *f = fopen (path, "r");
    if (!f) {
        int e = errno;
        snprintf (err, errlen, "%s: %s", path, strerror (e));
        return -e;
    }
    char line[512];
    int lineno = 0, rc = -ENODATA;
    snprintf (err, errlen, "%s: no key in it (64 hexadecimal digits; mscgs keygen --group)", path);
    while (fgets (line, sizeof line, f)) {
        lineno++;
        char *p = line;
        while (isspace ((unsigned char)*p))
            p++;
        if (!*p || *p == '#')
            continue;
        size_t n = strlen (p);
        while (n && isspace ((unsigned char)p[n - 1]))
            p[--n] = '\0';
        rc = -EINVAL;
        if (n != 2 * CGS_SEAL_KEY_BYTES) {
            snprintf (err, errlen,
                      "%s:%d: a key is 64 hexadecimal digits, this line has %zu characters", path,
                      lineno, n);
            break;
        }
        cgs_seal_key_t k;
        size_t i = 0;
        size_t bad = 0; // the first character that is no hexadecimal digit, 1-based
        for (; i < CGS_SEAL_KEY_BYTES && !bad; i++) {
            int hi = s_hex ((unsigned char)p[2 * i]), lo = s_hex ((unsigned char)p[2 * i + 1]);
            if (hi < 0 || lo < 0)
                bad = 2 * i + (hi < 0 ? 1 : 2);
            else
                k.k[i] = (uint8_t)(hi << 4 | lo);
        }
        if (bad) {
            snprintf (err, errlen, "%s:%d: not a hexadecimal digit at column %zu", path, lineno,
                      (size_t)(p - line) + bad);
            break;
        }
        *key = k;
        sodium_memzero (&k, sizeof k);
        rc = 0;
        break;
    }
    sodium_memzero (line, sizeof line);
    fclose (f);
    if (rc == 0 && errlen)
        err[0] = '\0';
    return rc;
}

bool cgs_seal_is_sealed (const void *payload, size_t len)
{
    return len >= S_MAGIC_LEN && memcmp (payload, s_magic, S_MAGIC_LEN) == 0;
}

size_t cgs_seal_size (size_t n, const char *source)
{
    return n + CGS_SEAL_FIXED + strlen (source);
}

static void s_put_u32 (uint8_t *p, uint32_t v)
{
    for (int i = 3; i >= 0; i--, v >>= 8)
        p[i] = (uint8_t)v;
}
static void s_put_u64 (uint8_t *p, uint64_t v)
{
    for (int i = 7; i >= 0; i--, v >>= 8)
        p[i] = (uint8_t)v;
}
static uint32_t s_get_u32 (const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}
static uint64_t s_get_u64 (const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v = v << 8 | p[i];
    return v;
}

/* The associated data: the topic, length-prefixed, then the clear header. */
static size_t s_ad (uint8_t *ad, const char *topic, size_t tlen, const uint8_t *clear, size_t clen)
{
    ad[0] = (uint8_t)tlen;
    memcpy (ad + 1, topic, tlen);
    memcpy (ad + 1 + tlen, clear, clen);
    return 1 + tlen + clen;
}

int cgs_seal (const cgs_seal_key_t *key, const char *topic, const cgs_seal_header_t *h,
              const void *plain, size_t n, void *out, size_t cap, size_t *out_len)
{
    size_t tlen = strlen (topic), slen = strlen (h->source);
    if (tlen > CGS_SEAL_TOPIC_MAX || slen > CGS_SEAL_SOURCE_MAX)
        return -EINVAL;
    if (cgs_seal_init () < 0)
        return -EIO;
    size_t clen = S_CLEAR + slen, total = clen + S_NONCE + n + S_TAG;
    if (cap < total)
        return -ENOBUFS;
    uint8_t *o = out;
    memcpy (o, s_magic, S_MAGIC_LEN);
    o[4] = S_VERSION;
    s_put_u32 (o + 5, h->exercise_id);
    s_put_u64 (o + 9, h->epoch);
    s_put_u64 (o + 17, h->seq);
    uint64_t bits;
    memcpy (&bits, &h->wall_time_s, sizeof bits);
    s_put_u64 (o + 25, bits);
    o[33] = (uint8_t)slen;
    memcpy (o + S_CLEAR, h->source, slen);
    uint8_t *nonce = o + clen;
    randombytes_buf (nonce, S_NONCE);
    uint8_t ad[1 + CGS_SEAL_TOPIC_MAX + S_CLEAR + CGS_SEAL_SOURCE_MAX];
    size_t adlen = s_ad (ad, topic, tlen, o, clen);
    unsigned long long clen_out = 0;
    crypto_aead_xchacha20poly1305_ietf_encrypt (nonce + S_NONCE, &clen_out, plain, n, ad, adlen,
                                                NULL, nonce, key->k);
    *out_len = clen + S_NONCE + (size_t)clen_out;
    return 0;
}

int cgs_seal_open (const cgs_seal_key_t *key, const char *topic, const void *sealed, size_t len,
                   cgs_seal_header_t *h, void *out, size_t cap, size_t *out_len)
{
    const uint8_t *s = sealed;
    size_t tlen = strlen (topic);
    if (tlen > CGS_SEAL_TOPIC_MAX || len < CGS_SEAL_FIXED || !cgs_seal_is_sealed (s, len) ||
        s[4] != S_VERSION || s[33] > CGS_SEAL_SOURCE_MAX)
        return -EPROTO;
    size_t slen = s[33], clen = S_CLEAR + slen;
    if (len < clen + S_NONCE + S_TAG)
        return -EPROTO;
    size_t n = len - clen - S_NONCE - S_TAG;
    if (cap < n)
        return -ENOBUFS;
    if (cgs_seal_init () < 0)
        return -EIO;
    uint8_t ad[1 + CGS_SEAL_TOPIC_MAX + S_CLEAR + CGS_SEAL_SOURCE_MAX];
    size_t adlen = s_ad (ad, topic, tlen, s, clen);
    unsigned long long mlen = 0;
    if (crypto_aead_xchacha20poly1305_ietf_decrypt (out, &mlen, NULL, s + clen + S_NONCE,
                                                    len - clen - S_NONCE, ad, adlen, s + clen,
                                                    key->k) != 0)
        return -EBADMSG;
    h->exercise_id = s_get_u32 (s + 5);
    h->epoch = s_get_u64 (s + 9);
    h->seq = s_get_u64 (s + 17);
    uint64_t bits = s_get_u64 (s + 25);
    memcpy (&h->wall_time_s, &bits, sizeof bits);
    memcpy (h->source, s + S_CLEAR, slen);
    h->source[slen] = '\0';
    *out_len = (size_t)mlen;
    return 0;
}
