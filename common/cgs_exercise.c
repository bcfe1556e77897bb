/* cgs_exercise — reads and checks the exercise file every host shares.
 *
 * Paths: `scenario`, `params` and `secret_key_file` are relative to the
 * exercise file's folder (as every path in a config file is); `state_dir` is
 * a runtime location, so a relative one is taken from the current working
 * directory of the process that loads the file. All four are made absolute.
 * The scenario need not exist when the exercise is loaded. [curve] names the
 * tools' CURVE key pair and the other admitted client keys; when the exercise
 * uses CURVE at all, every instance must have its pair (cgs_curve uses them).
 * Any other section, or an unknown key, is an error. Pure: no logging. */
#include "cgs_exercise.h"
#include "cgs_util.h"

#include "cgs_topics.h"

#include <arpa/inet.h>
#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

struct cgs_exercise {
    cgs_config_t *config;                // the parsed file
    char name[CGS_NAME_MAX];             // exercise name, default the file's base name
    uint32_t id;                         // 1..255, also the DIS exercise id
    cgs_geodetic_t origin;               // origin of the local ENU frame
    double time_scale;                   // simulation seconds per wall second
    uint64_t seed;                       // seed of every model's random generator
    bool curve;                          // CURVE is used (some key, or a [curve] section)
    char client_public_key[CGS_KEY_MAX]; // [curve]: the tools' pair ("" none)
    char client_secret_key_file[4096];
    char (*allowed)[CGS_KEY_MAX]; // [curve] allow = lines
    size_t nallowed;
    char *state_dir; // absolute
    char *scenario;  // absolute, "" when none
    cgs_instance_t *instances;
    size_t count;
    cgs_bus_params_t bus; // [bus]
    bool multicast;       // some instance publishes on multicast
};

#define S_SERVICE  "service"
#define S_ENDPOINT "an endpoint starting with tcp://, ipc:// or inproc://"

// path made absolute from the working directory into a new string; -ENOMEM or getcwd's error.
static int s_absolute (const char *path, char **ret)
{
    char *abs;
    if (path[0] == '/')
        abs = strdup (path);
    else {
        char *cwd = getcwd (NULL, 0);
        if (!cwd)
            return -errno;
        while (path[0] == '.' && path[1] == '/')
            path += 2;
        if (asprintf (&abs, "%s%s%s", cwd, strcmp (cwd, "/") == 0 ? "" : "/", path) < 0)
            abs = NULL;
        free (cwd);
    }
    if (!abs)
        return -ENOMEM;
    *ret = abs;
    return 0;
}

// A path key of a section, absolute, copied into buf ("" when absent or empty).
static int s_get_path (cgs_exercise_t *self, const char *section, const char *key, char *buf,
                       size_t size, char *err, size_t errlen)
{
    const char *value;
    int rc = cgs_config_get_path (self->config, section, key, NULL, &value, err, errlen);
    if (rc < 0)
        return rc;
    if (!value || !*value) {
        buf[0] = '\0';
        return 0;
    }
    char *abs;
    rc = s_absolute (value, &abs);
    if (rc < 0)
        return cgs_config_error (self->config, section, key, 0, err, errlen,
                                 "cannot make '%s' absolute: %s", value, strerror (-rc));
    if (strlen (abs) >= size) {
        free (abs);
        return cgs_config_error (self->config, section, key, 0, err, errlen,
                                 "path too long (at most %zu characters)", size - 1);
    }
    strcpy (buf, abs);
    free (abs);
    return 0;
}

// Letters, digits, '.', '-', '_' (dots only if dots), starting with a letter or digit.
static bool s_name_ok (const char *s, bool dots)
{
    if (!isalnum ((unsigned char)s[0]))
        return false;
    for (; *s; s++)
        if (!isalnum ((unsigned char)*s) && *s != '-' && *s != '_' && !(dots && *s == '.'))
            return false;
    return true;
}

// A name-like key into buf: checked against s_name_ok and the size; "" when absent.
static int s_get_name (cgs_exercise_t *self, const char *section, const char *key, const char *def,
                       bool dots, char *buf, size_t size, char *err, size_t errlen)
{
    const char *value;
    int rc = cgs_config_get_string (self->config, section, key, def, &value, err, errlen);
    if (rc < 0)
        return rc;
    if (!value)
        value = "";
    if (*value && (!s_name_ok (value, dots) || strlen (value) >= size))
        return cgs_config_error (self->config, section, key, 0, err, errlen,
                                 "expected a name of at most %zu letters, digits, %s'-' or '_', "
                                 "got '%s'",
                                 size - 1, dots ? "'.', " : "", value);
    strcpy (buf, value);
    return 0;
}

