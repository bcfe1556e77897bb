/* st_web — the embedded web server (see st_web.h). */
#include "st_web.h"

#include <civetweb.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>

#define S_PATH_MAX 4096

struct st_web_conn {
    st_web_t *web;
    struct mg_connection *mg;
    bool operator;
    bool listed;   // in the push list (ready), guarded by the web's lock
    bool broken;   // a write failed
    void *user;    // the request function's
    char peer[64]; // remote address
    st_web_conn_t *next;
};

struct st_web {
    struct mg_context *mg;
    st_web_request_fn *request;
    st_web_close_fn *close_fn;
    void *arg;
    char token[260];
    int port;
    uint8_t *relief;
    size_t relief_len;
    pthread_mutex_t lock; // everything below
    pthread_cond_t wake;  // a new picture, or stop
    pthread_t pusher;
    bool pusher_started, stopping;
    st_web_conn_t *conns; // pages that are ready
    char *picture;        // newest picture not yet pushed (owned)
    size_t picture_len;
    char *last; // the picture pushed last, for new pages (owned)
    size_t last_len;
    char *hello_operator, *hello_viewer;
    char image_path[S_PATH_MAX];
    st_web_stats_t stats;
    char last_error[256];
};

static double s_now (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int s_log (const struct mg_connection *conn, const char *message)
{
    st_web_t *self = mg_get_user_data (mg_get_context (conn));
    if (self) {
        pthread_mutex_lock (&self->lock);
        snprintf (self->last_error, sizeof self->last_error, "%s", message);
        pthread_mutex_unlock (&self->lock);
    }
    return 1; // handled: nothing on stdout
}

/* Constant-time comparison, so the token cannot be guessed byte by byte. */
static bool s_token_equal (const char *a, const char *b)
{
    size_t la = strlen (a), lb = strlen (b);
    unsigned char diff = (unsigned char)(la != lb);
    for (size_t i = 0; i < la; i++)
        diff |= (unsigned char)(a[i] ^ b[i % (lb ? lb : 1)]);
    return diff == 0;
}

/* The host:port part of an Origin header ("http://host:port"). */
static const char *s_origin_host (const char *origin)
{
    const char *p = strstr (origin, "://");
    return p ? p + 3 : origin;
}

static int s_ws_connect (const struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    const struct mg_request_info *ri = mg_get_request_info (conn);
    const char *origin = mg_get_header (conn, "Origin");
    const char *host = mg_get_header (conn, "Host");
    // Browsers always send Origin; other tools (tests, scripts) may not.
    if (origin && (!host || strcasecmp (s_origin_host (origin), host) != 0)) {
        pthread_mutex_lock (&self->lock);
        self->stats.refused++;
        snprintf (self->last_error, sizeof self->last_error,
                  "refused a WebSocket from %s: Origin %s is not this server (%s)", ri->remote_addr,
                  origin, host ? host : "no Host header");
        pthread_mutex_unlock (&self->lock);
        return 1;
    }
    st_web_conn_t *c = calloc (1, sizeof *c);
    if (!c)
        return 1;
    c->web = self;
    snprintf (c->peer, sizeof c->peer, "%s:%d", ri->remote_addr, ri->remote_port);
    if (!self->token[0])
        c->operator= true;
    else if (ri->query_string) {
        char given[260];
        if (mg_get_var (ri->query_string, strlen (ri->query_string), "token", given, sizeof given) >
            0)
            c->operator= s_token_equal (given, self->token);
    }
    mg_set_user_connection_data (conn, c);
    return 0;
}

/* Write text to a page; the caller holds no connection lock (CivetWeb takes it). */
static int s_write (st_web_conn_t *c, const char *text, size_t len)
{
    if (c->broken)
        return -EPIPE;
    if (mg_websocket_write (c->mg, MG_WEBSOCKET_OPCODE_TEXT, text, len) <= 0) {
        c->broken = true;
        return -EPIPE;
    }
    return 0;
}

static void s_ws_ready (struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    st_web_conn_t *c = mg_get_user_connection_data (conn);
    if (!c)
        return;
    c->mg = conn;
    pthread_mutex_lock (&self->lock);
    // The hello and the latest picture first, then the pushes: in that order.
    const char *hello = c->operator? self->hello_operator : self->hello_viewer;
    if (hello)
        s_write (c, hello, strlen (hello));
    if (self->last)
        s_write (c, self->last, self->last_len);
    c->listed = true;
    c->next = self->conns;
    self->conns = c;
    self->stats.pages++;
    self->stats.pages_total++;
    pthread_mutex_unlock (&self->lock);
}

static int s_ws_data (struct mg_connection *conn, int flags, char *data, size_t len, void *cbdata)
{
    st_web_t *self = cbdata;
    st_web_conn_t *c = mg_get_user_connection_data (conn);
    int opcode = flags & 0xf;
    if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE)
        return 0;
    if (!c || opcode != MG_WEBSOCKET_OPCODE_TEXT)
        return 1; // pings, pongs and binary frames: nothing to do
    pthread_mutex_lock (&self->lock);
    self->stats.requests++;
    pthread_mutex_unlock (&self->lock);
    self->request (self->arg, c, data, len, c->operator);
    return 1;
}

