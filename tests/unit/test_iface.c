/* test_iface — this host's interfaces as cgs_iface finds them: the loopback
 * by its name and by its address (IFF_LOOPBACK, the kernel's index,
 * 127.0.0.1), a name or address this host does not have (-ENODEV), names
 * that cannot be an interface's (-EINVAL), and the loopback address range. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_iface.h"

#include <errno.h>
#include <net/if.h>
#include <string.h>

static void test_loopback (void **state)
{
    (void)state;
    cgs_iface_t f;
    memset (&f, 0x5a, sizeof f);
    assert_int_equal (cgs_iface_find ("lo", &f), 0);
    assert_string_equal (f.name, "lo");
    assert_true (f.loopback);
    assert_true (f.up);
    assert_int_equal (f.index, if_nametoindex ("lo"));
    assert_int_equal (f.addr, 0x7f000001u);
    cgs_iface_t g;
    memset (&g, 0, sizeof g);
    assert_int_equal (cgs_iface_find ("127.0.0.1", &g), 0);
    assert_string_equal (g.name, "lo");
    assert_int_equal (g.index, f.index);
    assert_true (g.loopback);
}

static void test_missing_and_invalid (void **state)
{
    (void)state;
    cgs_iface_t f, before;
    memset (&f, 0x5a, sizeof f);
    before = f;
    // TEST-NET-3 (RFC 5737): no host has it on an interface.
    assert_int_equal (cgs_iface_find ("203.0.113.77", &f), -ENODEV);
    assert_int_equal (cgs_iface_find ("cgsnosuch0", &f), -ENODEV);
    assert_int_equal (cgs_iface_find ("", &f), -EINVAL);
    assert_int_equal (cgs_iface_find ("eth 0", &f), -EINVAL);
    assert_int_equal (cgs_iface_find ("averyverylongname", &f), -EINVAL); // 17 > 15
    assert_memory_equal (&f, &before, sizeof f);                           // never written
    assert_true (cgs_iface_name_valid ("enp3s0f1.100"));
    assert_true (cgs_iface_name_valid ("veth0@if3"));
    assert_true (cgs_iface_name_valid ("abcdefghijklmno"));   // 15
    assert_false (cgs_iface_name_valid ("abcdefghijklmnop")); // 16
    assert_false (cgs_iface_name_valid ("eth/0"));
}

static void test_loopback_range (void **state)
{
    (void)state;
    assert_true (cgs_iface_addr_is_loopback (0x7f000001u));
    assert_true (cgs_iface_addr_is_loopback (0x7fffffffu));
    assert_false (cgs_iface_addr_is_loopback (0x80000000u));
    assert_false (cgs_iface_addr_is_loopback (0x7effffffu));
    assert_false (cgs_iface_addr_is_loopback (0xef010203u));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_loopback),
        cmocka_unit_test (test_missing_and_invalid),
        cmocka_unit_test (test_loopback_range),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
