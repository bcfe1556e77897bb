/* cgs_pcapng — UDP datagrams into a pcapng file (the format Wireshark,
 * tshark, editcap and mergecap read and write): a section header, one
 * interface of raw IPv4 (LINKTYPE_IPV4) with nanosecond time stamps, and an
 * enhanced packet block per datagram, its IPv4 and UDP headers made from the
 * addresses given (the IPv4 header's checksum computed; UDP's 0, which IPv4
 * allows). Written with stdio: cgs_pcapng_flush puts what is buffered in the
 * file (a writer flushes at least once a second); a file cut short reads up
 * to its last whole block. No globals. */
#ifndef CGS_PCAPNG_H
#define CGS_PCAPNG_H

#include <netinet/in.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct cgs_pcapng cgs_pcapng_t;

/* Create (or truncate) path; application names the writer (shb_userappl).
 * With append, an existing pcapng file is kept: a block cut short at its end
 * (a writer killed) is cut off, and a new section follows (readers read all
 * sections); one that is not pcapng is refused. NULL with the reason in err. */
cgs_pcapng_t *cgs_pcapng_open (const char *path, const char *application, bool append, char *err,
                               size_t errlen);
/* One datagram from src to dst at time_ns (Unix nanoseconds): 0, or -EIO
 * (the first error is kept: cgs_pcapng_error), -EMSGSIZE over 65507 bytes. */
int cgs_pcapng_udp (cgs_pcapng_t *self, uint64_t time_ns, const struct sockaddr_in *src,
                    const struct sockaddr_in *dst, const void *payload, size_t len);
/* Write out what is buffered: 0 or -EIO. */
int cgs_pcapng_flush (cgs_pcapng_t *self);
/* Datagrams written. */
uint64_t cgs_pcapng_packets (const cgs_pcapng_t *self);
/* The first write error ("" when none). */
const char *cgs_pcapng_error (const cgs_pcapng_t *self);
/* Flush, close, free: 0 or -EIO with the reason in err. Accepts NULL. */
int cgs_pcapng_close (cgs_pcapng_t **self_p, char *err, size_t errlen);

#endif
