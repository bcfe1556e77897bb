/* cgs_iface — this host's network interfaces, looked up by name ("eth0") or
 * by one of their IPv4 addresses, for the outputs that send UDP (the DIS
 * gateway; later the other external formats and the bus's multicast). They
 * keep their traffic on this machine unless an exercise names a real
 * interface, and need to know whether the one named is a loopback. */
#ifndef CGS_IFACE_H
#define CGS_IFACE_H

#include <net/if.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct {
    char name[IF_NAMESIZE]; // the kernel's name ("lo", "eth0")
    unsigned index;         // interface index (if_nametoindex)
    uint32_t addr;          // its first IPv4 address, host byte order (0: none)
    uint32_t broadcast;     // that address's broadcast address, host byte order (0: none)
    bool loopback;          // IFF_LOOPBACK: nothing sent on it leaves this machine
    bool multicast;         // IFF_MULTICAST
    bool up;                // IFF_UP
} cgs_iface_t;

/* The interface named by name_or_addr: an interface name or a dotted IPv4
 * address one of them has. 0 and *ret, -ENODEV when this host has none such,
 * -EINVAL for an empty or over-long name, or another negative errno when the
 * interfaces cannot be listed. */
int cgs_iface_find (const char *name_or_addr, cgs_iface_t *ret);
/* True for an address of 127.0.0.0/8, host byte order. */
bool cgs_iface_addr_is_loopback (uint32_t addr);
/* True for a name that can be an interface's: 1 to IF_NAMESIZE - 1
 * characters, letters, digits, '.', '_', '-' and '@'. */
bool cgs_iface_name_valid (const char *name);

#endif
