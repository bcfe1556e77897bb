/* test_gw_params — the gateway's parameter file: the defaults are the values
 * deploy/params/gateway.ini documents (read by hand from it, and the shipped
 * file itself loaded), every key read from text, addresses in host order,
 * unicast peers with and without a port, the address bound and the
 * interface each mode takes when none is given, whether a set of parameters
 * sends DIS off this machine (the default never does, the lab's does), and
 * each kind of error naming its file, line, section and key; a refused file
 * leaves the parameters alone. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_config.h"
#include "gw_params.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void s_assert_equal (const gw_params_t *a, const gw_params_t *b)
{
#define S_SAME(f)                                                                                  \
    do {                                                                                           \
        if (a->f != b->f)                                                                          \
            fail_msg ("%s: %.17g != %.17g", #f, (double)a->f, (double)b->f);                       \
    } while (0)
    S_SAME (port);
    S_SAME (mode);
    S_SAME (address);
    S_SAME (bind_address);
    if (strcmp (a->interface, b->interface) != 0)
        fail_msg ("interface: '%s' != '%s'", a->interface, b->interface);
    S_SAME (ttl);
    S_SAME (loopback);
    S_SAME (peer_count);
    for (size_t i = 0; i < a->peer_count && i < GW_PEERS_MAX; i++) {
        S_SAME (peers[i].addr);
        S_SAME (peers[i].port);
    }
    S_SAME (version);
    S_SAME (site);
    S_SAME (application);
    S_SAME (entity_id_base);
    S_SAME (absolute_time);
    S_SAME (route_action_id);
    S_SAME (dis_pcapng);
    S_SAME (position_threshold_m);
    S_SAME (orientation_threshold_deg);
    S_SAME (heartbeat_s);
    S_SAME (timeout_s);
    S_SAME (first_entity_id);
    S_SAME (max_entities);
    S_SAME (publish_rate_hz);
    S_SAME (task_timeout_s);
    S_SAME (s4607_file);
    S_SAME (s4607_truth_tag);
    S_SAME (s4607_classification);
    S_SAME (s4607_platform_rate_hz);
    S_SAME (s4607_mdv_mps);
    S_SAME (cot_protobuf);
    S_SAME (cot_stale_s);
    S_SAME (cot_rate_hz);
    S_SAME (cot_designate);
    S_SAME (cot_designate_type_count);
    const gw_udp_t *ua[2] = {&a->s4607_udp, &a->cot_udp}, *ub[2] = {&b->s4607_udp, &b->cot_udp};
    for (int k = 0; k < 2; k++) {
        if (ua[k]->mode != ub[k]->mode || ua[k]->address != ub[k]->address ||
            ua[k]->port != ub[k]->port || ua[k]->input_port != ub[k]->input_port ||
            ua[k]->bind_address != ub[k]->bind_address || ua[k]->ttl != ub[k]->ttl ||
            ua[k]->loopback != ub[k]->loopback || ua[k]->peer_count != ub[k]->peer_count ||
            strcmp (ua[k]->interface, ub[k]->interface) != 0)
            fail_msg ("%s UDP output differs", k ? "cot" : "stanag4607");
    }
    if (strcmp (a->s4607_nationality, b->s4607_nationality) != 0 ||
        strcmp (a->s4607_class_system, b->s4607_class_system) != 0 ||
        strcmp (a->cot_uid_prefix, b->cot_uid_prefix) != 0 ||
        strcmp (a->cot_designate_uav, b->cot_designate_uav) != 0)
        fail_msg ("a text key differs");
    for (size_t i = 0; i < a->cot_designate_type_count && i < GW_COT_TYPES_MAX; i++)
        if (strcmp (a->cot_designate_types[i], b->cot_designate_types[i]) != 0)
            fail_msg ("designate type %zu: '%s' != '%s'", i, a->cot_designate_types[i],
                      b->cot_designate_types[i]);
#undef S_SAME
}

static void s_load (const char *text, gw_params_t *p)
{
    char err[512] = "";
    if (gw_params_load_string ("g.ini", text, p, err, sizeof err) != 0)
        fail_msg ("load failed: %s", err);
}

// Loading text as "g.ini" fails with -EINVAL, an error that starts with `where`
// ("g.ini:LINE: [section] key") and mentions `word`, and leaves *p alone.
static void s_fails (const char *text, const char *where, const char *word)
{
    gw_params_t p, before;
    gw_params_defaults (&p);
    p.heartbeat_s = 4.5; // not a default: a partial write would show
    before = p;
    char err[512] = "";
    int rc = gw_params_load_string ("g.ini", text, &p, err, sizeof err);
    if (rc != -EINVAL)
        fail_msg ("expected -EINVAL, got %d (%s) for:\n%s", rc, err, text);
    s_assert_equal (&p, &before);
    if (strncmp (err, where, strlen (where)) != 0 || !strstr (err, word))
        fail_msg ("error '%s', want '%s...%s...'", err, where, word);
}

static void test_defaults (void **state)
{
    (void)state;
    gw_params_t p;
    memset (&p, 0x5a, sizeof p);
    gw_params_defaults (&p);
    // As deploy/params/gateway.ini gives them.
    assert_int_equal (p.port, 3000);
    // Multicast to 239.1.2.3 on loopback, TTL 0, bound to the group.
    assert_int_equal (p.mode, GW_MODE_MULTICAST);
    assert_int_equal (p.address, 0xef010203u);
    assert_int_equal (p.bind_address, 0xef010203u);
    assert_string_equal (p.interface, "lo");
    assert_int_equal (p.ttl, 0);
    assert_true (p.loopback);
    assert_int_equal (p.peer_count, 0);
    assert_int_equal (p.version, 7);
    assert_int_equal (p.site, 1);
    assert_int_equal (p.application, 1);
    assert_int_equal (p.entity_id_base, 0);
    assert_true (p.absolute_time);
    assert_int_equal (p.route_action_id, 40);
    assert_false (p.dis_pcapng);
    assert_true (p.position_threshold_m == 1);
    assert_true (p.orientation_threshold_deg == 3);
    assert_true (p.heartbeat_s == 5);
    assert_true (p.timeout_s == 12);
    assert_int_equal (p.first_entity_id, 100000);
    assert_int_equal (p.max_entities, 10000);
    assert_true (p.publish_rate_hz == 10);
    assert_true (p.task_timeout_s == 1);
    assert_string_equal (gw_params_mode_name (GW_MODE_BROADCAST), "broadcast");
    assert_string_equal (gw_params_mode_name (GW_MODE_MULTICAST), "multicast");
    assert_string_equal (gw_params_mode_name (GW_MODE_UNICAST), "unicast");
    // The translators are off until an exercise turns them on; then on
    // loopback with TTL 0.
    assert_false (p.s4607_file);
    assert_int_equal (p.s4607_udp.mode, GW_UDP_OFF);
    assert_int_equal (p.s4607_udp.address, 0xef010204u);
    assert_int_equal (p.s4607_udp.port, 4607);
    assert_string_equal (p.s4607_udp.interface, "lo");
    assert_int_equal (p.s4607_udp.ttl, 0);
    assert_false (p.s4607_truth_tag);
    assert_string_equal (p.s4607_nationality, "XN");
    assert_string_equal (p.s4607_class_system, "XN");
    assert_int_equal (p.s4607_classification, 5);
    assert_true (p.s4607_platform_rate_hz == 1);
    assert_true (p.s4607_mdv_mps == 0.58);
    assert_int_equal (p.cot_udp.mode, GW_UDP_OFF);
    assert_int_equal (p.cot_udp.address, 0xef020301u); // 239.2.3.1
    assert_int_equal (p.cot_udp.port, 6969);
    assert_int_equal (p.cot_udp.input_port, 6969);
    assert_string_equal (p.cot_udp.interface, "lo");
    assert_int_equal (p.cot_udp.ttl, 0);
    assert_false (p.cot_protobuf);
    assert_true (p.cot_stale_s == 15);
    assert_true (p.cot_rate_hz == 1);
    assert_string_equal (p.cot_uid_prefix, "mscgs");
    assert_true (p.cot_designate);
    assert_int_equal (p.cot_designate_type_count, 1);
    assert_string_equal (p.cot_designate_types[0], "b-m-p-s-p-i");
    assert_string_equal (p.cot_designate_uav, "");
}

/* The translators' sections: every key from text, the address bound and
 * whether they leave this machine, and their errors. */