static void s_ws_close (const struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    st_web_conn_t *c = mg_get_user_connection_data (conn);
    if (!c)
        return;
    pthread_mutex_lock (&self->lock);
    for (st_web_conn_t **p = &self->conns; *p; p = &(*p)->next)
        if (*p == c) {
            *p = c->next;
            self->stats.pages--;
            break;
        }
    pthread_mutex_unlock (&self->lock);
    if (self->close_fn && c->user)
        self->close_fn (self->arg, c->user);
    mg_set_user_connection_data (conn, NULL);
    free (c);
}

static int s_relief (struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    if (!self->relief) {
        mg_send_http_error (conn, 404, "%s", "no terrain relief");
        return 404;
    }
    mg_send_http_ok (conn, "image/png", (long long)self->relief_len);
    mg_write (conn, self->relief, self->relief_len);
    return 200;
}

static int s_image (struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    char path[S_PATH_MAX];
    pthread_mutex_lock (&self->lock);
    snprintf (path, sizeof path, "%s", self->image_path);
    pthread_mutex_unlock (&self->lock);
    struct stat st;
    if (!path[0] || stat (path, &st) != 0) {
        mg_send_http_error (conn, 404, "%s", "no sensor image yet");
        return 404;
    }
    mg_send_mime_file2 (conn, path, "image/png", "Cache-Control: no-store\r\n");
    return 200;
}

/* The push thread: the newest picture to every page, until stopped. */
static void *s_pusher (void *arg)
{
    st_web_t *self = arg;
    pthread_mutex_lock (&self->lock);
    for (;;) {
        while (!self->picture && !self->stopping)
            pthread_cond_wait (&self->wake, &self->lock);
        if (self->stopping)
            break;
        free (self->last);
        self->last = self->picture;
        self->last_len = self->picture_len;
        self->picture = NULL;
        if (self->last_len > self->stats.max_push_bytes)
            self->stats.max_push_bytes = self->last_len;
        // Pages are written under the lock: a page's close waits for it, so
        // none is freed while being written to.
        double t0 = s_now ();
        for (st_web_conn_t *c = self->conns; c; c = c->next) {
            if (s_write (c, self->last, self->last_len) == 0)
                self->stats.pushes++;
            else if (c->listed) {
                c->listed = false; // counted once; CivetWeb closes it
                self->stats.write_errors++;
            }
        }
        self->stats.last_push_s = s_now () - t0;
    }
    pthread_mutex_unlock (&self->lock);
    return NULL;
}

/* Start CivetWeb with the configuration; NULL with the reason in why. */
static struct mg_context *s_start (st_web_t *self, const st_web_config_t *cfg, char *ports,
                                   size_t portslen, char *why, size_t whylen)
{
    mg_init_library (0);
    char threads[16], timeout[32];
    bool v6 = strchr (cfg->listen_address, ':') != NULL;
    snprintf (ports, portslen, v6 ? "[%s]:%d" : "%s:%d", cfg->listen_address, cfg->port);
    snprintf (threads, sizeof threads, "%d", cfg->threads);
    snprintf (timeout, sizeof timeout, "%.0f", cfg->write_timeout_s * 1000);
    const char *options[] = {"listening_ports",
                             ports,
                             "document_root",
                             cfg->web_root,
                             "num_threads",
                             threads,
                             "enable_directory_listing",
                             "no",
                             "request_timeout_ms",
                             timeout,
                             "websocket_timeout_ms",
                             "30000",
                             "enable_websocket_ping_pong",
                             "yes",
                             "additional_header",
                             "X-Content-Type-Options: nosniff",
                             NULL};
    struct mg_callbacks callbacks = {.log_message = s_log};
    struct mg_init_data init = {&callbacks, self, options};
    unsigned code = 0;
    struct mg_error_data error = {&code, why, whylen};
    struct mg_context *mg = mg_start2 (&init, &error);
    if (!mg)
        mg_exit_library ();
    return mg;
}

