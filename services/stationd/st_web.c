/* st_web — the embedded web server (see st_web.h). */
#include "st_web.h"

#include "st_params.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdarg.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define S_PATH_MAX           4096
#define S_REQUEST_MAX        4096        // bytes of one page message
#define S_VIDEO_QUEUE_FRAMES 64          // video frames waiting for one page, at most,
#define S_VIDEO_QUEUE_BYTES  (1 << 20)   // their bytes,
#define S_VIDEO_BEHIND_S     1.0         // and the wall seconds the oldest has waited
#define S_VIDEO_SNDBUF       (128 << 10) // a video page's socket send buffer, bytes

struct st_web_conn {
    st_web_t *web;
    struct mg_connection *mg;
    bool operator;
    bool listed;   // in the push list, guarded by the web's lock
    bool closing;  // its close handler runs: no new pushes (lock)
    int refs;      // pushes in flight to it (lock)
    bool broken;   // a write failed (atomic): it is being closed
    void *user;    // the request function's
    char peer[64]; // remote address
    st_web_conn_t *next;
};

/* One video frame's bytes, shared by the queues of every page it goes to. */
typedef struct {
    int refs;    // queues holding it, or its writer (web lock)
    double at_s; // when it was queued, monotonic seconds
    size_t len;
    uint8_t data[];
} s_vframe_t;

/* A /video page: its queue and its writer thread. */
typedef struct s_vpage s_vpage_t;
struct s_vpage {
    st_web_t *web;
    struct mg_connection *mg;
    pthread_t writer;
    bool writer_started;
    pthread_cond_t wake;                     // a frame queued, or the end (web lock)
    s_vframe_t *queue[S_VIDEO_QUEUE_FRAMES]; // oldest at head (web lock)
    size_t head, count, bytes;               // (web lock)
    bool synced;                             // a keyframe and all since were queued (web lock)
    bool behind;                             // it fell behind and waits for a keyframe (web lock)
    bool closing;                            // its close handler runs (web lock)
    bool ended;                              // its writer ended: nothing more queued (web lock)
    bool restart;                            // the stream changed: close it (web lock)
    s_vpage_t *next;
};

struct st_web {
    struct mg_context *mg;
    st_web_request_fn *request;
    st_web_close_fn *close_fn;
    void *arg;
    char token[260];
    int port;
    bool loopback; // listens on a loopback address: Host is checked
    int max_pages;
    uint8_t *relief;
    size_t relief_len;
    char *hello_operator, *hello_viewer; // set before serving, never changed
    pthread_mutex_t lock;                // everything below
    pthread_cond_t wake;                 // a new picture, or stop
    pthread_cond_t idle;                 // a push round let go of its pages
    pthread_t pusher;
    bool pusher_started, stopping;
    st_web_conn_t *conns; // pages that are ready
    s_vpage_t *vpages;    // video pages that are ready
    char *picture;        // newest picture not yet pushed (owned)
    size_t picture_len;
    char *last; // a copy of the picture pushed last, for new pages (owned)
    size_t last_len;
    char image_path[S_PATH_MAX];
    st_web_stats_t stats;
    pthread_mutex_t error_lock; // last_error alone: CivetWeb's log callback may
    char last_error[256];       // run inside any CivetWeb call
};

