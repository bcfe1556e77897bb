/* cgs_iface — this host's network interfaces (see cgs_iface.h). */
#include "cgs_iface.h"

#include <arpa/inet.h>
#include <errno.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <stdio.h>
#include <string.h>

bool cgs_iface_addr_is_loopback (uint32_t addr)
{
    return (addr >> 24) == 127;
}

bool cgs_iface_name_valid (const char *name)
{
    size_t n = strlen (name);
    if (n == 0 || n >= IF_NAMESIZE)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = name[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '.' || c == '_' || c == '-' || c == '@'))
            return false;
    }
    return true;
}

int cgs_iface_find (const char *name_or_addr, cgs_iface_t *ret)
{
    struct in_addr want;
    bool by_addr = inet_pton (AF_INET, name_or_addr, &want) == 1;
    if (!by_addr && !cgs_iface_name_valid (name_or_addr))
        return -EINVAL;
    struct ifaddrs *list;
    if (getifaddrs (&list) < 0)
        return -errno;
    // The name of the interface wanted first (an address names one).
    const char *name = by_addr ? NULL : name_or_addr;
    for (struct ifaddrs *a = list; a && !name; a = a->ifa_next)
        if (a->ifa_addr && a->ifa_addr->sa_family == AF_INET &&
            ((struct sockaddr_in *)a->ifa_addr)->sin_addr.s_addr == want.s_addr)
            name = a->ifa_name;
    cgs_iface_t f = {0};
    bool found = false;
    for (struct ifaddrs *a = list; a && name; a = a->ifa_next) {
        if (strcmp (a->ifa_name, name) != 0)
            continue;
        if (!found) {
            found = true;
            snprintf (f.name, sizeof f.name, "%s", a->ifa_name);
            f.loopback = (a->ifa_flags & IFF_LOOPBACK) != 0;
            f.multicast = (a->ifa_flags & IFF_MULTICAST) != 0;
            f.up = (a->ifa_flags & IFF_UP) != 0;
        }
        if (a->ifa_addr && a->ifa_addr->sa_family == AF_INET && f.addr == 0) {
            f.addr = ntohl (((struct sockaddr_in *)a->ifa_addr)->sin_addr.s_addr);
            if ((a->ifa_flags & IFF_BROADCAST) && a->ifa_broadaddr)
                f.broadcast = ntohl (((struct sockaddr_in *)a->ifa_broadaddr)->sin_addr.s_addr);
        }
    }
    freeifaddrs (list);
    if (!found)
        return -ENODEV;
    f.index = if_nametoindex (f.name);
    if (f.index == 0)
        return -ENODEV; // gone meanwhile
    if (by_addr)
        f.addr = ntohl (want.s_addr); // the address named, when the interface has several
    *ret = f;
    return 0;
}