static int s_get_endpoint (cgs_exercise_t *self, const char *section, const char *key, char *buf,
                           char *err, size_t errlen)
{
    static const char *const schemes[] = {"tcp://", "ipc://", "inproc://"};
    const char *value;
    int rc = cgs_config_get_string (self->config, section, key, "", &value, err, errlen);
    if (rc < 0)
        return rc;
    bool ok = !*value;
    for (size_t i = 0; !ok && i < sizeof schemes / sizeof schemes[0]; i++) {
        size_t n = strlen (schemes[i]);
        ok = strncmp (value, schemes[i], n) == 0 && value[n] != '\0';
    }
    if (!ok)
        return cgs_config_error (self->config, section, key, 0, err, errlen,
                                 "expected " S_ENDPOINT ", got '%s'", value);
    if (strlen (value) >= CGS_ENDPOINT_MAX)
        return cgs_config_error (self->config, section, key, 0, err, errlen,
                                 "endpoint too long (at most %d characters)", CGS_ENDPOINT_MAX - 1);
    strcpy (buf, value);
    return 0;
}

static bool s_z85_ok (const char *s)
{
    static const char z85[] = "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                              ".-:+=^!/*?&<>()[]{}@%$#";
    return strlen (s) == CGS_KEY_MAX - 1 && strspn (s, z85) == CGS_KEY_MAX - 1;
}

// The [exercise] section.
static int s_load_exercise (cgs_exercise_t *self, char *err, size_t errlen)
{
    cgs_config_t *cfg = self->config;
    const char *sec = "exercise";
    long id;
    int rc = cgs_config_get_int (cfg, sec, "id", 1, 1, 255, &id, err, errlen);
    if (rc < 0)
        return rc;
    self->id = (uint32_t)id;

    // name: default the file's base name without ".ini"
    char base[CGS_NAME_MAX];
    const char *path = cgs_config_path (cfg);
    const char *slash = strrchr (path, '/');
    snprintf (base, sizeof base, "%s", slash ? slash + 1 : path);
    size_t n = strlen (base);
    if (n > 4 && strcmp (base + n - 4, ".ini") == 0)
        base[n - 4] = '\0';
    const char *name;
    rc = cgs_config_get_string (cfg, sec, "name", base, &name, err, errlen);
    if (rc < 0)
        return rc;
    if (!*name || strlen (name) >= sizeof self->name)
        return cgs_config_error (cfg, sec, "name", 0, err, errlen,
                                 "expected a name of 1 to %zu characters, got '%s'",
                                 sizeof self->name - 1, name);
    strcpy (self->name, name);

    // origin: required, geodetic (local metres would be relative to itself)
    rc = cgs_config_require (cfg, sec, "origin",
                             "the exercise origin, e.g. `origin = geo 35.96 -121.23 0`", err,
                             errlen);
    if (rc < 0)
        return -EINVAL;
    const char *origin;
    rc = cgs_config_get_string (cfg, sec, "origin", NULL, &origin, err, errlen);
    if (rc < 0)
        return rc;
    char why[512];
    if (cgs_config_parse_geodetic (origin, &self->origin, why, sizeof why) < 0)
        return cgs_config_error (cfg, sec, "origin", 0, err, errlen, "%s", why);

    rc = cgs_config_get_double (cfg, sec, "time_scale", 1.0, 0.0, 1000.0, &self->time_scale, err,
                                errlen);
    if (rc < 0)
        return rc;
    if (self->time_scale <= 0.0)
        return cgs_config_error (cfg, sec, "time_scale", 0, err, errlen,
                                 "expected a number in (0, 1000], got '%s'",
                                 cgs_config_get_nth (cfg, sec, "time_scale", 0));
    rc = cgs_config_get_uint64 (cfg, sec, "seed", 1, &self->seed, err, errlen);
    if (rc < 0)
        return rc;

    // state_dir: a runtime location, so relative to the working directory
    const char *state_dir;
    rc = cgs_config_get_string (cfg, sec, "state_dir", "state", &state_dir, err, errlen);
    if (rc < 0)
        return rc;
    if (!*state_dir)
        return cgs_config_error (cfg, sec, "state_dir", 0, err, errlen,
                                 "expected a directory, got ''");
    rc = s_absolute (state_dir, &self->state_dir);
    if (rc < 0)
        return cgs_config_error (cfg, sec, "state_dir", 0, err, errlen,
                                 "cannot make '%s' absolute: %s", state_dir, strerror (-rc));

    char scenario[4096];
    rc = s_get_path (self, sec, "scenario", scenario, sizeof scenario, err, errlen);
    if (rc < 0)
        return rc;
    self->scenario = strdup (scenario);
    if (!self->scenario) {
        cgs_errf (err, errlen, "%s: out of memory", path);
        return -ENOMEM;
    }
    return 0;
}

// An interface name or address: no spaces, ';' or ','; "" when absent.
static int s_get_interface (cgs_exercise_t *self, const char *section, char *buf, char *err,
                            size_t errlen)
{
    const char *v;
    int rc = cgs_config_get_string (self->config, section, "interface", "", &v, err, errlen);
    if (rc < 0)
        return rc;
    if (strlen (v) >= CGS_NAME_MAX || strcspn (v, " \t;,:/") != strlen (v))
        return cgs_config_error (self->config, section, "interface", 0, err, errlen,
                                 "expected a network interface's name (eth0) or IPv4 address, "
                                 "got '%s'",
                                 v);
    strcpy (buf, v);
    return 0;
}

/* "A.B.C.D:PORT" with A.B.C.D an IPv4 multicast group (224.0.0.0/4) and PORT
 * 1..65535; into *group (host order) and *port. */
static bool s_parse_group (const char *s, uint32_t *group, long *port)
{
    const char *colon = strrchr (s, ':');
    char addr[32];
    if (!colon || (size_t)(colon - s) >= sizeof addr)
        return false;
    memcpy (addr, s, (size_t)(colon - s));
    addr[colon - s] = '\0';
    struct in_addr in;
    char *end;
    long p = strtol (colon + 1, &end, 10);
    if (inet_pton (AF_INET, addr, &in) != 1 || *end || end == colon + 1 || p < 1 || p > 65535)
        return false;
    *group = ntohl (in.s_addr);
    *port = p;
    return (*group >> 28) == 0xE;
}

/* NORM carries the bus only with a libzmq newer than 4.3.4: 4.3.4's NORM
 * engine (Debian 12's) stops on any message over 2038 bytes (its 2048-byte
 * buffer; zeromq/libzmq#3501): measured here, a PUB socket with a norm://
 * endpoint that sends one 3000-byte message sends nothing more on any of its
 * endpoints, and zmq_ctx_term then never returns. `entity` and `track`
 * batches are far larger. */
#define S_NORM_REFUSED                                                                             \
    "norm is refused: this libzmq (%d.%d.%d) stops a NORM socket for good on the first "           \
    "message over 2038 bytes (zeromq/libzmq#3501), and entity and track batches are larger; "      \
    "use epgm"

bool cgs_exercise_norm_usable (int *major, int *minor, int *patch)
{
    zmq_version (major, minor, patch);
    return *major > 4 || (*major == 4 && (*minor > 3 || (*minor == 3 && *patch > 4)));
}

/* `multicast = SCHEME://[IFACE;]GROUP:PORT` or `no` (no multicast even when
 * [bus] transport gives one). The interface, when given, is this instance's. */
static int s_get_multicast (cgs_exercise_t *self, const char *sec, cgs_instance_t *inst, char *err,
                            size_t errlen)
{
    const char *v;
    int rc = cgs_config_get_string (self->config, sec, "multicast", "", &v, err, errlen);
    if (rc < 0 || !*v)
        return rc;
    if (strcmp (v, "no") == 0) {
        strcpy (inst->mcast_scheme, "no");
        return 0;
    }
    static const char *const schemes[] = {"norm", "epgm"};
    for (size_t i = 0; i < 2; i++) {
        size_t n = strlen (schemes[i]);
        if (strncmp (v, schemes[i], n) != 0 || strncmp (v + n, "://", 3) != 0)
            continue;
        const char *rest = v + n + 3, *semi = strchr (rest, ';');
        if (semi) {
            if ((size_t)(semi - rest) >= sizeof inst->interface || semi == rest)
                break;
            char iface[CGS_NAME_MAX];
            snprintf (iface, sizeof iface, "%.*s", (int)(semi - rest), rest);
            if (*inst->interface && strcmp (iface, inst->interface) != 0)
                return cgs_config_error (self->config, sec, "multicast", 0, err, errlen,
                                         "its interface '%s' is not the instance's interface "
                                         "'%s'",
                                         iface, inst->interface);
            strcpy (inst->interface, iface);
            rest = semi + 1;
        }
        uint32_t g;
        long port;
        if (!s_parse_group (rest, &g, &port))
            break;
        int ma, mi, pa;
        if (i == 0 && !cgs_exercise_norm_usable (&ma, &mi, &pa))
            return cgs_config_error (self->config, sec, "multicast", 0, err, errlen, S_NORM_REFUSED,
                                     ma, mi, pa);
        strcpy (inst->mcast_scheme, schemes[i]);
        snprintf (inst->mcast_group, sizeof inst->mcast_group, "%s", rest);
        return 0;
    }
    return cgs_config_error (self->config, sec, "multicast", 0, err, errlen,
                             "expected norm://[IFACE;]GROUP:PORT, epgm://[IFACE;]GROUP:PORT "
                             "(GROUP an IPv4 multicast address, 224.0.0.0 to 239.255.255.255) "
                             "or no, got '%s'",
                             v);
}

// One [service NAME] section, the i-th of the file, into inst.
static int s_load_instance (cgs_exercise_t *self, size_t i, cgs_instance_t *inst, char *err,
                            size_t errlen)
{
    cgs_config_t *cfg = self->config;
    const char *sec = cgs_config_section_name (cfg, i);
    const char *name = sec + strlen (S_SERVICE);
    if (*name == ' ')
        name++;
    if (!*name || !s_name_ok (name, true) || strlen (name) >= sizeof inst->name)
        return cgs_config_error (cfg, sec, NULL, 0, err, errlen,
                                 "expected [service NAME] with NAME an instance name of at most "
                                 "%zu letters, digits, '.', '-' or '_', e.g. [service mtid.uav1]",
                                 sizeof inst->name - 1);
    strcpy (inst->name, name);

    // program: the instance name up to its first '.', unless given
    char program[CGS_NAME_MAX];
    snprintf (program, sizeof program, "%.*s", (int)strcspn (name, "."), name);
    int rc = s_get_name (self, sec, "program", program, false, inst->program, sizeof inst->program,
                         err, errlen);
    if (rc < 0)
        return rc;
    if (!*inst->program)
        return cgs_config_error (cfg, sec, "program", 0, err, errlen,
                                 "expected a program name, got ''");
    rc = s_get_endpoint (self, sec, "publish", inst->publish, err, errlen);
    if (rc < 0)
        return rc;
    rc = s_get_endpoint (self, sec, "command", inst->command, err, errlen);
    if (rc < 0)
        return rc;

    const char *host;
    rc = cgs_config_get_string (cfg, sec, "host", "localhost", &host, err, errlen);
    if (rc < 0)
        return rc;
    if (!*host || strlen (host) >= sizeof inst->host || strcspn (host, " \t") != strlen (host))
        return cgs_config_error (cfg, sec, "host", 0, err, errlen,
                                 "expected a host name of at most %zu characters, got '%s'",
                                 sizeof inst->host - 1, host);
    strcpy (inst->host, host);

    rc = s_get_name (self, sec, "uav", "", true, inst->uav, sizeof inst->uav, err, errlen);
    if (rc < 0)
        return rc;
    rc = s_get_path (self, sec, "params", inst->params, sizeof inst->params, err, errlen);
    if (rc < 0)
        return rc;

    const char *key;
    rc = cgs_config_get_string (cfg, sec, "public_key", "", &key, err, errlen);
    if (rc < 0)
        return rc;
    if (*key && !s_z85_ok (key))
        return cgs_config_error (cfg, sec, "public_key", 0, err, errlen,
                                 "expected a CURVE public key of %d Z85 characters, got '%s'",
                                 CGS_KEY_MAX - 1, key);
    strcpy (inst->public_key, key);
    rc = s_get_path (self, sec, "secret_key_file", inst->secret_key_file,
                     sizeof inst->secret_key_file, err, errlen);
    if (rc < 0)
        return rc;
    long hwm;
    rc = cgs_config_get_int (cfg, sec, "hwm", CGS_EXERCISE_DEFAULT_HWM, 10, 100000000, &hwm, err,
                             errlen);
    if (rc < 0)
        return rc;
    inst->hwm = (int)hwm;
    rc = cgs_config_get_bool (cfg, sec, "enabled", true, &inst->enabled, err, errlen);
    if (rc < 0)
        return rc;
    rc = s_get_interface (self, sec, inst->interface, err, errlen);
    if (rc < 0)
        return rc;
    rc = s_get_multicast (self, sec, inst, err, errlen);
    if (rc < 0)
        return rc;
    if (!*inst->publish)
        return cgs_config_error (cfg, sec, NULL, 0, err, errlen,
                                 "missing key 'publish' (expected %s: every service publishes "
                                 "its health)",
                                 S_ENDPOINT);
    return 0;
}

// No two instances may bind the same endpoint: the later one is the error.
static int s_check_endpoints (cgs_exercise_t *self, char *err, size_t errlen)
{
    static const char *const keys[] = {"publish", "command"};
    for (size_t i = 0; i < self->count; i++) {
        const cgs_instance_t *a = &self->instances[i];
        const char *ends_a[] = {a->publish, a->command};
        for (size_t ka = 0; ka < 2; ka++) {
            if (!*ends_a[ka])
                continue;
            // every endpoint before this one, in file order
            for (size_t j = 0; j <= i; j++) {
                const cgs_instance_t *b = &self->instances[j];
                const char *ends_b[] = {b->publish, b->command};
                for (size_t kb = 0; kb < 2 && (j < i || kb < ka); kb++) {
                    if (strcmp (ends_a[ka], ends_b[kb]) != 0)
                        continue;
                    char sec_a[CGS_NAME_MAX + 8], sec_b[CGS_NAME_MAX + 8];
                    snprintf (sec_a, sizeof sec_a, S_SERVICE " %s", a->name);
                    snprintf (sec_b, sizeof sec_b, S_SERVICE " %s", b->name);
                    return cgs_config_error (self->config, sec_a, keys[ka], 0, err, errlen,
                                             "endpoint '%s' is already used by [%s] %s at line %d",
                                             ends_a[ka], sec_b, keys[kb],
                                             cgs_config_line (self->config, sec_b, keys[kb], 0));
                }
            }
        }
    }
    return 0;
}

static int s_load_services (cgs_exercise_t *self, char *err, size_t errlen)
{
    cgs_config_t *cfg = self->config;
    size_t n = 0;
    for (size_t i = 0; i < cgs_config_section_count (cfg); i++)
        n += strncmp (cgs_config_section_name (cfg, i), S_SERVICE, strlen (S_SERVICE)) == 0;
    self->instances = calloc (n ? n : 1, sizeof *self->instances);
    if (!self->instances) {
        cgs_errf (err, errlen, "%s: out of memory", cgs_config_path (cfg));
        return -ENOMEM;
    }
    for (size_t i = 0; i < cgs_config_section_count (cfg); i++) {
        const char *sec = cgs_config_section_name (cfg, i);
        // "service NAME"; "servicex" is some other (unknown) section
        if (strncmp (sec, S_SERVICE, strlen (S_SERVICE)) != 0)
            continue;
        char after = sec[strlen (S_SERVICE)];
        if (after != '\0' && after != ' ')
            continue;
        int rc = s_load_instance (self, i, &self->instances[self->count], err, errlen);
        if (rc < 0)
            return rc;
        self->count++;
    }
    return s_check_endpoints (self, err, errlen);
}

/* A CURVE public key value of [section] key (idx-th), checked. */
static int s_key (cgs_exercise_t *self, const char *section, const char *key, const char *value,
                  size_t idx, char *err, size_t errlen)
{
    if (s_z85_ok (value))
        return 0;
    return cgs_config_error (self->config, section, key, idx, err, errlen,
                             "expected a CURVE public key of %d Z85 characters, got '%s'",
                             CGS_KEY_MAX - 1, value);
}

// The [curve] section, and every instance's pair when CURVE is used.
static int s_load_curve (cgs_exercise_t *self, char *err, size_t errlen)
{
    cgs_config_t *cfg = self->config;
    self->curve = cgs_config_has_section (cfg, "curve");
    for (size_t i = 0; i < self->count; i++)
        self->curve |= *self->instances[i].public_key != '\0';
    if (!self->curve)
        return 0;
    const char *v;
    int rc = cgs_config_get_string (cfg, "curve", "client_public_key", "", &v, err, errlen);
    if (rc == 0 && *v)
        rc = s_key (self, "curve", "client_public_key", v, 0, err, errlen);
    if (rc < 0)
        return rc;
    snprintf (self->client_public_key, sizeof self->client_public_key, "%s", v);
    rc = s_get_path (self, "curve", "client_secret_key_file", self->client_secret_key_file,
                     sizeof self->client_secret_key_file, err, errlen);
    if (rc < 0)
        return rc;
    if (!*self->client_public_key != !*self->client_secret_key_file)
        return cgs_config_error (
            cfg, "curve", *self->client_public_key ? "client_public_key" : "client_secret_key_file",
            0, err, errlen, "give client_public_key and client_secret_key_file together");
    size_t n = cgs_config_count (cfg, "curve", "allow");
    self->allowed = calloc (n ? n : 1, sizeof *self->allowed);
    if (!self->allowed) {
        cgs_errf (err, errlen, "%s: out of memory", cgs_config_path (cfg));
        return -ENOMEM;
    }
    for (size_t i = 0; i < n; i++) {
        v = cgs_config_get_nth (cfg, "curve", "allow", i);
        if ((rc = s_key (self, "curve", "allow", v, i, err, errlen)) < 0)
            return rc;
        snprintf (self->allowed[self->nallowed++], CGS_KEY_MAX, "%s", v);
    }
    for (size_t i = 0; i < self->count; i++) {
        const cgs_instance_t *in = &self->instances[i];
        if (!*in->public_key || !*in->secret_key_file) {
            char sec[CGS_NAME_MAX + 16];
            snprintf (sec, sizeof sec, "service %s", in->name);
            int line = 0;
            for (size_t k = 0; k < cgs_config_section_count (cfg) && !line; k++)
                if (strcmp (cgs_config_section_name (cfg, k), sec) == 0)
                    line = cgs_config_section_line (cfg, k);
            cgs_errf (err, errlen,
                      "%s:%d: [service %s] has no %s, but the exercise uses CURVE (every "
                      "instance needs a key pair: mscgs keygen)",
                      cgs_config_path (cfg), line, in->name,
                      *in->public_key ? "secret_key_file" : "public_key");
            return -EINVAL;
        }
    }
    return 0;
}

/* The [bus] section, then each instance's multicast endpoint (derived from
 * transport, group and port where the instance gives none) and interface. */
static int s_load_bus (cgs_exercise_t *self, char *err, size_t errlen)
{
    cgs_config_t *cfg = self->config;
    const char *sec = "bus";
    cgs_bus_params_t *b = &self->bus;
    const char *v;
    int rc = cgs_config_get_string (cfg, sec, "transport", "tcp", &v, err, errlen);
    if (rc < 0)
        return rc;
    if (strcmp (v, "norm") && strcmp (v, "epgm") && strcmp (v, "tcp") && strcmp (v, "ipc"))
        return cgs_config_error (cfg, sec, "transport", 0, err, errlen,
                                 "expected norm, epgm, tcp or ipc, got '%s'", v);
    int ma, mi, pa;
    if (strcmp (v, "norm") == 0 && !cgs_exercise_norm_usable (&ma, &mi, &pa))
        return cgs_config_error (cfg, sec, "transport", 0, err, errlen, S_NORM_REFUSED, ma, mi, pa);
    snprintf (b->transport, sizeof b->transport, "%s", v);
    bool derive = strcmp (v, "norm") == 0 || strcmp (v, "epgm") == 0;
    rc = cgs_config_get_string (cfg, sec, "group", CGS_BUS_DEFAULT_GROUP, &v, err, errlen);
    if (rc < 0)
        return rc;
    char gp[80];
    snprintf (gp, sizeof gp, "%s:1", v);
    uint32_t group;
    long port;
    if (!s_parse_group (gp, &group, &port))
        return cgs_config_error (cfg, sec, "group", 0, err, errlen,
                                 "expected an IPv4 multicast group (224.0.0.0 to "
                                 "239.255.255.255), got '%s'",
                                 v);
    rc = cgs_config_get_int (cfg, sec, "port", CGS_BUS_DEFAULT_PORT, 1, 65535, &port, err, errlen);
    if (rc < 0)
        return rc;
    char iface[CGS_NAME_MAX];
    if ((rc = s_get_interface (self, sec, iface, err, errlen)) < 0 ||
        (rc = s_get_path (self, sec, "key_file", b->key_file, sizeof b->key_file, err, errlen)) <
            0 ||
        (rc = cgs_config_get_double (cfg, sec, "replay_window_s", CGS_BUS_DEFAULT_WINDOW_S, 0,
                                     86400, &b->replay_window_s, err, errlen)) < 0)
        return rc;
    long rate, recovery, hops;
    if ((rc = cgs_config_get_int (cfg, sec, "rate_kbps", CGS_BUS_DEFAULT_RATE_KBPS, 10, 10000000,
                                  &rate, err, errlen)) < 0 ||
        (rc = cgs_config_get_int (cfg, sec, "recovery_ms", CGS_BUS_DEFAULT_RECOVERY, 100, 600000,
                                  &recovery, err, errlen)) < 0 ||
        (rc = cgs_config_get_int (cfg, sec, "hops", CGS_BUS_DEFAULT_HOPS, 1, 255, &hops, err,
                                  errlen)) < 0)
        return rc;
    b->rate_kbps = (int)rate;
    b->recovery_ms = (int)recovery;
    b->hops = (int)hops;

    size_t k = 0; // publishers given a derived endpoint so far
    for (size_t i = 0; i < self->count; i++) {
        cgs_instance_t *in = &self->instances[i];
        char isec[CGS_NAME_MAX + 16];
        snprintf (isec, sizeof isec, S_SERVICE " %s", in->name);
        if (!*in->interface)
            strcpy (in->interface, iface);
        if (strcmp (in->mcast_scheme, "no") == 0) {
            in->mcast_scheme[0] = '\0';
            continue;
        }
        if (!*in->mcast_scheme && derive) {
            uint32_t g = group + (uint32_t)k;
            long p = port + (long)k;
            if ((g >> 28) != 0xE || p > 65535)
                return cgs_config_error (cfg, sec, "group", 0, err, errlen,
                                         "too few groups or ports from here for %zu publishers "
                                         "([service %s] is the %zu-th)",
                                         k + 1, in->name, k + 1);
            struct in_addr a = {.s_addr = htonl (g)};
            char addr[INET_ADDRSTRLEN];
            inet_ntop (AF_INET, &a, addr, sizeof addr);
            snprintf (in->mcast_group, sizeof in->mcast_group, "%s:%ld", addr, p);
            snprintf (in->mcast_scheme, sizeof in->mcast_scheme, "%s", b->transport);
            k++;
        }
        if (!*in->mcast_scheme)
            continue;
        self->multicast = true;
        for (size_t j = 0; j < i; j++)
            if (strcmp (self->instances[j].mcast_group, in->mcast_group) == 0)
                return cgs_config_error (cfg, isec, NULL, 0, err, errlen,
                                         "multicast group and port %s are already [service %s]'s",
                                         in->mcast_group, self->instances[j].name);
    }
    // Every instance of a multicast exercise joins groups: it needs an interface.
    for (size_t i = 0; self->multicast && i < self->count; i++) {
        const cgs_instance_t *in = &self->instances[i];
        if (*in->interface)
            continue;
        char isec[CGS_NAME_MAX + 16];
        snprintf (isec, sizeof isec, S_SERVICE " %s", in->name);
        return cgs_config_error (cfg, isec, NULL, 0, err, errlen,
                                 "the bus uses multicast but this instance has no interface "
                                 "(give `interface =` here, or in [bus] for every instance)");
    }
    return 0;
}

const cgs_bus_params_t *cgs_exercise_bus (const cgs_exercise_t *self)
{
    return &self->bus;
}

bool cgs_exercise_uses_multicast (const cgs_exercise_t *self)
{
    return self->multicast;
}

bool cgs_exercise_endpoint_for (const cgs_instance_t *pub, const cgs_instance_t *local, char *buf,
                                size_t len)
{
    bool mc = *pub->mcast_scheme && local && *local->interface &&
              (local == pub || strcmp (local->host, pub->host) != 0);
    if (mc)
        snprintf (buf, len, "%s://%s;%s", pub->mcast_scheme, local->interface, pub->mcast_group);
    else
        snprintf (buf, len, "%s", pub->publish);
    return mc;
}

int cgs_exercise_load (const char *path, cgs_exercise_t **ret_ex, char *err, size_t errlen)
{
    assert (path && ret_ex);
    cgs_exercise_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_errf (err, errlen, "%s: out of memory", path);
        return -ENOMEM;
    }
    int rc = cgs_config_load (path, &self->config, err, errlen);
    if (rc < 0)
        goto fail;
    rc = s_load_exercise (self, err, errlen);
    if (rc < 0)
        goto fail;
    rc = s_load_services (self, err, errlen);
    if (rc < 0)
        goto fail;
    rc = s_load_curve (self, err, errlen);
    if (rc < 0)
        goto fail;
    rc = s_load_bus (self, err, errlen);
    if (rc < 0)
        goto fail;
    rc = cgs_config_check_unused (self->config, err, errlen);
    if (rc < 0)
        goto fail;
    *ret_ex = self;
    return 0;
fail:
    cgs_exercise_destroy (&self);
    return rc;
}