static double s_now (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void s_error (st_web_t *self, const char *fmt, ...) __attribute__ ((format (printf, 2, 3)));
static void s_error (st_web_t *self, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    pthread_mutex_lock (&self->error_lock);
    vsnprintf (self->last_error, sizeof self->last_error, fmt, ap);
    pthread_mutex_unlock (&self->error_lock);
    va_end (ap);
}

static int s_log (const struct mg_connection *conn, const char *message)
{
    st_web_t *self = mg_get_user_data (mg_get_context (conn));
    if (self)
        s_error (self, "%s", message);
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

/* On a loopback server, Host must name this machine's loopback: another
 * name that resolves here is a DNS-rebinding page from elsewhere. */
static bool s_host_ok (const st_web_t *self, const char *host)
{
    if (!self->loopback)
        return true; // reachable by its names; the token guards the commands
    if (!host)
        return false;
    static const char *const names[] = {"127.0.0.1", "localhost", "[::1]"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        size_t n = strlen (names[i]);
        if (strncasecmp (host, names[i], n) != 0)
            continue;
        if (host[n] == '\0')
            return self->port == 80;
        char *end;
        long port = host[n] == ':' ? strtol (host + n + 1, &end, 10) : -1;
        if (port == self->port && *end == '\0')
            return true;
    }
    return false;
}

/* Whether a WebSocket (/ws or /video) may open: its Origin is the Host it
 * asked, that Host is this server's (on loopback), and fewer WebSockets
 * than max_pages are open. A refusal is counted and kept as the last error. */
static bool s_ws_admit (st_web_t *self, const struct mg_connection *conn, const char *what)
{
    const struct mg_request_info *ri = mg_get_request_info (conn);
    const char *origin = mg_get_header (conn, "Origin");
    const char *host = mg_get_header (conn, "Host");
    // Browsers always send Origin; other tools (tests, scripts) may not.
    bool foreign = origin && (!host || strcasecmp (s_origin_host (origin), host) != 0);
    if (foreign || !s_host_ok (self, host)) {
        pthread_mutex_lock (&self->lock);
        self->stats.refused++;
        pthread_mutex_unlock (&self->lock);
        s_error (self, "refused a %s WebSocket from %s: %s %s is not this server", what,
                 ri->remote_addr, foreign ? "Origin" : "Host",
                 foreign ? origin
                 : host  ? host
                         : "(none)");
        return false;
    }
    pthread_mutex_lock (&self->lock);
    bool full = self->stats.pages + self->stats.video_pages >= (uint64_t)self->max_pages;
    if (full)
        self->stats.full++;
    pthread_mutex_unlock (&self->lock);
    if (full) {
        s_error (self,
                 "refused a %s WebSocket from %s: %d WebSockets are open, as many as the "
                 "threads allow",
                 what, ri->remote_addr, self->max_pages);
        return false;
    }
    return true;
}

static int s_ws_connect (const struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    const struct mg_request_info *ri = mg_get_request_info (conn);
    if (!s_ws_admit (self, conn, "page"))
        return 1;
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

/* Write text to a page, never under the web's lock (CivetWeb takes the
 * connection's own). A write that fails, or falls short, breaks the page:
 * it gets a close frame and no more pushes. 0 or -EPIPE. */
static int s_write (st_web_conn_t *c, const char *text, size_t len)
{
    if (__atomic_load_n (&c->broken, __ATOMIC_ACQUIRE))
        return -EPIPE;
    int n = mg_websocket_write (c->mg, MG_WEBSOCKET_OPCODE_TEXT, text, len);
    if (n > 0 && (size_t)n >= len)
        return 0;
    __atomic_store_n (&c->broken, true, __ATOMIC_RELEASE);
    mg_websocket_write (c->mg, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, "", 0);
    return -EPIPE;
}

/* A malloc'd copy of text, or NULL. */
static char *s_dup (const char *text, size_t len)
{
    char *d = text ? malloc (len + 1) : NULL;
    if (d) {
        memcpy (d, text, len);
        d[len] = '\0';
    }
    return d;
}

static void s_ws_ready (struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    st_web_conn_t *c = mg_get_user_connection_data (conn);
    if (!c)
        return;
    c->mg = conn;
    // The hello and the latest picture first, then the pushes: in that order.
    const char *hello = c->operator? self->hello_operator : self->hello_viewer;
    if (hello)
        s_write (c, hello, strlen (hello));
    pthread_mutex_lock (&self->lock);
    size_t len = self->last_len;
    char *last = self->last ? s_dup (self->last, len) : NULL;
    pthread_mutex_unlock (&self->lock);
    if (last)
        s_write (c, last, len);
    free (last);
    pthread_mutex_lock (&self->lock);
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
    if (c && __atomic_load_n (&c->broken, __ATOMIC_ACQUIRE))
        return 0; // a write to it failed: close it
    if (!c || (opcode != MG_WEBSOCKET_OPCODE_TEXT && opcode != MG_WEBSOCKET_OPCODE_CONTINUATION))
        return 1; // pings, pongs and binary frames: nothing to do
    pthread_mutex_lock (&self->lock);
    self->stats.requests++;
    bool refuse = len > S_REQUEST_MAX || !(flags & 0x80) || opcode != MG_WEBSOCKET_OPCODE_TEXT;
    if (refuse)
        self->stats.oversized++;
    pthread_mutex_unlock (&self->lock);
    if (refuse) {
        static const char why[] = "{\"type\":\"error\",\"error\":\"a message must be one text "
                                  "frame of at most 4096 bytes\"}";
        st_web_send (c, why, sizeof why - 1);
        return 1;
    }
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
    c->closing = true;
    for (st_web_conn_t **p = &self->conns; *p; p = &(*p)->next)
        if (*p == c) {
            *p = c->next;
            self->stats.pages--;
            break;
        }
    while (c->refs > 0) // a push round is writing to it: wait until it is done
        pthread_cond_wait (&self->idle, &self->lock);
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
    // Only a regular file named latest.png (not a link): the path comes off the bus.
    // imagerd replaces it by renaming a new file over it, so it is opened once
    // and sent from that one open file: its size and its bytes agree.
    const char *base = strrchr (path, '/');
    int fd = path[0] && base && strcmp (base, "/latest.png") == 0
                 ? open (path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC)
                 : -1;
    struct stat st;
    uint8_t *png = NULL;
    bool ok = fd >= 0 && fstat (fd, &st) == 0 && S_ISREG (st.st_mode) && st.st_size > 0 &&
              st.st_size <= (off_t)64 << 20 && (png = malloc ((size_t)st.st_size)) &&
              read (fd, png, (size_t)st.st_size) == (ssize_t)st.st_size;
    if (fd >= 0)
        close (fd);
    if (!ok) {
        free (png);
        mg_send_http_error (conn, 404, "%s", "no sensor image yet");
        return 404;
    }
    mg_send_http_ok (conn, "image/png", (long long)st.st_size); // with no-cache headers
    mg_write (conn, png, (size_t)st.st_size);
    free (png);
    return 200;
}

/* ---- the live video (/video) ------------------------------------------------------ */

/* Let go of a frame (web lock held): freed by its last holder. */
static void s_vframe_release (s_vframe_t *f)
{
    if (--f->refs == 0)
        free (f);
}

/* Drop what waits for a page (web lock held); the number of frames dropped. */
static size_t s_vpage_drain (s_vpage_t *v)
{
    size_t n = v->count;
    for (; v->count > 0; v->count--) {
        s_vframe_release (v->queue[v->head]);
        v->head = (v->head + 1) % S_VIDEO_QUEUE_FRAMES;
    }
    v->head = 0;
    v->bytes = 0;
    return n;
}

/* A video page's writer: its queued frames, oldest first, one binary
 * message each, written with the lock released; until the page closes, a
 * write fails (the page is then closed) or the stream changes (the page is
 * closed, and starts over on the new stream). */
static void *s_video_writer (void *arg)
{
    s_vpage_t *v = arg;
    st_web_t *self = v->web;
    bool failed = false;
    pthread_mutex_lock (&self->lock);
    for (;;) {
        while (!v->count && !v->closing && !v->restart)
            pthread_cond_wait (&v->wake, &self->lock);
        if (v->closing || v->restart)
            break;
        s_vframe_t *f = v->queue[v->head];
        v->head = (v->head + 1) % S_VIDEO_QUEUE_FRAMES;
        v->count--;
        v->bytes -= f->len;
        pthread_mutex_unlock (&self->lock);
        int n =
            mg_websocket_write (v->mg, MG_WEBSOCKET_OPCODE_BINARY, (const char *)f->data, f->len);
        pthread_mutex_lock (&self->lock);
        bool ok = n > 0 && (size_t)n >= f->len;
        if (ok) {
            self->stats.video_sent++;
            self->stats.video_bytes += f->len;
        }
        s_vframe_release (f);
        if (!ok) {
            self->stats.write_errors++;
            failed = true;
            break;
        }
    }
    bool close_it = (failed || v->restart) && !v->closing;
    v->ended = true;
    s_vpage_drain (v);
    pthread_mutex_unlock (&self->lock);
    if (close_it) // the page answers with its own close, and its close handler runs
        mg_websocket_write (v->mg, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, "", 0);
    return NULL;
}

/* The kernel's send buffer of this connection's socket bounded to bytes, so
 * a page that reads slowly is seen behind within about a second (the
 * kernel grows it up to net.core.wmem_max, megabytes: as many seconds of
 * video queued unseen). CivetWeb does not give the socket: it is the one
 * whose peer is the request's remote address and port, and whose own port
 * is this server's. False when none is found. */
static bool s_bound_send_buffer (const st_web_t *self, const struct mg_connection *conn, int bytes)
{
    const struct mg_request_info *ri = mg_get_request_info (conn);
    DIR *d = opendir ("/proc/self/fd");
    if (!d)
        return false;
    bool done = false;
    struct dirent *e;
    while (!done && (e = readdir (d))) {
        char *end;
        long fd = strtol (e->d_name, &end, 10);
        if (end == e->d_name || *end || fd < 0 || fd == dirfd (d))
            continue;
        struct sockaddr_storage peer, own;
        socklen_t pl = sizeof peer, ol = sizeof own;
        if (getpeername ((int)fd, (struct sockaddr *)&peer, &pl) != 0 ||
            getsockname ((int)fd, (struct sockaddr *)&own, &ol) != 0 ||
            peer.ss_family != own.ss_family)
            continue;
        char addr[INET6_ADDRSTRLEN] = "";
        int pport = -1, oport = -1;
        if (peer.ss_family == AF_INET) {
            const struct sockaddr_in *p4 = (const struct sockaddr_in *)&peer;
            inet_ntop (AF_INET, &p4->sin_addr, addr, sizeof addr);
            pport = ntohs (p4->sin_port);
            oport = ntohs (((const struct sockaddr_in *)&own)->sin_port);
        } else if (peer.ss_family == AF_INET6) {
            const struct sockaddr_in6 *p6 = (const struct sockaddr_in6 *)&peer;
            inet_ntop (AF_INET6, &p6->sin6_addr, addr, sizeof addr);
            pport = ntohs (p6->sin6_port);
            oport = ntohs (((const struct sockaddr_in6 *)&own)->sin6_port);
        }
        if (pport != ri->remote_port || oport != self->port || strcmp (addr, ri->remote_addr) != 0)
            continue;
        done = setsockopt ((int)fd, SOL_SOCKET, SO_SNDBUF, &bytes, sizeof bytes) == 0;
        break;
    }
    closedir (d);
    return done;
}

static int s_video_connect (const struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    if (!s_ws_admit (self, conn, "video"))
        return 1;
    s_vpage_t *v = calloc (1, sizeof *v);
    if (!v)
        return 1;
    v->web = self;
    pthread_cond_init (&v->wake, NULL);
    mg_set_user_connection_data (conn, v);
    return 0;
}

static void s_video_ready (struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    s_vpage_t *v = mg_get_user_connection_data (conn);
    if (!v)
        return;
    v->mg = conn;
    if (!s_bound_send_buffer (self, conn, S_VIDEO_SNDBUF))
        s_error (self, "a video page's socket keeps the system's send buffer: a slow page is "
                       "seen behind late");
    // CivetWeb's threads take no signals, nor does this one (it inherits that).
    if (pthread_create (&v->writer, NULL, s_video_writer, v) != 0) {
        s_error (self, "cannot start a video page's writer thread: the page is closed");
        v->ended = true; // not listed: no other thread sees it
        mg_websocket_write (conn, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, "", 0);
        return;
    }
    v->writer_started = true;
    pthread_mutex_lock (&self->lock);
    v->next = self->vpages;
    self->vpages = v;
    self->stats.video_pages++;
    self->stats.video_pages_total++;
    pthread_mutex_unlock (&self->lock);
}

static int s_video_data (struct mg_connection *conn, int flags, char *data, size_t len,
                         void *cbdata)
{
    (void)data;
    (void)len;
    st_web_t *self = cbdata;
    s_vpage_t *v = mg_get_user_connection_data (conn);
    if ((flags & 0xf) == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE || !v)
        return 0;
    pthread_mutex_lock (&self->lock);
    bool ended = v->ended;
    pthread_mutex_unlock (&self->lock);
    return ended ? 0 : 1; // the page says nothing; an ended one is closed
}

static void s_video_close (const struct mg_connection *conn, void *cbdata)
{
    st_web_t *self = cbdata;
    s_vpage_t *v = mg_get_user_connection_data (conn);
    if (!v)
        return;
    pthread_mutex_lock (&self->lock);
    for (s_vpage_t **p = &self->vpages; *p; p = &(*p)->next)
        if (*p == v) {
            *p = v->next;
            self->stats.video_pages--;
            break;
        }
    v->closing = true;
    pthread_cond_signal (&v->wake);
    pthread_mutex_unlock (&self->lock);
    if (v->writer_started) // it ends after the write in hand, if any
        pthread_join (v->writer, NULL);
    pthread_mutex_lock (&self->lock);
    s_vpage_drain (v);
    pthread_mutex_unlock (&self->lock);
    pthread_cond_destroy (&v->wake);
    mg_set_user_connection_data (conn, NULL);
    free (v);
}

void st_web_video_publish (st_web_t *self, const uint8_t *ts, size_t len, bool keyframe)
{
    pthread_mutex_lock (&self->lock);
    self->stats.video_frames++;
    bool any = self->vpages != NULL;
    pthread_mutex_unlock (&self->lock);
    if (!any || !ts || !len)
        return;
    s_vframe_t *f = malloc (sizeof *f + len);
    double now = s_now ();
    pthread_mutex_lock (&self->lock);
    if (f) {
        memcpy (f->data, ts, len);
        f->len = len;
        f->at_s = now;
        f->refs = 1; // this function's, until every queue has it
    }
    for (s_vpage_t *v = self->vpages; v; v = v->next) {
        if (v->closing || v->ended || v->restart)
            continue;
        bool fits = v->count == 0 ||
                    (v->count < S_VIDEO_QUEUE_FRAMES && v->bytes + len <= S_VIDEO_QUEUE_BYTES &&
                     now - v->queue[v->head]->at_s <= S_VIDEO_BEHIND_S);
        if (v->synced && (!fits || !f)) {
            // Behind (or no memory): what waits is dropped; it starts again
            // at the next keyframe.
            self->stats.video_dropped += s_vpage_drain (v);
            self->stats.video_behind++;
            v->synced = false;
            v->behind = true;
        }
        if (!f || (!v->synced && !keyframe)) {
            if (v->behind)
                self->stats.video_dropped++;
            continue; // a new page waits for its first keyframe
        }
        size_t tail = (v->head + v->count) % S_VIDEO_QUEUE_FRAMES;
        v->queue[tail] = f;
        f->refs++;
        v->count++;
        v->bytes += len;
        v->synced = true;
        v->behind = false;
        pthread_cond_signal (&v->wake);
    }
    if (f)
        s_vframe_release (f);
    pthread_mutex_unlock (&self->lock);
}

void st_web_video_restart (st_web_t *self)
{
    pthread_mutex_lock (&self->lock);
    for (s_vpage_t *v = self->vpages; v; v = v->next) {
        if (v->closing || v->ended)
            continue;
        s_vpage_drain (v);
        v->restart = true;
        pthread_cond_signal (&v->wake);
    }
    self->stats.video_restarts++;
    pthread_mutex_unlock (&self->lock);
}

/* The push thread: the newest picture to every page, until stopped. The
 * pages of a round are held (refs) so none is freed while written to, and
 * written with the lock released. */
static void *s_pusher (void *arg)
{
    st_web_t *self = arg;
    st_web_conn_t **round = calloc ((size_t)self->max_pages + 1, sizeof *round);
    pthread_mutex_lock (&self->lock);
    for (;;) {
        while (!self->picture && !self->stopping)
            pthread_cond_wait (&self->wake, &self->lock);
        if (self->stopping)
            break;
        char *pic = self->picture;
        size_t len = self->picture_len;
        self->picture = NULL;
        free (self->last);
        self->last = s_dup (pic, len);
        self->last_len = self->last ? len : 0;
        if (len > self->stats.max_push_bytes)
            self->stats.max_push_bytes = len;
        size_t n = 0;
        for (st_web_conn_t *c = self->conns; c && round && n < (size_t)self->max_pages + 1;
             c = c->next)
            if (!c->closing && !__atomic_load_n (&c->broken, __ATOMIC_ACQUIRE)) {
                c->refs++;
                round[n++] = c;
            }
        pthread_mutex_unlock (&self->lock);
        double t0 = s_now ();
        uint64_t ok = 0, failed = 0;
        for (size_t i = 0; i < n; i++) {
            if (s_write (round[i], pic, len) == 0)
                ok++;
            else
                failed++;
        }
        double took = s_now () - t0;
        free (pic);
        pthread_mutex_lock (&self->lock);
        for (size_t i = 0; i < n; i++)
            round[i]->refs--;
        pthread_cond_broadcast (&self->idle);
        self->stats.pushes += ok;
        self->stats.write_errors += failed;
        self->stats.last_push_s = took;
    }
    pthread_mutex_unlock (&self->lock);
    free (round);
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
    // The page's ES modules as text/javascript (CivetWeb's own type for .js
    // is application/javascript).
    const char *options[] = {"listening_ports",
                             ports,
                             "document_root",
                             cfg->web_root,
                             "num_threads",
                             threads,
                             "enable_directory_listing",
                             "no",
                             "extra_mime_types",
                             ".js=text/javascript",
                             "request_timeout_ms",
                             timeout,
                             "websocket_timeout_ms",
                             "30000",
                             "enable_websocket_ping_pong",
                             "yes",
                             "tcp_nodelay",
                             "1",
                             "additional_header",
                             "X-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\n"
                             "Content-Security-Policy: frame-ancestors 'none'",
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
    pthread_mutex_init (&self->error_lock, NULL);
    pthread_cond_init (&self->wake, NULL);
    pthread_cond_init (&self->idle, NULL);
    self->loopback = st_params_is_loopback (cfg->listen_address);
    self->max_pages = cfg->threads > 4 ? cfg->threads - 2 : 2;
    self->port = cfg->port;
    self->request = request;
    self->close_fn = close_fn;
    self->arg = arg;
    snprintf (self->token, sizeof self->token, "%s", cfg->token ? cfg->token : "");
    self->hello_operator = strdup (cfg->hello_operator ? cfg->hello_operator : "");
    self->hello_viewer = strdup (cfg->hello_viewer ? cfg->hello_viewer : "");
    if (!self->hello_operator || !self->hello_viewer) {
        snprintf (err, errlen, "out of memory");
        goto fail;
    }
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
    mg_set_websocket_handler (self->mg, "/video$", s_video_connect, s_video_ready, s_video_data,
                              s_video_close, self);
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
    pthread_mutex_lock (&self->lock);
    self->stopping = true; // the push thread ends after its round
    pthread_cond_signal (&self->wake);
    pthread_mutex_unlock (&self->lock);
    if (self->mg) {
        // Closes every page: each close handler waits for a round writing to it.
        mg_stop (self->mg);
        mg_exit_library ();
    }
    if (self->pusher_started)
        pthread_join (self->pusher, NULL);
    free (self->picture);
    free (self->last);
    free (self->hello_operator);
    free (self->hello_viewer);
    free (self->relief);
    pthread_cond_destroy (&self->wake);
    pthread_cond_destroy (&self->idle);
    pthread_mutex_destroy (&self->lock);
    pthread_mutex_destroy (&self->error_lock);
    free (self);
    *self_p = NULL;
}

int st_web_port (const st_web_t *self)
{
    return self->port;
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
    return s_write (conn, text, len);
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
    pthread_mutex_unlock (&self->lock);
    if (err && errlen) {
        pthread_mutex_lock (&self->error_lock);
        snprintf (err, errlen, "%s", self->last_error);
        pthread_mutex_unlock (&self->error_lock);
    }
}
