/* st_params — stationd's parameter file (see st_params.h). */
#include "st_params.h"

#include "cgs_config.h"

#include <arpa/inet.h>
#include <ctype.h>
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

void st_params_defaults (st_params_t *p)
{
    memset (p, 0, sizeof *p);
    snprintf (p->listen_address, sizeof p->listen_address, "127.0.0.1");
    p->port = 8080;
    p->threads = 16;
    p->write_timeout_s = 10;
    p->push_hz = 5;
    p->history_scans = 20;
    p->bcis_timeout_s = 5;
    p->track_stale_s = 60;
    p->truth_stale_s = 30;
    p->sun_azimuth_deg = 315;
    p->sun_elevation_deg = 45;
    p->z_factor = 1;
    p->max_pixels = 4096;
    p->command_timeout_s = 1;
    p->command_attempts = 3;
}

bool st_params_is_loopback (const char *address)
{
    struct in_addr a4;
    struct in6_addr a6;
    if (inet_pton (AF_INET, address, &a4) == 1)
        return (ntohl (a4.s_addr) >> 24) == 127;
    if (inet_pton (AF_INET6, address, &a6) == 1)
        return IN6_IS_ADDR_LOOPBACK (&a6);
    return strcmp (address, "localhost") == 0;
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (st_params_t, field), lo, hi                                              \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("http", "write_timeout_s", write_timeout_s, 0.1, 3600.0),
    S_R ("display", "push_hz", push_hz, 0.1, 50.0),
    S_R ("display", "bcis_timeout_s", bcis_timeout_s, 0.1, 3600.0),
    S_R ("display", "track_stale_s", track_stale_s, 1.0, 86400.0),
    S_R ("display", "truth_stale_s", truth_stale_s, 1.0, 86400.0),
    S_R ("relief", "sun_azimuth_deg", sun_azimuth_deg, 0.0, 360.0),
    S_R ("relief", "sun_elevation_deg", sun_elevation_deg, 1.0, 90.0),
    S_R ("relief", "z_factor", z_factor, 0.01, 100.0),
    S_R ("commands", "timeout_s", command_timeout_s, 0.05, 60.0),
};
#undef S_R
#define S_I(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (st_params_t, field), lo, hi                                              \
    }
static const cgs_config_int_t s_ints[] = {
    S_I ("http", "port", port, 0, 65535),
    S_I ("http", "threads", threads, 4, 256),
    S_I ("display", "history_scans", history_scans, 0, 200),
    S_I ("relief", "max_pixels", max_pixels, 64, 16384),
    S_I ("commands", "attempts", command_attempts, 1, 20),
};
#undef S_I

/* A token is printable ASCII without spaces, so it fits a URL's query. */
static bool s_token_ok (const char *t)
{
    if (strlen (t) < 8)
        return false;
    for (const char *c = t; *c; c++)
        if (!isgraph ((unsigned char)*c) || strchr ("&#%+?/=", *c))
            return false;
    return true;
}

/* The token from the file at path: its first line, without the newline. */
static int s_token_file (cgs_config_t *cfg, const char *path, st_params_t *p, char *err,
                         size_t errlen)
{
    FILE *f = fopen (path, "r");
    if (!f)
        return cgs_config_error (cfg, "http", "token_file", 0, err, errlen, "cannot read %s: %s",
                                 path, strerror (errno));
    char line[ST_TOKEN_MAX + 2] = "";
    bool got = fgets (line, sizeof line, f) != NULL;
    fclose (f);
    size_t len = strcspn (line, "\r\n");
    if (got && len >= ST_TOKEN_MAX) // never cut: a cut token would match nobody's
        return cgs_config_error (cfg, "http", "token_file", 0, err, errlen,
                                 "%s: the token is longer than %d characters", path,
                                 ST_TOKEN_MAX - 1);
    line[len] = '\0';
    if (!got || !s_token_ok (line))
        return cgs_config_error (cfg, "http", "token_file", 0, err, errlen,
                                 "%s: the first line must be the token: at least 8 printable "
                                 "characters without spaces or any of & # %% + ? / =",
                                 path);
    snprintf (p->token, sizeof p->token, "%s", line);
    p->token_from_file = true;
    return 0;
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    st_params_t *out = arg, p = *out;
    const char *s;
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, sizeof s_reals / sizeof s_reals[0], s_ints,
                                   sizeof s_ints / sizeof s_ints[0], &p, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_string (cfg, "http", "listen", p.listen_address, &s, err, errlen);
    if (rc == 0) {
        struct in_addr a4;
        struct in6_addr a6;
        if (strlen (s) >= sizeof p.listen_address ||
            (inet_pton (AF_INET, s, &a4) != 1 && inet_pton (AF_INET6, s, &a6) != 1))
            rc = cgs_config_error (cfg, "http", "listen", 0, err, errlen,
                                   "expected an IPv4 or IPv6 address (127.0.0.1, 0.0.0.0, ::1), "
                                   "got '%s'",
                                   s);
        else if (s != p.listen_address)
            snprintf (p.listen_address, sizeof p.listen_address, "%s", s);
    }
    if (rc == 0 && cgs_config_has (cfg, "http", "token") &&
        cgs_config_has (cfg, "http", "token_file"))
        rc = cgs_config_error (cfg, "http", "token_file", 0, err, errlen,
                               "give the token or token_file, not both");
    if (rc == 0)
        rc = cgs_config_get_string (cfg, "http", "token", p.token, &s, err, errlen);
    if (rc == 0 && *s && (strlen (s) >= sizeof p.token || !s_token_ok (s)))
        rc = cgs_config_error (cfg, "http", "token", 0, err, errlen,
                               "expected at least 8 printable characters without spaces or any "
                               "of & # %% + ? / =");
    if (rc == 0 && *s && s != p.token)
        snprintf (p.token, sizeof p.token, "%s", s);
    if (rc == 0 && cgs_config_has (cfg, "http", "token_file")) {
        rc = cgs_config_get_path (cfg, "http", "token_file", "", &s, err, errlen);
        if (rc == 0)
            rc = s_token_file (cfg, s, &p, err, errlen);
    }
    if (rc == 0)
        rc = cgs_config_get_path (cfg, "http", "web_root", p.web_root, &s, err, errlen);
    if (rc == 0 && s != p.web_root)
        snprintf (p.web_root, sizeof p.web_root, "%s", s);
    if (rc == 0 && !p.token[0] && !st_params_is_loopback (p.listen_address))
        rc = cgs_config_error (cfg, "http", "listen", 0, err, errlen,
                               "listening on %s (not loopback) needs an operators' access token: "
                               "give `token` or `token_file` in [http]",
                               p.listen_address);
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc < 0)
        return rc;
    *out = p;
    return 0;
}

int st_params_load (const char *path, st_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int st_params_load_string (const char *name, const char *text, st_params_t *p, char *err,
                           size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}
