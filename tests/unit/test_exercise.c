/* Unit tests of cgs_exercise: the default exercise file, defaults, paths,
 * publishers of a topic, and every kind of rejected file. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_exercise.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct {
    char dir[64];   // a fresh temporary folder
    char path[128]; // dir/ex.ini
} s_tmp_t;

static int s_setup (void **state)
{
    s_tmp_t *t = calloc (1, sizeof *t);
    if (!t)
        return -1;
    snprintf (t->dir, sizeof t->dir, "/tmp/test_exercise.XXXXXX");
    if (!mkdtemp (t->dir)) {
        free (t);
        return -1;
    }
    snprintf (t->path, sizeof t->path, "%s/ex.ini", t->dir);
    *state = t;
    return 0;
}

static int s_teardown (void **state)
{
    s_tmp_t *t = *state;
    unlink (t->path);
    rmdir (t->dir);
    free (t);
    return 0;
}

// Write text to the temporary exercise file and load it.
static int s_load (s_tmp_t *t, const char *text, cgs_exercise_t **ret, char *err, size_t errlen)
{
    FILE *f = fopen (t->path, "w");
    assert_non_null (f);
    fputs (text, f);
    fclose (f);
    return cgs_exercise_load (t->path, ret, err, errlen);
}

// Loading text fails with -EINVAL and the message "<path>:" followed by expected.
static void s_load_fails (s_tmp_t *t, const char *text, const char *expected)
{
    char err[512] = "", want[512];
    cgs_exercise_t *ex = NULL;
    assert_int_equal (s_load (t, text, &ex, err, sizeof err), -EINVAL);
    assert_null (ex);
    snprintf (want, sizeof want, "%s%s", t->path, expected);
    assert_string_equal (err, want);
}

#define S_HEAD "[exercise]\norigin = geo 35.96 -121.23 0\n"

// The working directory joined with a relative path, as a runtime location is resolved.
static void s_from_cwd (const char *rel, char *buf, size_t size)
{
    char *cwd = getcwd (NULL, 0);
    assert_non_null (cwd);
    snprintf (buf, size, "%s%s%s", cwd, strcmp (cwd, "/") == 0 ? "" : "/", rel);
    free (cwd);
}

static void test_default_exercise (void **state)
{
    (void)state;
    const char *root = getenv ("CGS_ROOT");
    char path[1024], want[1100];
    snprintf (path, sizeof path, "%s/deploy/exercises/default.ini", root ? root : ".");
    char err[512] = "";
    cgs_exercise_t *ex = NULL;
    int rc = cgs_exercise_load (path, &ex, err, sizeof err);
    if (rc != 0)
        fail_msg ("%s", err);
    assert_string_equal (cgs_exercise_path (ex), path);
    assert_string_equal (cgs_exercise_name (ex), "default");
    assert_int_equal (cgs_exercise_id (ex), 1);
    cgs_geodetic_t o = cgs_exercise_origin (ex);
    assert_true (o.lat_deg > 35.9 && o.lat_deg < 36.0); // Fort Hunter Liggett
    assert_true (o.lon_deg > -121.3 && o.lon_deg < -121.2);
    assert_true (cgs_exercise_time_scale (ex) == 1.0);
    assert_true (cgs_exercise_seed (ex) == 1);
    s_from_cwd ("state", want, sizeof want);
    assert_string_equal (cgs_exercise_state_dir (ex), want);
    // relative to the exercise file, absolute, and not required to exist
    const char *scenario = cgs_exercise_scenario (ex);
    assert_true (scenario[0] == '/');
    const char *tail = "deploy/exercises/../scenarios/default.ini";
    assert_true (strlen (scenario) > strlen (tail));
    assert_string_equal (scenario + strlen (scenario) - strlen (tail), tail);
    assert_non_null (cgs_exercise_config (ex));

    const char *names[] = {"uavsim",    "mtid.uav1",    "bcisd.uav1", "trackerd",
                           "guidanced", "imagerd.uav1", "gateway",    "stationd"};
    const char *programs[] = {"uavsim",    "mtid",    "bcisd",   "trackerd",
                              "guidanced", "imagerd", "gateway", "stationd"};
    assert_int_equal (cgs_exercise_instance_count (ex), 8);
    for (size_t i = 0; i < 8; i++) {
        const cgs_instance_t *inst = cgs_exercise_instance (ex, i);
        assert_non_null (inst);
        assert_string_equal (inst->name, names[i]);
        assert_string_equal (inst->program, programs[i]);
        assert_ptr_equal (cgs_exercise_find (ex, names[i]), inst);
        snprintf (want, sizeof want, "ipc:///tmp/mscgs/%s.pub", names[i]);
        assert_string_equal (inst->publish, want);
        bool commands = strcmp (names[i], "uavsim") == 0 || strcmp (names[i], "guidanced") == 0 ||
                        strcmp (names[i], "imagerd.uav1") == 0;
        snprintf (want, sizeof want, "ipc:///tmp/mscgs/%s.cmd", names[i]);
        assert_string_equal (inst->command, commands ? want : "");
        assert_string_equal (inst->uav, strstr (names[i], ".uav1") ? "uav1" : "");
        assert_string_equal (inst->host, "localhost");
        const char *file = strcmp (names[i], "trackerd") == 0       ? "tracker.ini"
                           : strcmp (names[i], "guidanced") == 0    ? "guidance.ini"
                           : strcmp (names[i], "imagerd.uav1") == 0 ? "imager.ini"
                           : strcmp (names[i], "gateway") == 0      ? "gateway.ini"
                           : strcmp (names[i], "stationd") == 0     ? "station.ini"
                                                                    : NULL;
        if (file) { // relative to the exercise file
            char p[64];
            snprintf (p, sizeof p, "deploy/exercises/../params/%s", file);
            assert_true (strlen (inst->params) > strlen (p));
            assert_string_equal (inst->params + strlen (inst->params) - strlen (p), p);
        } else {
            assert_string_equal (inst->params, "");
        }
        assert_string_equal (inst->public_key, "");
        assert_true (inst->enabled);
    }
    assert_null (cgs_exercise_instance (ex, 8));
    assert_null (cgs_exercise_find (ex, "mtid.uav2"));

    const cgs_instance_t *pubs[16];
    assert_int_equal (cgs_exercise_publishers_of (ex, "mti", pubs, 16), 1);
    assert_string_equal (pubs[0]->name, "mtid.uav1");
    assert_int_equal (cgs_exercise_publishers_of (ex, "health", pubs, 16), 8);
    for (size_t i = 0; i < 8; i++)
        assert_string_equal (pubs[i]->name, names[i]);
    assert_int_equal (cgs_exercise_publishers_of (ex, "entity", pubs, 16), 2);
    assert_string_equal (pubs[0]->name, "uavsim");
    assert_string_equal (pubs[1]->name, "gateway");
    assert_int_equal (cgs_exercise_publishers_of (ex, "intercept", pubs, 16), 1);
    assert_string_equal (pubs[0]->name, "guidanced");
    assert_int_equal (cgs_exercise_publishers_of (ex, "no.such.topic", pubs, 16), 0);
    // more than max: counted, not written past max
    pubs[2] = NULL;
    assert_int_equal (cgs_exercise_publishers_of (ex, "health", pubs, 2), 8);
    assert_null (pubs[2]);
    assert_int_equal (cgs_exercise_publishers_of (ex, "health", NULL, 0), 8);

    cgs_exercise_destroy (&ex);
    assert_null (ex);
    cgs_exercise_destroy (&ex);
    cgs_exercise_destroy (NULL);
}

static void test_defaults (void **state)
{
    s_tmp_t *t = *state;
    char err[512] = "";
    cgs_exercise_t *ex = NULL;
    if (s_load (t, S_HEAD "[service trackerd]\npublish = inproc://t\n", &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_string_equal (cgs_exercise_name (ex), "ex");
    assert_int_equal (cgs_exercise_id (ex), 1);
    assert_true (cgs_exercise_time_scale (ex) == 1.0);
    assert_true (cgs_exercise_seed (ex) == 1);
    assert_string_equal (cgs_exercise_scenario (ex), "");
    assert_int_equal (cgs_exercise_instance_count (ex), 1);
    const cgs_instance_t *inst = cgs_exercise_instance (ex, 0);
    assert_string_equal (inst->name, "trackerd");
    assert_string_equal (inst->program, "trackerd");
    assert_string_equal (inst->publish, "inproc://t");
    assert_string_equal (inst->command, "");
    assert_string_equal (inst->host, "localhost");
    assert_true (inst->enabled);
    assert_int_equal (cgs_exercise_publishers_of (ex, "track", NULL, 0), 1);
    cgs_exercise_destroy (&ex);
}

static void test_every_key (void **state)
{
    s_tmp_t *t = *state;
    char err[512] = "", want[512];
    cgs_exercise_t *ex = NULL;
    const char *key = "rq{B)6.gA?0xZ5&pv:PKj&SDT$p<@-W^M?y5x8xP"; // 40 Z85 characters
    char text[2048];
    snprintf (text, sizeof text,
              "[exercise]\n"
              "id = 255\n"
              "name = lab-test\n"
              "origin = 35.96N 121.23W 250\n"
              "time_scale = 20\n"
              "seed = 12345678901234567890\n"
              "state_dir = /var/lib/mscgs\n"
              "scenario = scenarios/hills.ini\n"
              "\n"
              "[service mtid.uav2]\n"
              "program = mtid_debug\n"
              "publish = tcp://10.0.0.5:6001\n"
              "command = inproc://mtid2\n"
              "host = lab-b\n"
              "uav = uav2\n"
              "params = params/mti.ini\n"
              "public_key = %s\n"
              "secret_key_file = /etc/mscgs/mtid.uav2.key\n"
              "enabled = no\n"
              "\n"
              "[curve]\n"
              "allow = %s\n",
              key, key);
    if (s_load (t, text, &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_int_equal (cgs_exercise_id (ex), 255);
    assert_string_equal (cgs_exercise_name (ex), "lab-test");
    cgs_geodetic_t o = cgs_exercise_origin (ex);
    assert_true (o.lat_deg == 35.96 && o.lon_deg == -121.23 && o.height_m == 250);
    assert_true (cgs_exercise_time_scale (ex) == 20);
    assert_true (cgs_exercise_seed (ex) == 12345678901234567890ull);
    assert_string_equal (cgs_exercise_state_dir (ex), "/var/lib/mscgs");
    snprintf (want, sizeof want, "%s/scenarios/hills.ini", t->dir);
    assert_string_equal (cgs_exercise_scenario (ex), want);
    const cgs_instance_t *inst = cgs_exercise_find (ex, "mtid.uav2");
    assert_non_null (inst);
    assert_string_equal (inst->program, "mtid_debug");
    assert_string_equal (inst->publish, "tcp://10.0.0.5:6001");
    assert_string_equal (inst->command, "inproc://mtid2");
    assert_string_equal (inst->host, "lab-b");
    assert_string_equal (inst->uav, "uav2");
    snprintf (want, sizeof want, "%s/params/mti.ini", t->dir);
    assert_string_equal (inst->params, want);
    assert_string_equal (inst->public_key, key);
    assert_string_equal (inst->secret_key_file, "/etc/mscgs/mtid.uav2.key");
    assert_false (inst->enabled);
    // the program, not the instance name, decides what it publishes
    assert_int_equal (cgs_exercise_publishers_of (ex, "mti", NULL, 0), 0);
    assert_int_equal (cgs_exercise_publishers_of (ex, "health", NULL, 0), 1);
    assert_string_equal (cgs_config_get_nth (cgs_exercise_config (ex), "curve", "allow", 0), key);
    assert_string_equal (cgs_exercise_allowed (ex, 0), key);
    cgs_exercise_destroy (&ex);

    // a relative state_dir is taken from the working directory
    if (s_load (t, S_HEAD "state_dir = run/state\n", &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    s_from_cwd ("run/state", want, sizeof want);
    assert_string_equal (cgs_exercise_state_dir (ex), want);
    cgs_exercise_destroy (&ex);
}

static void test_duplicate_endpoint (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t,
                  S_HEAD "\n"
                         "[service a]\n"
                         "publish = ipc:///tmp/x.pub\n"
                         "\n"
                         "[service b]\n"
                         "command = ipc:///tmp/b.cmd\n"
                         "publish = ipc:///tmp/x.pub\n",
                  ":9: [service b] publish: endpoint 'ipc:///tmp/x.pub' is already used by "
                  "[service a] publish at line 5");
    // publish against command, and within one instance
    s_load_fails (t,
                  S_HEAD "[service a]\n"
                         "command = tcp://127.0.0.1:7000\n"
                         "publish = inproc://pa\n"
                         "[service b]\n"
                         "publish = tcp://127.0.0.1:7000\n",
                  ":7: [service b] publish: endpoint 'tcp://127.0.0.1:7000' is already used by "
                  "[service a] command at line 4");
    s_load_fails (t,
                  S_HEAD "[service a]\n"
                         "publish = inproc://a\n"
                         "command = inproc://a\n",
                  ":5: [service a] command: endpoint 'inproc://a' is already used by [service a] "
                  "publish at line 4");
    // a service named twice merges, so its keys are given twice
    s_load_fails (t,
                  S_HEAD "[service a]\n"
                         "publish = inproc://a\n"
                         "[service a]\n"
                         "publish = inproc://b\n",
                  ":6: [service a] publish: given twice (first at line 4)");
}

static void test_bad_endpoint (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t, S_HEAD "[service a]\npublish = udp://1.2.3.4:5\n",
                  ":4: [service a] publish: expected an endpoint starting with tcp://, ipc:// or "
                  "inproc://, got 'udp://1.2.3.4:5'");
    s_load_fails (t, S_HEAD "[service a]\ncommand = tcp://\n",
                  ":4: [service a] command: expected an endpoint starting with tcp://, ipc:// or "
                  "inproc://, got 'tcp://'");
    s_load_fails (t, S_HEAD "[service a]\ncommand = /tmp/a.cmd\n",
                  ":4: [service a] command: expected an endpoint starting with tcp://, ipc:// or "
                  "inproc://, got '/tmp/a.cmd'");
}

static void test_origin (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t, "[exercise]\nid = 2\n[service a]\n",
                  ": [exercise]: missing key 'origin' (expected the exercise origin, e.g. "
                  "`origin = geo 35.96 -121.23 0`)");
    s_load_fails (t, "[service a]\n",
                  ": [exercise]: missing key 'origin' (expected the exercise origin, e.g. "
                  "`origin = geo 35.96 -121.23 0`)");
    s_load_fails (t, "[exercise]\norigin = 1200 -350\n",
                  ":2: [exercise] origin: expected a geodetic position as `geo LAT LON [H]`, "
                  "`LAT{N|S} LON{E|W} [H]` or `mgrs GRID` (local metres have no meaning here), "
                  "got '1200 -350'");
    s_load_fails (t, "[exercise]\norigin = geo 91 0\n",
                  ":2: [exercise] origin: latitude 91 is outside [-90, 90] in 'geo 91 0'");

    // MGRS works too
    char err[512] = "";
    cgs_exercise_t *ex = NULL;
    if (s_load (t, "[exercise]\norigin = mgrs 10SFF 00000 00000\n", &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    cgs_geodetic_t o = cgs_exercise_origin (ex);
    assert_true (o.lat_deg > 35 && o.lat_deg < 37 && o.height_m == 0);
    cgs_exercise_destroy (&ex);
}

static void test_bad_values (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t, S_HEAD "id = 0\n",
                  ":3: [exercise] id: expected an integer in [1, 255], got '0'");
    s_load_fails (t, S_HEAD "time_scale = 0\n",
                  ":3: [exercise] time_scale: expected a number in (0, 1000], got '0'");
    s_load_fails (t, S_HEAD "time_scale = 2000\n",
                  ":3: [exercise] time_scale: expected a number in [0, 1000], got '2000'");
    s_load_fails (t, S_HEAD "seed = -1\n",
                  ":3: [exercise] seed: expected an integer in [0, 18446744073709551615], got "
                  "'-1'");
    s_load_fails (t, S_HEAD "state_dir =\n",
                  ":3: [exercise] state_dir: expected a directory, got ''");
    s_load_fails (t, S_HEAD "[service a]\nenabled = perhaps\n",
                  ":4: [service a] enabled: expected true/false, yes/no, on/off or 1/0, got "
                  "'perhaps'");
    s_load_fails (t, S_HEAD "[service a]\npublic_key = short\n",
                  ":4: [service a] public_key: expected a CURVE public key of 40 Z85 characters, "
                  "got 'short'");
    s_load_fails (t, S_HEAD "[service a]\nuav = uav 1\n",
                  ":4: [service a] uav: expected a name of at most 63 letters, digits, '.', '-' "
                  "or '_', got 'uav 1'");
    s_load_fails (t, S_HEAD "[service a]\nprogram = mtid.x\n",
                  ":4: [service a] program: expected a name of at most 63 letters, digits, '-' "
                  "or '_', got 'mtid.x'");
}

static void test_bad_instance_name (void **state)
{
    s_tmp_t *t = *state;
    const char *why = " expected [service NAME] with NAME an instance name of at most 63 "
                      "letters, digits, '.', '-' or '_', e.g. [service mtid.uav1]";
    char want[512];
    snprintf (want, sizeof want, ":3: [service]%s", why);
    s_load_fails (t, S_HEAD "[service]\npublish = inproc://a\n", want);
    snprintf (want, sizeof want, ":3: [service mtid/uav1]%s", why);
    s_load_fails (t, S_HEAD "[service mtid/uav1]\n", want);
    snprintf (want, sizeof want, ":3: [service .uav1]%s", why);
    s_load_fails (t, S_HEAD "[service .uav1]\n", want);
    char text[512], name[80];
    memset (name, 'x', 64);
    name[64] = '\0';
    snprintf (text, sizeof text, S_HEAD "[service %s]\n", name);
    snprintf (want, sizeof want, ":3: [service %s]%s", name, why);
    s_load_fails (t, text, want);
    // 63 characters is fine
    name[63] = '\0';
    snprintf (text, sizeof text, S_HEAD "[service %s]\npublish = inproc://x\n", name);
    char err[512] = "";
    cgs_exercise_t *ex = NULL;
    if (s_load (t, text, &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_string_equal (cgs_exercise_instance (ex, 0)->name, name);
    cgs_exercise_destroy (&ex);
}

static void test_curve (void **state)
{
    s_tmp_t *t = *state;
#define S_K1 "rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7"
#define S_K2 "Yne@$w-vo<fVvi]a<NY6T1ed:M$fCG*[IaLV{hID"
#define S_A  "[service a]\npublish = inproc://a\n"
    // Without keys or [curve]: no CURVE.
    cgs_exercise_t *ex = NULL;
    char err[512] = "";
    assert_int_equal (s_load (t, S_HEAD S_A, &ex, err, sizeof err), 0);
    assert_false (cgs_exercise_uses_curve (ex));
    assert_ptr_equal (cgs_exercise_first_of (ex, "a"), cgs_exercise_find (ex, "a"));
    assert_null (cgs_exercise_first_of (ex, "b"));
    cgs_exercise_destroy (&ex);
    // Keys everywhere: the tools' pair and the allowed keys are read.
    assert_int_equal (s_load (t,
                              S_HEAD "[curve]\nclient_public_key = " S_K2
                                     "\nclient_secret_key_file = ops.key\nallow = " S_K1
                                     "\nallow = " S_K2 "\n" S_A "public_key = " S_K1
                                     "\nsecret_key_file = a.key\n",
                              &ex, err, sizeof err),
                      0);
    assert_true (cgs_exercise_uses_curve (ex));
    assert_string_equal (cgs_exercise_client_public_key (ex), S_K2);
    const char *f = cgs_exercise_client_secret_key_file (ex);
    assert_true (f[0] == '/' && strstr (f, "/ops.key")); // relative to the file, made absolute
    assert_int_equal (cgs_exercise_allowed_count (ex), 2);
    assert_string_equal (cgs_exercise_allowed (ex, 1), S_K2);
    assert_null (cgs_exercise_allowed (ex, 2));
    cgs_exercise_destroy (&ex);
    // A key on one instance makes CURVE the rule: the other needs its pair.
    s_load_fails (t,
                  S_HEAD S_A "public_key = " S_K1
                             "\nsecret_key_file = a.key\n[service b]\npublish = inproc://b\n",
                  ":7: [service b] has no public_key, but the exercise uses CURVE (every instance "
                  "needs a key pair: mscgs keygen)");
    s_load_fails (t, S_HEAD S_A "public_key = " S_K1 "\n",
                  ":3: [service a] has no secret_key_file, but the exercise uses CURVE (every "
                  "instance needs a key pair: mscgs keygen)");
    // [curve] alone (an empty one too) turns CURVE on.
    s_load_fails (t, S_HEAD "[curve]\n" S_A,
                  ":4: [service a] has no public_key, but the exercise uses CURVE (every instance "
                  "needs a key pair: mscgs keygen)");
    // Its keys are checked, and its unknown keys refused.
    s_load_fails (
        t, S_HEAD "[curve]\nallow = notakey\n" S_A,
        ":4: [curve] allow: expected a CURVE public key of 40 Z85 characters, got 'notakey'");
    s_load_fails (t, S_HEAD "[curve]\nclient_public_key = " S_K2 "\n" S_A,
                  ":4: [curve] client_public_key: give client_public_key and "
                  "client_secret_key_file together");
    s_load_fails (t,
                  S_HEAD "[curve]\nalow = " S_K1 "\n" S_A "public_key = " S_K1
                         "\nsecret_key_file = a.key\n",
                  ":4: [curve] unknown key 'alow'");
#undef S_K1
#undef S_K2
#undef S_A
}

static void test_unknown (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t, S_HEAD "[service a]\ncommand = inproc://c\n",
                  ":3: [service a] missing key 'publish' (expected an endpoint starting with "
                  "tcp://, ipc:// or inproc://: every service publishes its health)");
    s_load_fails (t, S_HEAD "[service a]\npublish = inproc://a\npublsh = inproc://b\n",
                  ":5: [service a] unknown key 'publsh'");
    s_load_fails (t, S_HEAD "colour = red\n[service a]\npublish = inproc://a\n",
                  ":3: [exercise] unknown key 'colour'");
    s_load_fails (t, S_HEAD "[services a]\npublish = inproc://a\n",
                  ":3: unknown section [services a]");
    s_load_fails (t, "top = 1\n" S_HEAD, ":1: unknown key 'top' (before any section)");
    s_load_fails (t, S_HEAD "[service a]\nno equals sign\n",
                  ":4: syntax error (expected `key = value` or `[section]`)");

    char err[512] = "", want[512];
    cgs_exercise_t *ex = (cgs_exercise_t *)0x1;
    snprintf (want, sizeof want, "%s/none.ini", t->dir);
    assert_int_equal (cgs_exercise_load (want, &ex, err, sizeof err), -ENOENT);
    assert_ptr_equal (ex, (cgs_exercise_t *)0x1);
    strcat (want, ": No such file or directory");
    assert_string_equal (err, want);
}

/* [bus] transport = epgm: every publisher gets group + k and port + k,
 * except one that gives its own endpoint (not counted in k) and one that
 * says `multicast = no`; the interface is [bus]'s unless the instance gives
 * one. A subscriber on another host reaches a publisher over multicast on
 * its own interface; on the same host, and a tool, over `publish`. */
