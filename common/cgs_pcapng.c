/* cgs_pcapng — see cgs_pcapng.h. Block layouts from the pcapng
 * specification (IETF draft-ietf-opsawg-pcapng): every block is its type, its
 * total length, its body padded to 32 bits, and its total length again;
 * written in this host's byte order, which the section header's byte-order
 * magic tells readers. */
#include "cgs_pcapng.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cgs_util.h"

#define S_SHB         0x0A0D0D0Au
#define S_IDB         0x00000001u
#define S_EPB         0x00000006u
#define S_BOM         0x1A2B3C4Du
#define S_LINK_IPV4   228u // LINKTYPE_IPV4: raw IPv4, no link header
#define S_OPT_END     0
#define S_OPT_USERAPP 4 // shb_userappl
#define S_OPT_TSRESOL 9 // if_tsresol
#define S_MAX_UDP     65507

struct cgs_pcapng {
    FILE *f;
    char path[4096];
    char error[256];
    uint64_t packets;
    uint16_t ip_id;
};

static int s_fail (cgs_pcapng_t *self, const char *what)
{
    if (!self->error[0])
        snprintf (self->error, sizeof self->error, "%s: %s: %s", self->path, what,
                  strerror (errno ? errno : EIO));
    return -EIO;
}

static int s_put (cgs_pcapng_t *self, const void *p, size_t n)
{
    if (self->error[0])
        return -EIO;
    if (n && fwrite (p, 1, n, self->f) != n)
        return s_fail (self, "cannot write");
    return 0;
}

static int s_u32 (cgs_pcapng_t *self, uint32_t v)
{
    return s_put (self, &v, 4);
}

static int s_u16 (cgs_pcapng_t *self, uint16_t v)
{
    return s_put (self, &v, 2);
}

/* An option: code, length, value padded to 32 bits. */
static int s_opt (cgs_pcapng_t *self, uint16_t code, const void *v, uint16_t len)
{
    static const uint8_t zero[4] = {0};
    s_u16 (self, code);
    s_u16 (self, len);
    s_put (self, v, len);
    return s_put (self, zero, (4 - len % 4) % 4);
}

static uint32_t s_opt_size (size_t len)
{
    return (uint32_t)(4 + (len + 3) / 4 * 4);
}

/* The end of the last whole block of the pcapng file f (size bytes): its
 * offset, or -1 when f is not pcapng. */
static long s_whole (FILE *f, long size)
{
    uint32_t h[3];
    if (size < 12 || fseek (f, 0, SEEK_SET) != 0 || fread (h, 4, 3, f) != 3 || h[0] != S_SHB ||
        h[2] != S_BOM)
        return -1;
    long pos = 0;
    while (pos + 12 <= size) {
        uint32_t len;
        if (fseek (f, pos + 4, SEEK_SET) != 0 || fread (&len, 4, 1, f) != 1 || len < 12 ||
            len % 4 != 0 || pos + (long)len > size)
            break;
        pos += (long)len;
    }
    return pos;
}

cgs_pcapng_t *cgs_pcapng_open (const char *path, const char *application, bool append, char *err,
                               size_t errlen)
{
    cgs_pcapng_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_errf (err, errlen, "%s: out of memory", path);
        return NULL;
    }
    snprintf (self->path, sizeof self->path, "%s", path);
    struct stat st;
    if (append && stat (path, &st) == 0 && st.st_size > 0) {
        if (!(self->f = fopen (path, "r+b"))) {
            cgs_errf (err, errlen, "%s: cannot open: %s", path, strerror (errno));
            free (self);
            return NULL;
        }
        long end = s_whole (self->f, (long)st.st_size);
        if (end < 0 || ftruncate (fileno (self->f), end) != 0 ||
            fseek (self->f, end, SEEK_SET) != 0) {
            cgs_errf (err, errlen,
                      end < 0 ? "%s: not a pcapng file: refused (move it away)"
                              : "%s: cannot cut its partial block: %s",
                      path, strerror (errno));
            fclose (self->f);
            free (self);
            return NULL;
        }
    } else if (!(self->f = fopen (path, "wb"))) {
        cgs_errf (err, errlen, "%s: cannot create: %s", path, strerror (errno));
        free (self);
        return NULL;
    }
    const char *app = application ? application : "mscgs";
    size_t alen = strlen (app) > 200 ? 200 : strlen (app);
    // Section header: magic, byte order, version 1.0, section length unknown.
    uint32_t shb_len = 28 + s_opt_size (alen) + 4;
    s_u32 (self, S_SHB);
    s_u32 (self, shb_len);
    s_u32 (self, S_BOM);
    s_u16 (self, 1);
    s_u16 (self, 0);
    uint64_t unknown = UINT64_MAX;
    s_put (self, &unknown, 8);
    s_opt (self, S_OPT_USERAPP, app, (uint16_t)alen);
    s_opt (self, S_OPT_END, NULL, 0);
    s_u32 (self, shb_len);
    // Interface 0: raw IPv4, no snap length limit, time stamps in nanoseconds.
    uint8_t tsresol = 9;
    uint32_t idb_len = 16 + s_opt_size (1) + 4 + 4;
    s_u32 (self, S_IDB);
    s_u32 (self, idb_len);
    s_u16 (self, (uint16_t)S_LINK_IPV4);
    s_u16 (self, 0);
    s_u32 (self, 0);
    s_opt (self, S_OPT_TSRESOL, &tsresol, 1);
    s_opt (self, S_OPT_END, NULL, 0);
    s_u32 (self, idb_len);
    if (cgs_pcapng_flush (self) < 0) {
        cgs_errf (err, errlen, "%s", self->error);
        fclose (self->f);
        free (self);
        return NULL;
    }
    return self;
}