void cgs_exercise_destroy (cgs_exercise_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_exercise_t *self = *self_p;
    cgs_config_destroy (&self->config);
    free (self->state_dir);
    free (self->scenario);
    free (self->instances);
    free (self->allowed);
    free (self);
    *self_p = NULL;
}

const char *cgs_exercise_path (const cgs_exercise_t *self)
{
    return cgs_config_path (self->config);
}

const char *cgs_exercise_name (const cgs_exercise_t *self)
{
    return self->name;
}

uint32_t cgs_exercise_id (const cgs_exercise_t *self)
{
    return self->id;
}

cgs_geodetic_t cgs_exercise_origin (const cgs_exercise_t *self)
{
    return self->origin;
}

double cgs_exercise_time_scale (const cgs_exercise_t *self)
{
    return self->time_scale;
}

uint64_t cgs_exercise_seed (const cgs_exercise_t *self)
{
    return self->seed;
}

const char *cgs_exercise_state_dir (const cgs_exercise_t *self)
{
    return self->state_dir;
}

const char *cgs_exercise_scenario (const cgs_exercise_t *self)
{
    return self->scenario;
}

cgs_config_t *cgs_exercise_config (cgs_exercise_t *self)
{
    return self->config;
}

size_t cgs_exercise_instance_count (const cgs_exercise_t *self)
{
    return self->count;
}