static void test_bus_multicast (void **state)
{
    s_tmp_t *t = *state;
    cgs_exercise_t *ex = NULL;
    char err[512] = "";
    const char *text = S_HEAD "[bus]\ntransport = epgm\ngroup = 239.1.2.250\nport = 7000\n"
                              "interface = eth0\nkey_file = keys/group.key\nreplay_window_s = 5\n"
                              "[service uavsim]\npublish = tcp://10.0.0.1:7100\nhost = a\n"
                              "[service mtid.uav1]\npublish = tcp://10.0.0.2:7101\nhost = b\n"
                              "interface = 10.0.0.2\n"
                              "[service trackerd]\npublish = tcp://10.0.0.2:7102\nhost = b\n"
                              "multicast = epgm://10.0.0.2;239.9.9.9:9000\n"
                              "[service stationd]\npublish = tcp://10.0.0.3:7103\nhost = c\n"
                              "multicast = no\n"
                              "[service gateway]\npublish = tcp://10.0.0.3:7104\nhost = c\n";
    if (s_load (t, text, &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    const cgs_bus_params_t *b = cgs_exercise_bus (ex);
    assert_string_equal (b->transport, "epgm");
    char want[256];
    snprintf (want, sizeof want, "%s/keys/group.key", t->dir);
    assert_string_equal (b->key_file, want);
    assert_true (b->replay_window_s == 5);
    assert_int_equal (b->rate_kbps, CGS_BUS_DEFAULT_RATE_KBPS);
    assert_int_equal (b->recovery_ms, CGS_BUS_DEFAULT_RECOVERY);
    assert_int_equal (b->hops, 1);
    assert_true (cgs_exercise_uses_multicast (ex));
    const cgs_instance_t *u = cgs_exercise_find (ex, "uavsim"),
                         *m = cgs_exercise_find (ex, "mtid.uav1"),
                         *k = cgs_exercise_find (ex, "trackerd"),
                         *s = cgs_exercise_find (ex, "stationd"),
                         *g = cgs_exercise_find (ex, "gateway");
    assert_string_equal (u->mcast_group, "239.1.2.250:7000");
    assert_string_equal (m->mcast_group, "239.1.2.251:7001");
    assert_string_equal (k->mcast_scheme, "epgm");
    assert_string_equal (k->mcast_group, "239.9.9.9:9000");
    assert_string_equal (s->mcast_scheme, "");
    assert_string_equal (g->mcast_scheme, "epgm");
    assert_string_equal (g->mcast_group, "239.1.2.252:7002");
    assert_string_equal (u->interface, "eth0");
    assert_string_equal (m->interface, "10.0.0.2");
    assert_string_equal (k->interface, "10.0.0.2");

    char ep[CGS_ENDPOINT_MAX];
    // uavsim binds its own multicast endpoint on its interface.
    assert_true (cgs_exercise_endpoint_for (u, u, ep, sizeof ep));
    assert_string_equal (ep, "epgm://eth0;239.1.2.250:7000");
    // mtid (host b) reaches uavsim (host a) over multicast, on b's interface.
    assert_true (cgs_exercise_endpoint_for (u, m, ep, sizeof ep));
    assert_string_equal (ep, "epgm://10.0.0.2;239.1.2.250:7000");
    // trackerd (host b) reaches mtid (host b) over tcp.
    assert_false (cgs_exercise_endpoint_for (m, k, ep, sizeof ep));
    assert_string_equal (ep, "tcp://10.0.0.2:7101");
    // stationd reaches trackerd over epgm; anyone reaches stationd over tcp.
    assert_true (cgs_exercise_endpoint_for (k, s, ep, sizeof ep));
    assert_string_equal (ep, "epgm://eth0;239.9.9.9:9000");
    assert_false (cgs_exercise_endpoint_for (s, u, ep, sizeof ep));
    assert_string_equal (ep, "tcp://10.0.0.3:7103");
    // A tool takes publish.
    assert_false (cgs_exercise_endpoint_for (u, NULL, ep, sizeof ep));
    assert_string_equal (ep, "tcp://10.0.0.1:7100");
    cgs_exercise_destroy (&ex);

    // Without [bus]: tcp, in the clear, no multicast.
    if (s_load (t, S_HEAD "[service a]\npublish = inproc://a\n", &ex, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_string_equal (cgs_exercise_bus (ex)->transport, "tcp");
    assert_string_equal (cgs_exercise_bus (ex)->key_file, "");
    assert_false (cgs_exercise_uses_multicast (ex));
    assert_false (cgs_exercise_endpoint_for (cgs_exercise_find (ex, "a"),
                                             cgs_exercise_find (ex, "a"), ep, sizeof ep));
    assert_string_equal (ep, "inproc://a");
    cgs_exercise_destroy (&ex);
}

static void test_bus_refused (void **state)
{
    s_tmp_t *t = *state;
    s_load_fails (t, S_HEAD "[bus]\ntransport = udp\n",
                  ":4: [bus] transport: expected norm, epgm, tcp or ipc, got 'udp'");
    s_load_fails (t, S_HEAD "[bus]\ngroup = 10.0.0.1\n",
                  ":4: [bus] group: expected an IPv4 multicast group (224.0.0.0 to "
                  "239.255.255.255), got '10.0.0.1'");
    s_load_fails (t, S_HEAD "[bus]\ntransport = epgm\n[service a]\npublish = inproc://a\n",
                  ":5: [service a] the bus uses multicast but this instance has no interface "
                  "(give `interface =` here, or in [bus] for every instance)");
    s_load_fails (t,
                  S_HEAD "[bus]\ntransport = epgm\ngroup = 239.255.255.255\ninterface = lo\n"
                         "[service a]\npublish = inproc://a\n[service b]\npublish = inproc://b\n",
                  ":5: [bus] group: too few groups or ports from here for 2 publishers "
                  "([service b] is the 2-th)");
    s_load_fails (t,
                  S_HEAD "[service a]\npublish = inproc://a\nmulticast = epgm://lo;239.1.1.1:80\n"
                         "[service b]\npublish = inproc://b\nmulticast = epgm://lo;239.1.1.1:80\n",
                  ":6: [service b] multicast group and port 239.1.1.1:80 are already [service "
                  "a]'s");
    s_load_fails (t, S_HEAD "[service a]\npublish = inproc://a\nmulticast = udp://239.1.1.1:80\n",
                  ":5: [service a] multicast: expected norm://[IFACE;]GROUP:PORT, "
                  "epgm://[IFACE;]GROUP:PORT (GROUP an IPv4 multicast address, 224.0.0.0 to "
                  "239.255.255.255) or no, got 'udp://239.1.1.1:80'");
    s_load_fails (t, S_HEAD "[service a]\npublish = inproc://a\nmulticast = epgm://239.1.1.1:0\n",
                  ":5: [service a] multicast: expected norm://[IFACE;]GROUP:PORT, "
                  "epgm://[IFACE;]GROUP:PORT (GROUP an IPv4 multicast address, 224.0.0.0 to "
                  "239.255.255.255) or no, got 'epgm://239.1.1.1:0'");
    // NORM: refused with a libzmq whose NORM engine stops on big messages.
    int ma, mi, pa;
    if (!cgs_exercise_norm_usable (&ma, &mi, &pa)) {
        char want[512];
        snprintf (want, sizeof want,
                  ":4: [bus] transport: norm is refused: this libzmq (%d.%d.%d) stops a NORM "
                  "socket for good on the first message over 2038 bytes (zeromq/libzmq#3501), "
                  "and entity and track batches are larger; use epgm",
                  ma, mi, pa);
        s_load_fails (t, S_HEAD "[bus]\ntransport = norm\ninterface = lo\n", want);
        snprintf (want, sizeof want,
                  ":5: [service a] multicast: norm is refused: this libzmq (%d.%d.%d) stops a "
                  "NORM socket for good on the first message over 2038 bytes "
                  "(zeromq/libzmq#3501), and entity and track batches are larger; use epgm",
                  ma, mi, pa);
        s_load_fails (
            t, S_HEAD "[service a]\npublish = inproc://a\nmulticast = norm://lo;239.1.1.1:80\n",
            want);
    }
    s_load_fails (t,
                  S_HEAD "[service a]\npublish = inproc://a\ninterface = 10.0.0.1\n"
                         "multicast = epgm://10.0.0.2;239.1.1.1:80\n",
                  ":6: [service a] multicast: its interface '10.0.0.2' is not the instance's "
                  "interface '10.0.0.1'");
    s_load_fails (t, S_HEAD "[bus]\ninterface = eth 0\n",
                  ":4: [bus] interface: expected a network interface's name (eth0) or IPv4 "
                  "address, got 'eth 0'");
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_default_exercise),
        cmocka_unit_test_setup_teardown (test_defaults, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_every_key, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_duplicate_endpoint, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bad_endpoint, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_origin, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bad_values, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bad_instance_name, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_curve, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_unknown, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bus_multicast, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bus_refused, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