static void test_translators (void **state)
{
    (void)state;
    gw_params_t p;
    gw_params_defaults (&p);
    char err[512] = "";
    const char *text = "[stanag4607]\nfile = yes\nudp = unicast\npeer = 10.1.2.3:5000\n"
                       "peer = 127.0.0.1\nport = 4700\ntruth_tag = yes\nnationality = US\n"
                       "class_system = US\nclassification = 4\nplatform_rate_hz = 2\n"
                       "mdv_mps = 1.5\n"
                       "[cot]\nmode = multicast\naddress = 239.2.3.9\nport = 7000\n"
                       "interface = 127.0.0.1\nttl = 1\nloopback = no\nformat = protobuf\n"
                       "stale_s = 30\nrate_hz = 2\nuid_prefix = lab\ndesignate = no\n"
                       "designate_type = b-m-p-s-p-i\ndesignate_type = b-m-p-w\n"
                       "designate_uav = uav2\n";
    if (gw_params_load_string ("g.ini", text, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_true (p.s4607_file);
    assert_int_equal (p.s4607_udp.mode, GW_UDP_UNICAST);
    assert_int_equal (p.s4607_udp.peer_count, 2);
    assert_int_equal (p.s4607_udp.peers[0].addr, 0x0a010203u);
    assert_int_equal (p.s4607_udp.peers[0].port, 5000);
    assert_int_equal (p.s4607_udp.peers[1].port, 4700); // the section's port
    assert_int_equal (p.s4607_udp.bind_address, 0);     // a peer off this host: every address
    assert_string_equal (p.s4607_udp.interface, "");    // unicast names none unless given
    assert_true (p.s4607_truth_tag);
    assert_string_equal (p.s4607_nationality, "US");
    assert_string_equal (p.s4607_class_system, "US");
    assert_int_equal (p.s4607_classification, 4);
    assert_true (p.s4607_platform_rate_hz == 2);
    assert_true (p.s4607_mdv_mps == 1.5);
    assert_true (gw_params_udp_leaves_host (&p.s4607_udp, false));
    assert_int_equal (p.cot_udp.mode, GW_UDP_MULTICAST);
    assert_int_equal (p.cot_udp.address, 0xef020309u);
    assert_int_equal (p.cot_udp.bind_address, 0xef020309u); // the group
    assert_int_equal (p.cot_udp.port, 7000);
    assert_int_equal (p.cot_udp.input_port, 7000);
    assert_string_equal (p.cot_udp.interface, "127.0.0.1");
    assert_int_equal (p.cot_udp.ttl, 1);
    assert_false (p.cot_udp.loopback);
    assert_true (p.cot_protobuf);
    assert_true (p.cot_stale_s == 30);
    assert_true (p.cot_rate_hz == 2);
    assert_string_equal (p.cot_uid_prefix, "lab");
    assert_false (p.cot_designate);
    assert_int_equal (p.cot_designate_type_count, 2);
    assert_string_equal (p.cot_designate_types[1], "b-m-p-w");
    assert_string_equal (p.cot_designate_uav, "uav2");
    // TTL 1 on an interface that is not loopback leaves; on loopback it stays.
    assert_true (gw_params_udp_leaves_host (&p.cot_udp, false));
    assert_false (gw_params_udp_leaves_host (&p.cot_udp, true));
    char where[160];
    gw_params_describe_udp (&p.cot_udp, where, sizeof where);
    assert_string_equal (where, "multicast to 239.2.3.9:7000 on 127.0.0.1, TTL 1");
    gw_params_describe_udp (&p.s4607_udp, where, sizeof where);
    assert_string_equal (where, "unicast to 10.1.2.3:5000 and 1 more");
    // Unicast CoT to loopback peers hears on 127.0.0.1:input_port.
    gw_params_defaults (&p);
    if (gw_params_load_string ("g.ini",
                               "[cot]\nmode = unicast\npeer = 127.0.0.1:7001\n"
                               "input_port = 7002\n",
                               &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_int_equal (p.cot_udp.bind_address, 0x7f000001u);
    assert_int_equal (p.cot_udp.input_port, 7002);
    assert_int_equal (p.cot_udp.peers[0].port, 7001);
    assert_false (gw_params_udp_leaves_host (&p.cot_udp, false));
    gw_params_describe_udp (&p.s4607_udp, where, sizeof where);
    assert_string_equal (where, "off");
}

// The shipped file names every key but `peer` and `bind` (whose default
// follows the mode: a comment shows it), and gives exactly the defaults.
static void test_shipped_file (void **state)
{
    (void)state;
    static const char *const keys[][2] = {
        {"network", "port"},
        {"network", "mode"},
        {"network", "address"},
        {"network", "interface"},
        {"network", "ttl"},
        {"network", "loopback"},
        {"dis", "version"},
        {"dis", "site"},
        {"dis", "application"},
        {"dis", "entity_id_base"},
        {"dis", "timestamp"},
        {"dis", "route_action_id"},
        {"dis", "pcapng"},
        {"dead_reckoning", "position_threshold_m"},
        {"dead_reckoning", "orientation_threshold_deg"},
        {"dead_reckoning", "heartbeat_s"},
        {"dead_reckoning", "timeout_s"},
        {"external", "first_entity_id"},
        {"external", "max_entities"},
        {"external", "publish_rate_hz"},
        {"external", "task_timeout_s"},
        {"stanag4607", "file"},
        {"stanag4607", "udp"},
        {"stanag4607", "truth_tag"},
        {"stanag4607", "nationality"},
        {"stanag4607", "class_system"},
        {"stanag4607", "classification"},
        {"stanag4607", "platform_rate_hz"},
        {"stanag4607", "mdv_mps"},
        {"cot", "mode"},
        {"cot", "address"},
        {"cot", "port"},
        {"cot", "interface"},
        {"cot", "ttl"},
        {"cot", "format"},
        {"cot", "rate_hz"},
        {"cot", "stale_s"},
        {"cot", "uid_prefix"},
        {"cot", "designate"},
        {"cot", "designate_type"},
    };
    const char *root = getenv ("CGS_ROOT");
    char path[1024], err[512] = "";
    snprintf (path, sizeof path, "%s/deploy/params/gateway.ini", root ? root : ".");
    gw_params_t p, def;
    gw_params_defaults (&def);
    // Loaded over a set that differs in every field, it writes each one back.
    p = def;
    p.port = 4000, p.mode = GW_MODE_MULTICAST, p.address = 0xe0000001u, p.bind_address = 1;
    snprintf (p.interface, sizeof p.interface, "eth9");
    p.ttl = 9, p.loopback = false, p.version = 5, p.site = 2;
    p.application = 3, p.entity_id_base = 10, p.absolute_time = false, p.route_action_id = 1;
    p.dis_pcapng = true;
    p.position_threshold_m = 2, p.orientation_threshold_deg = 4, p.heartbeat_s = 6;
    p.timeout_s = 20, p.first_entity_id = 70000, p.max_entities = 5, p.publish_rate_hz = 2;
    p.task_timeout_s = 3;
    p.s4607_platform_rate_hz = 7, p.s4607_mdv_mps = 3, p.s4607_classification = 1;
    p.cot_stale_s = 99, p.cot_rate_hz = 9, p.cot_udp.port = 1, p.cot_designate = false;
    if (gw_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    // The default exercise writes the 4607 file with truth tags and sends
    // CoT on loopback; every other value is the built-in default.
    def.s4607_file = true;
    def.s4607_truth_tag = true;
    def.cot_udp.mode = GW_UDP_MULTICAST;
    s_assert_equal (&p, &def);
    cgs_config_t *cfg = NULL;
    if (cgs_config_load (path, &cfg, err, sizeof err) != 0)
        fail_msg ("%s", err);
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (!cgs_config_has (cfg, keys[i][0], keys[i][1]))
            fail_msg ("%s has no [%s] %s", path, keys[i][0], keys[i][1]);
    assert_int_equal (cgs_config_section_count (cfg), 6);
    cgs_config_destroy (&cfg);
}

static void test_values (void **state)
{
    (void)state;
    gw_params_t p;
    gw_params_defaults (&p);
    s_load ("[network]\n"
            "port = 3001\n"
            "mode = unicast\n"
            "bind = 10.0.0.5\n"
            "ttl = 4\n"
            "loopback = no\n"
            "peer = 192.168.1.10\n"
            "peer = 10.0.0.2:3100\n"
            "[dis]\n"
            "version = 6\n"
            "site = 17\n"
            "application = 23\n"
            "entity_id_base = 1000\n"
            "timestamp = relative\n"
            "route_action_id = 4294967295\n"
            "pcapng = yes\n"
            "[dead_reckoning]\n"
            "position_threshold_m = 0.5\n"
            "orientation_threshold_deg = 2.5\n"
            "heartbeat_s = 10\n"
            "timeout_s = 24\n"
            "[external]\n"
            "first_entity_id = 200000\n"
            "max_entities = 50\n"
            "publish_rate_hz = 5\n"
            "task_timeout_s = 2\n",
            &p);
    gw_params_t want;
    gw_params_defaults (&want);
    want.port = 3001, want.mode = GW_MODE_UNICAST, want.bind_address = 0x0a000005u;
    want.interface[0] = '\0'; // unicast: none unless given
    want.ttl = 4, want.loopback = false;
    want.peer_count = 2;
    want.peers[0] = (gw_peer_t){0xc0a8010au, 3001}; // no port: the file's port
    want.peers[1] = (gw_peer_t){0x0a000002u, 3100};
    want.version = 6, want.site = 17, want.application = 23, want.entity_id_base = 1000;
    want.absolute_time = false, want.route_action_id = 4294967295L, want.dis_pcapng = true;
    want.position_threshold_m = 0.5, want.orientation_threshold_deg = 2.5;
    want.heartbeat_s = 10, want.timeout_s = 24;
    want.first_entity_id = 200000, want.max_entities = 50, want.publish_rate_hz = 5;
    want.task_timeout_s = 2;
    s_assert_equal (&p, &want);
    // Multicast without an address: the documented group 239.1.2.3.
    gw_params_defaults (&p);
    s_load ("[network]\nmode = multicast\ninterface = 192.168.7.1\n", &p);
    assert_int_equal (p.mode, GW_MODE_MULTICAST);
    assert_int_equal (p.address, 0xef010203u);
    assert_string_equal (p.interface, "192.168.7.1");
    gw_params_defaults (&p);
    s_load ("[network]\nmode = multicast\naddress = 224.0.0.1\n", &p);
    assert_int_equal (p.address, 0xe0000001u);
    gw_params_defaults (&p);
    s_load ("[network]\nmode = broadcast\naddress = 192.168.1.255\n", &p);
    assert_int_equal (p.mode, GW_MODE_BROADCAST);
    assert_int_equal (p.address, 0xc0a801ffu);
}

// What each mode takes when a key is not given: the address (a group for
// multicast, 255.255.255.255 for broadcast), the address bound (only what
// the mode's peers send to), the interface (loopback, none for unicast).
static void test_mode_defaults (void **state)
{
    (void)state;
    gw_params_t p;
    gw_params_defaults (&p);
    s_load ("[network]\nmode = broadcast\n", &p);
    assert_int_equal (p.address, 0xffffffffu);
    assert_int_equal (p.bind_address, 0);
    assert_string_equal (p.interface, "lo");
    gw_params_defaults (&p);
    s_load ("[network]\nmode = multicast\naddress = 239.9.9.9\ninterface = eth1\n", &p);
    assert_int_equal (p.bind_address, 0xef090909u); // the group
    assert_string_equal (p.interface, "eth1");
    gw_params_defaults (&p);
    s_load ("[network]\nmode = unicast\npeer = 127.0.0.1:3001\npeer = 127.0.0.2\n", &p);
    assert_int_equal (p.bind_address, 0x7f000001u); // loopback peers only: loopback
    assert_string_equal (p.interface, "");
    gw_params_defaults (&p);
    s_load ("[network]\nmode = unicast\npeer = 127.0.0.1\npeer = 10.0.0.2\n", &p);
    assert_int_equal (p.bind_address, 0);
    gw_params_defaults (&p);
    s_load ("[network]\nmode = unicast\npeer = 10.0.0.2\ninterface = eth0\nbind = 10.0.0.1\n", &p);
    assert_string_equal (p.interface, "eth0");
    assert_int_equal (p.bind_address, 0x0a000001u);
    gw_params_defaults (&p);
    s_load ("[network]\ninterface = 0.0.0.0\n", &p); // the routing table's choice
    assert_string_equal (p.interface, "");
    gw_params_defaults (&p);
    s_load ("[network]\ninterface = enp3s0f1.100\n", &p);
    assert_string_equal (p.interface, "enp3s0f1.100");
}

// Whether DIS can leave this machine, for every mode, against the rule the
// header states; and the words that say where it goes.
static void test_leaves_host (void **state)
{
    (void)state;
    static const struct {
        const char *text;  // the [network] section
        bool loopback_if;  // whether its interface is a loopback one
        bool leaves;       // expected
        const char *where; // expected description
    } cases[] = {
        {"", true, false, "multicast to 239.1.2.3:3000 on lo, TTL 0"},
        {"ttl = 1\n", true, false, "multicast to 239.1.2.3:3000 on lo, TTL 1"},
        {"interface = eth0\n", false, false, "multicast to 239.1.2.3:3000 on eth0, TTL 0"},
        {"interface = eth0\nttl = 1\n", false, true, "multicast to 239.1.2.3:3000 on eth0, TTL 1"},
        {"interface = 0.0.0.0\nttl = 2\n", false, true,
         "multicast to 239.1.2.3:3000 on the routing table's interface, TTL 2"},
        {"mode = broadcast\n", true, false, "broadcast to 255.255.255.255:3000 on lo"},
        {"mode = broadcast\ninterface = eth0\n", false, true,
         "broadcast to 255.255.255.255:3000 on eth0"},
        {"mode = broadcast\ninterface = 0.0.0.0\naddress = 127.255.255.255\n", false, false,
         "broadcast to 127.255.255.255:3000 on the routing table's interface"},
        {"mode = unicast\npeer = 127.0.0.1:4000\n", false, false, "unicast to 127.0.0.1:4000"},
        {"mode = unicast\npeer = 127.0.0.1\npeer = 10.1.1.1\npeer = 10.1.1.2\n", false, true,
         "unicast to 127.0.0.1:3000 and 2 more"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[256], where[160];
        snprintf (text, sizeof text, "[network]\n%s", cases[i].text);
        gw_params_t p;
        gw_params_defaults (&p);
        s_load (text, &p);
        gw_params_describe (&p, where, sizeof where);
        if (strcmp (where, cases[i].where) != 0)
            fail_msg ("case %zu: '%s', want '%s'", i, where, cases[i].where);
        if (gw_params_leaves_host (&p, cases[i].loopback_if) != cases[i].leaves)
            fail_msg ("case %zu (%s): leaves_host should be %d", i, where, cases[i].leaves);
    }
    // A short buffer is cut and terminated.
    gw_params_t p;
    gw_params_defaults (&p);
    char small[10];
    gw_params_describe (&p, small, sizeof small);
    assert_string_equal (small, "multicast");
}

// The lab exercise's parameters broadcast on the interface they name, so
// they leave the machine; every other key keeps its default.
static void test_lab_file (void **state)
{
    (void)state;
    const char *root = getenv ("CGS_ROOT");
    char path[1024], err[512] = "";
    snprintf (path, sizeof path, "%s/deploy/params/gateway-lab.ini", root ? root : ".");
    gw_params_t p, want;
    gw_params_defaults (&p);
    if (gw_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    gw_params_defaults (&want);
    want.mode = GW_MODE_BROADCAST;
    want.address = 0xffffffffu;
    want.bind_address = 0;
    snprintf (want.interface, sizeof want.interface, "eth0");
    s_assert_equal (&p, &want);
    assert_true (gw_params_leaves_host (&p, false));
}

static void test_errors (void **state)
{
    (void)state;
    s_fails ("[network]\nport = 3000\nspeed = 9\n", "g.ini:3: [network]", "speed");
    s_fails ("[dis]\nversion = 2\n", "g.ini:2: [dis] version", "2");
    s_fails ("[dis]\n\nversion = 8\n", "g.ini:3: [dis] version", "8");
    s_fails ("[network]\nport = 0\n", "g.ini:2: [network] port", "0");
    s_fails ("[network]\nport = 65536\n", "g.ini:2: [network] port", "65536");
    s_fails ("[network]\nmode = unicast\n", "g.ini:2: [network] mode", "peer");
    s_fails ("[network]\nmode = unicast\npeer = 10.0.0.1\npeer = 1.2.3:99999\n",
             "g.ini:4: [network] peer", "1.2.3:99999");
    s_fails ("[network]\nmode = unicast\npeer = 1.2.3:3000\n", "g.ini:3: [network] peer",
             "1.2.3:3000");
    s_fails ("[network]\nmode = unicast\npeer = 10.0.0.1:\n", "g.ini:3: [network] peer",
             "10.0.0.1:");
    s_fails ("[network]\nmode = multicast\naddress = 10.1.2.3\n", "g.ini:3: [network] address",
             "224.0.0.0/4");
    s_fails ("[network]\naddress = 300.1.2.3\n", "g.ini:2: [network] address", "300.1.2.3");
    s_fails ("[network]\npeer = 10.0.0.1\n", "g.ini:2: [network] peer", "unicast");
    s_fails ("[network]\nmode = anycast\n", "g.ini:2: [network] mode", "anycast");
    s_fails ("[dead_reckoning]\nheartbeat_s = 6\ntimeout_s = 6\n",
             "g.ini:3: [dead_reckoning] timeout_s", "heartbeat_s");
    s_fails ("[dead_reckoning]\ntimeout_s = 4\n", "g.ini:2: [dead_reckoning] timeout_s",
             "heartbeat_s");
    s_fails ("[dis]\ntimestamp = sometimes\n", "g.ini:2: [dis] timestamp", "sometimes");
    s_fails ("[external]\nfirst_entity_id = 65534\n", "g.ini:2: [external] first_entity_id",
             "65534");
    s_fails ("[dis]\nsite = 1\nsite = 2\n", "g.ini:3: [dis] site", "twice");
    s_fails ("[network]\ninterface = eth 0\n", "g.ini:2: [network] interface", "eth 0");
    s_fails ("[network]\ninterface = averyverylongname\n", "g.ini:2: [network] interface",
             "ip -br link");
    s_fails ("[network]\ninterface = eth/0\n", "g.ini:2: [network] interface", "eth/0");
    s_fails ("[dis]\napplication = 300\n[stanag4607]\ntruth_tag = yes\n",
             "g.ini:4: [stanag4607] truth_tag", "300");
    s_fails ("[stanag4607]\nudp = sometimes\n", "g.ini:2: [stanag4607] udp", "sometimes");
    s_fails ("[stanag4607]\nudp = unicast\n", "g.ini:2: [stanag4607] udp", "peer");
    s_fails ("[stanag4607]\nnationality = USA\n", "g.ini:2: [stanag4607] nationality", "USA");
    s_fails ("[stanag4607]\nclassification = 6\n", "g.ini:2: [stanag4607] classification", "6");
    s_fails ("[stanag4607]\nmdv_mps = -1\n", "g.ini:2: [stanag4607] mdv_mps", "-1");
    s_fails ("[cot]\nmode = multicast\naddress = 10.0.0.1\n", "g.ini:3: [cot] address",
             "224.0.0.0/4");
    s_fails ("[cot]\npeer = 127.0.0.1\n", "g.ini:2: [cot] peer", "unicast");
    s_fails ("[cot]\nformat = json\n", "g.ini:2: [cot] format", "json");
    s_fails ("[cot]\nrate_hz = 0\n", "g.ini:2: [cot] rate_hz", "0");
    s_fails ("[cot]\ndesignate_type = b m p\n", "g.ini:2: [cot] designate_type", "b m p");
    s_fails ("[cot]\nuid_prefix = a\"b\n", "g.ini:2: [cot] uid_prefix", "a\"b");
    s_fails ("[cot]\ninterface = eth 0\n", "g.ini:2: [cot] interface", "eth 0");
    // Seventeen peers: one too many, named at the seventeenth.
    char text[1024] = "[network]\nmode = unicast\n";
    for (int i = 1; i <= GW_PEERS_MAX + 1; i++) {
        size_t n = strlen (text);
        snprintf (text + n, sizeof text - n, "peer = 10.0.0.%d\n", i);
    }
    s_fails (text, "g.ini:19: [network] peer", "16");
    // A missing file is named.
    gw_params_t p;
    gw_params_defaults (&p);
    char err[512] = "";
    assert_true (gw_params_load ("/nonexistent/gateway.ini", &p, err, sizeof err) < 0);
    assert_non_null (strstr (err, "/nonexistent/gateway.ini"));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_defaults),    cmocka_unit_test (test_shipped_file),
        cmocka_unit_test (test_values),      cmocka_unit_test (test_mode_defaults),
        cmocka_unit_test (test_leaves_host), cmocka_unit_test (test_lab_file),
        cmocka_unit_test (test_errors),      cmocka_unit_test (test_translators),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