/* The IPv4 header checksum: the ones' complement of the ones' complement sum. */
static uint16_t s_ip_sum (const uint8_t *h, size_t n)
{
    uint32_t sum = 0;
    for (size_t i = 0; i + 1 < n; i += 2)
        sum += (uint32_t)h[i] << 8 | h[i + 1];
    while (sum >> 16)
        sum = (sum & 0xffff) + (sum >> 16);
    return (uint16_t)~sum;
}

int cgs_pcapng_udp (cgs_pcapng_t *self, uint64_t time_ns, const struct sockaddr_in *src,
                    const struct sockaddr_in *dst, const void *payload, size_t len)
{
    if (self->error[0])
        return -EIO;
    if (len > S_MAX_UDP)
        return -EMSGSIZE;
    uint8_t h[28];
    size_t total = 28 + len;
    uint16_t id = self->ip_id++;
    // IPv4: version 4, 20-byte header, don't fragment, TTL 64, UDP.
    h[0] = 0x45, h[1] = 0;
    h[2] = (uint8_t)(total >> 8), h[3] = (uint8_t)total;
    h[4] = (uint8_t)(id >> 8), h[5] = (uint8_t)id;
    h[6] = 0x40, h[7] = 0;
    h[8] = 64, h[9] = 17;
    h[10] = h[11] = 0;
    memcpy (h + 12, &src->sin_addr.s_addr, 4); // network order already
    memcpy (h + 16, &dst->sin_addr.s_addr, 4);
    uint16_t sum = s_ip_sum (h, 20);
    h[10] = (uint8_t)(sum >> 8), h[11] = (uint8_t)sum;
    // UDP: ports (network order already), length, no checksum.
    memcpy (h + 20, &src->sin_port, 2);
    memcpy (h + 22, &dst->sin_port, 2);
    h[24] = (uint8_t)((8 + len) >> 8), h[25] = (uint8_t)(8 + len);
    h[26] = h[27] = 0;
    static const uint8_t zero[4] = {0};
    size_t pad = (4 - total % 4) % 4;
    uint32_t blen = (uint32_t)(28 + total + pad + 4);
    s_u32 (self, S_EPB);
    s_u32 (self, blen);
    s_u32 (self, 0); // interface 0
    s_u32 (self, (uint32_t)(time_ns >> 32));
    s_u32 (self, (uint32_t)time_ns);
    s_u32 (self, (uint32_t)total);
    s_u32 (self, (uint32_t)total);
    s_put (self, h, sizeof h);
    s_put (self, payload, len);
    s_put (self, zero, pad);
    int rc = s_u32 (self, blen);
    if (rc == 0)
        self->packets++;
    return rc;
}

int cgs_pcapng_flush (cgs_pcapng_t *self)
{
    if (self->error[0])
        return -EIO;
    return fflush (self->f) == 0 ? 0 : s_fail (self, "cannot write");
}

uint64_t cgs_pcapng_packets (const cgs_pcapng_t *self)
{
    return self->packets;
}

const char *cgs_pcapng_error (const cgs_pcapng_t *self)
{
    return self->error;
}

int cgs_pcapng_close (cgs_pcapng_t **self_p, char *err, size_t errlen)
{
    cgs_pcapng_t *self = self_p ? *self_p : NULL;
    if (!self)
        return 0;
    int rc = cgs_pcapng_flush (self);
    if (fclose (self->f) != 0 && rc == 0)
        rc = s_fail (self, "cannot close");
    if (rc < 0)
        cgs_errf (err, errlen, "%s", self->error);
    free (self);
    *self_p = NULL;
    return rc;
}