st_web_t *st_web_new (const st_web_config_t *cfg, st_web_request_fn *request,
                      st_web_close_fn *close_fn, void *arg, char *err, size_t errlen)
{
    struct stat st;
    if (!cfg->web_root || stat (cfg->web_root, &st) != 0 || !S_ISDIR (st.st_mode)) {
        snprintf (err, errlen, "the page's folder %s is missing (build it with make)",
                  cfg->web_root ? cfg->web_root : "(none)");
        return NULL;
    }
    st_web_t *self = calloc (1, sizeof *self);
    if (!self) {
        snprintf (err, errlen, "out of memory");
        return NULL;
    }
    pthread_mutex_init (&self->lock, NULL);
    pthread_cond_init (&self->wake, NULL);
    self->request = request;
    self->close_fn = close_fn;
    self->arg = arg;
    snprintf (self->token, sizeof self->token, "%s", cfg->token ? cfg->token : "");
    if (cfg->relief_png && cfg->relief_len) {
        if (!(self->relief = malloc (cfg->relief_len))) {
            snprintf (err, errlen, "out of memory");
            goto fail;
        }
        memcpy (self->relief, cfg->relief_png, cfg->relief_len);
        self->relief_len = cfg->relief_len;
    }
    // Its threads (the push thread's, CivetWeb's) take no signals: they stay
    // the main thread's, whose loop stops on them.
    sigset_t all, old;
    sigfillset (&all);
    pthread_sigmask (SIG_BLOCK, &all, &old);
    int started = pthread_create (&self->pusher, NULL, s_pusher, self);
    if (started == 0)
        self->pusher_started = true;
    char ports[96], why[256] = "";
    if (started == 0)
        self->mg = s_start (self, cfg, ports, sizeof ports, why, sizeof why);
    pthread_sigmask (SIG_SETMASK, &old, NULL);
    if (started != 0) {
        snprintf (err, errlen, "cannot start the push thread");
        goto fail;
    }
    if (!self->mg) {
        snprintf (err, errlen, "cannot serve on %s: %s", ports, why[0] ? why : "CivetWeb failed");
        goto fail;
    }
    struct mg_server_port sp[4];
    int n = mg_get_server_ports (self->mg, 4, sp);
    self->port = n > 0 ? sp[0].port : cfg->port;
    mg_set_request_handler (self->mg, "/relief.png$", s_relief, self);
    mg_set_request_handler (self->mg, "/image/latest.png$", s_image, self);
    mg_set_websocket_handler (self->mg, "/ws$", s_ws_connect, s_ws_ready, s_ws_data, s_ws_close,
                              self);
    return self;
fail:
    st_web_destroy (&self);
    return NULL;
}

void st_web_destroy (st_web_t **self_p)
{
    st_web_t *self = self_p ? *self_p : NULL;
    if (!self)
        return;
    if (self->pusher_started) {
        pthread_mutex_lock (&self->lock);
        self->stopping = true;
        pthread_cond_signal (&self->wake);
        pthread_mutex_unlock (&self->lock);
        pthread_join (self->pusher, NULL);
    }
    if (self->mg) {
        mg_stop (self->mg); // closes every page (their close handlers run)
        mg_exit_library ();
    }
    free (self->picture);
    free (self->last);
    free (self->hello_operator);
    free (self->hello_viewer);
    free (self->relief);
    pthread_cond_destroy (&self->wake);
    pthread_mutex_destroy (&self->lock);
    free (self);
    *self_p = NULL;
}

int st_web_port (const st_web_t *self)
{
    return self->port;
}

int st_web_set_hello (st_web_t *self, const char *hello_operator, const char *hello_viewer)
{
    char *a = strdup (hello_operator), *b = strdup (hello_viewer);
    if (!a || !b) {
        free (a);
        free (b);
        return -ENOMEM;
    }
    pthread_mutex_lock (&self->lock);
    free (self->hello_operator);
    free (self->hello_viewer);
    self->hello_operator = a;
    self->hello_viewer = b;
    pthread_mutex_unlock (&self->lock);
    return 0;
}

void st_web_publish (st_web_t *self, char *json, size_t len)
{
    pthread_mutex_lock (&self->lock);
    if (self->picture)
        self->stats.skipped++;
    free (self->picture);
    self->picture = json;
    self->picture_len = len;
    pthread_cond_signal (&self->wake);
    pthread_mutex_unlock (&self->lock);
}

void st_web_set_image (st_web_t *self, const char *path)
{
    pthread_mutex_lock (&self->lock);
    snprintf (self->image_path, sizeof self->image_path, "%s", path ? path : "");
    pthread_mutex_unlock (&self->lock);
}

int st_web_send (st_web_conn_t *conn, const char *text, size_t len)
{
    // From the page's own thread: CivetWeb's connection lock orders it with the pushes.
    return mg_websocket_write (conn->mg, MG_WEBSOCKET_OPCODE_TEXT, text, len) > 0 ? 0 : -EPIPE;
}

void *st_web_conn_user (const st_web_conn_t *conn)
{
    return conn->user;
}

void st_web_conn_set_user (st_web_conn_t *conn, void *user)
{
    conn->user = user;
}

const char *st_web_conn_peer (const st_web_conn_t *conn)
{
    return conn->peer;
}

void st_web_stats (st_web_t *self, st_web_stats_t *ret, char *err, size_t errlen)
{
    pthread_mutex_lock (&self->lock);
    *ret = self->stats;
    if (err && errlen)
        snprintf (err, errlen, "%s", self->last_error);
    pthread_mutex_unlock (&self->lock);
}