const cgs_instance_t *cgs_exercise_instance (const cgs_exercise_t *self, size_t i)
{
    return i < self->count ? &self->instances[i] : NULL;
}

const cgs_instance_t *cgs_exercise_find (const cgs_exercise_t *self, const char *name)
{
    for (size_t i = 0; i < self->count; i++)
        if (strcmp (self->instances[i].name, name) == 0)
            return &self->instances[i];
    return NULL;
}

/* Instances without a publish endpoint cannot publish and are left out;
 * disabled instances are kept (they may be started by hand). */
size_t cgs_exercise_publishers_of (const cgs_exercise_t *self, const char *topic,
                                   const cgs_instance_t **ret, size_t max)
{
    const cgs_topic_t *t = cgs_topics_find (topic);
    size_t n = 0;
    for (size_t i = 0; t && i < self->count; i++) {
        const cgs_instance_t *inst = &self->instances[i];
        if (!*inst->publish || !cgs_topics_published_by (t, inst->program))
            continue;
        if (ret && n < max)
            ret[n] = inst;
        n++;
    }
    return n;
}

bool cgs_exercise_uses_curve (const cgs_exercise_t *self)
{
    return self->curve;
}

const char *cgs_exercise_client_public_key (const cgs_exercise_t *self)
{
    return self->client_public_key;
}

const char *cgs_exercise_client_secret_key_file (const cgs_exercise_t *self)
{
    return self->client_secret_key_file;
}

size_t cgs_exercise_allowed_count (const cgs_exercise_t *self)
{
    return self->nallowed;
}

const char *cgs_exercise_allowed (const cgs_exercise_t *self, size_t i)
{
    return i < self->nallowed ? self->allowed[i] : NULL;
}

const cgs_instance_t *cgs_exercise_first_of (const cgs_exercise_t *self, const char *program)
{
    for (size_t i = 0; i < self->count; i++)
        if (strcmp (self->instances[i].program, program) == 0)
            return &self->instances[i];
    return NULL;
}
