/* cgs_cmd — command client (DEALER, lazy pirate) and server (ROUTER, stored
 * replies for exactly-once handling). */
#include "cgs_cmd.h"
#include "cgs_bus.h"
#include "cgs_state.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define S_PER_CLIENT  16   // replies kept per client
#define S_MAX_ENTRIES 4096 // replies kept in all
#define S_CACHE_MAX   (64u << 20)

static int64_t s_now_ms (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

const char *cgs_cmd_name (const Cgs__Command *cmd)
{
    const ProtobufCFieldDescriptor *f = protobuf_c_message_descriptor_get_field (
        &cgs__command__descriptor, (unsigned)cmd->body_case);
    return f && cmd->body_case != CGS__COMMAND__BODY__NOT_SET ? f->name : "none";
}

void cgs_cmd_reply_free (Cgs__Reply **reply_p)
{
    cgs_msg_free ((ProtobufCMessage **)reply_p);
}

/* ---- client --------------------------------------------------------------------- */

struct cgs_cmd_client {
    void *ctx;
    void *socket; // NULL between attempts after a timeout
    char endpoint[256];
    char id[128];
    uint64_t next_number;
    int (*hook) (void *socket, void *arg);
    void *hook_arg;
};

static cgs_cmd_client_t *s_client_new (void *ctx, const char *endpoint)
{
    if (!ctx || !endpoint || strlen (endpoint) >= 256) {
        errno = EINVAL;
        return NULL;
    }
    cgs_cmd_client_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->ctx = ctx;
    snprintf (self->endpoint, sizeof self->endpoint, "%s", endpoint);
    self->next_number = 1;
    return self;
}

cgs_cmd_client_t *cgs_cmd_client_new (void *ctx, const char *endpoint, const char *label)
{
    cgs_cmd_client_t *self = s_client_new (ctx, endpoint);
    if (!self)
        return NULL;
    // Unique per process, so a restarted client numbering from 1 again is
    // never taken for a retry of its predecessor.
    char host[64] = "host";
    gethostname (host, sizeof host - 1);
    uint32_t r = 0;
    if (getrandom (&r, sizeof r, 0) != (ssize_t)sizeof r)
        r = (uint32_t)s_now_ms () ^ (uint32_t)getpid ();
    snprintf (self->id, sizeof self->id, "%s@%s:%ld:%08x", label && *label ? label : "client", host,
              (long)getpid (), r);
    return self;
}

cgs_cmd_client_t *cgs_cmd_client_new_exact (void *ctx, const char *endpoint, const char *client_id,
                                            uint64_t first_number)
{
    if (!client_id || !*client_id || strlen (client_id) >= 128 || first_number == 0) {
        errno = EINVAL;
        return NULL;
    }
    cgs_cmd_client_t *self = s_client_new (ctx, endpoint);
    if (!self)
        return NULL;
    snprintf (self->id, sizeof self->id, "%s", client_id);
    self->next_number = first_number;
    return self;
}

void cgs_cmd_client_set_next_number (cgs_cmd_client_t *self, uint64_t n)
{
    if (self && n > 0)
        self->next_number = n;
}

void cgs_cmd_client_destroy (cgs_cmd_client_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    if ((*self_p)->socket)
        zmq_close ((*self_p)->socket);
    free (*self_p);
    *self_p = NULL;
}

const char *cgs_cmd_client_id (const cgs_cmd_client_t *self)
{
    return self->id;
}

void cgs_cmd_client_set_socket_hook (cgs_cmd_client_t *self, int (*hook) (void *, void *),
                                     void *arg)
{
    self->hook = hook;
    self->hook_arg = arg;
}

static int s_client_open (cgs_cmd_client_t *self)
{
    self->socket = zmq_socket (self->ctx, ZMQ_DEALER);
    if (!self->socket)
        return -zmq_errno ();
    int linger = 0;
    zmq_setsockopt (self->socket, ZMQ_LINGER, &linger, sizeof linger);
    // The bus's tcp liveness too: a kept client (guidanced's to uavsim)
    // finds a silent network in seconds, not at TCP's retransmission limit.
    int rc = cgs_bus_set_liveness (self->socket);
    if (rc == 0 && self->hook)
        rc = self->hook (self->socket, self->hook_arg);
    if (rc == 0 && zmq_connect (self->socket, self->endpoint) < 0)
        rc = -zmq_errno ();
    if (rc < 0) {
        zmq_close (self->socket);
        self->socket = NULL;
    }
    return rc;
}

int cgs_cmd_client_call (cgs_cmd_client_t *self, Cgs__Command *cmd, int timeout_ms, int attempts,
                         Cgs__Reply **ret_reply, char *err, size_t errlen)
{
    if (timeout_ms <= 0)
        timeout_ms = CGS_CMD_DEFAULT_TIMEOUT_MS;
    if (attempts <= 0)
        attempts = CGS_CMD_DEFAULT_ATTEMPTS;
    cmd->client_id = self->id;
    cmd->command_number = self->next_number++;
    cmd->sent_wall_time_s = cgs_bus_wall_time ();
    uint8_t *buf = NULL;
    size_t len = 0;
    int rc = cgs_msg_encode_alloc (&cmd->base, &buf, &len);
    cmd->client_id = (char *)protobuf_c_empty_string;
    if (rc < 0)
        return rc;

    for (int attempt = 1; attempt <= attempts; attempt++) {
        if (!self->socket && (rc = s_client_open (self)) < 0) {
            snprintf (err, errlen, "cannot connect to %s: %s", self->endpoint, zmq_strerror (-rc));
            goto done;
        }
        if (zmq_send (self->socket, buf, len, 0) < 0) {
            rc = -zmq_errno ();
            snprintf (err, errlen, "cannot send to %s: %s", self->endpoint, zmq_strerror (-rc));
            goto done;
        }
        int64_t deadline = s_now_ms () + timeout_ms;
        for (;;) {
            int64_t left = deadline - s_now_ms ();
            if (left <= 0)
                break;
            zmq_pollitem_t item = {self->socket, 0, ZMQ_POLLIN, 0};
            int n = zmq_poll (&item, 1, (long)left);
            if (n < 0) {
                rc = -zmq_errno ();
                snprintf (err, errlen, "interrupted waiting for %s", self->endpoint);
                goto done;
            }
            if (n == 0)
                break;
            zmq_msg_t m;
            zmq_msg_init (&m);
            if (zmq_msg_recv (&m, self->socket, ZMQ_DONTWAIT) < 0) {
                zmq_msg_close (&m);
                continue;
            }
            bool more = zmq_msg_more (&m);
            ProtobufCMessage *pm = NULL;
            int drc = more ? -EPROTO
                           : cgs_msg_decode (&cgs__reply__descriptor, zmq_msg_data (&m),
                                             zmq_msg_size (&m), NULL, &pm);
            zmq_msg_close (&m);
            while (more) { // drain frames of a malformed reply
                zmq_msg_init (&m);
                zmq_msg_recv (&m, self->socket, 0);
                more = zmq_msg_more (&m);
                zmq_msg_close (&m);
            }
            if (drc < 0) {
                rc = -EPROTO;
                snprintf (err, errlen, "malformed reply from %s", self->endpoint);
                goto done;
            }
            Cgs__Reply *reply = (Cgs__Reply *)pm;
            if (reply->command_number != cmd->command_number ||
                strcmp (reply->client_id, self->id) != 0) {
                cgs_cmd_reply_free (&reply); // a late reply to an earlier command
                continue;
            }
            *ret_reply = reply;
            rc = 0;
            goto done;
        }
        // Silence: drop the socket and whatever it still queues, then retry.
        zmq_close (self->socket);
        self->socket = NULL;
    }
    rc = -ETIMEDOUT;
    snprintf (err, errlen,
              "no reply from %s after %d attempt%s over %.1f s (is the service running?)",
              self->endpoint, attempts, attempts == 1 ? "" : "s", attempts * timeout_ms / 1000.0);
done:
    free (buf);
    return rc;
}

/* ---- server --------------------------------------------------------------------- */

typedef struct {
    Cgs__Reply *reply; // owned copy, as sent
    uint64_t tick;     // last use, for eviction
} s_entry_t;

struct cgs_cmd_server {
    void *socket;
    char name[128];
    char *cache_path;
    cgs_cmd_handler_fn *handler;
    cgs_cmd_save_fn *save;
    void *arg;
    uint8_t *saved_state; // service state loaded at start
    size_t saved_len;
    s_entry_t *entries;
    size_t nentries;
    uint64_t tick;
    char load_error[256];
    char last_error[512]; // the latest failure to write the state file
    uint64_t applied, duplicates, malformed, write_errors;
};

static int s_cache_write (cgs_cmd_server_t *self);

static void s_entries_free (cgs_cmd_server_t *self)
{
    for (size_t i = 0; i < self->nentries; i++)
        cgs_cmd_reply_free (&self->entries[i].reply);
    self->nentries = 0;
}

void cgs_cmd_server_destroy (cgs_cmd_server_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_cmd_server_t *self = *self_p;
    if (self->socket)
        zmq_close (self->socket);
    s_entries_free (self);
    free (self->entries);
    free (self->cache_path);
    free (self->saved_state);
    free (self);
    *self_p = NULL;
}

/* Load the state file: 0 (also when absent, or damaged and set aside), or
 * -errno when it cannot be read. */
static int s_cache_load (cgs_cmd_server_t *self)
{
    void *data = NULL;
    size_t len = 0;
    int rc = cgs_state_read (self->cache_path, S_CACHE_MAX, &data, &len);
    if (rc == -ENOENT)
        return 0;
    ProtobufCMessage *m = NULL;
    if (rc == 0)
        rc = cgs_msg_decode (&cgs__reply_cache__descriptor, data, len, NULL, &m);
    free (data);
    if (rc < 0 && rc != -EPROTO)
        return rc; // cannot read it (permissions, I/O): refuse to start rather than lose it
    if (rc < 0) {
        char bad[4200];
        snprintf (bad, sizeof bad, "%s.bad", self->cache_path);
        rename (self->cache_path, bad);
        snprintf (self->load_error, sizeof self->load_error, "%s: %s; set aside as %s",
                  self->cache_path, "not a command server state file", bad);
        return 0;
    }
    Cgs__ReplyCache *cache = (Cgs__ReplyCache *)m;
    if (cache->service_state.len > 0) {
        self->saved_state = malloc (cache->service_state.len);
        if (self->saved_state) {
            memcpy (self->saved_state, cache->service_state.data, cache->service_state.len);
            self->saved_len = cache->service_state.len;
        }
    }
    size_t n = cache->n_replies < S_MAX_ENTRIES ? cache->n_replies : S_MAX_ENTRIES;
    for (size_t i = 0; i < n; i++) {
        self->entries[self->nentries].reply = cache->replies[i];
        self->entries[self->nentries].tick = ++self->tick;
        cache->replies[i] = NULL; // ownership moves to the entry
        self->nentries++;
    }
    // Free the container and any replies past the limit.
    for (size_t i = n; i < cache->n_replies; i++)
        cgs_cmd_reply_free (&cache->replies[i]);
    cache->n_replies = 0;
    cgs_msg_free (&m);
    return 0;
}

cgs_cmd_server_t *cgs_cmd_server_new (void *ctx, const char *name, const char *cache_path,
                                      cgs_cmd_handler_fn *handler, void *arg)
{
    if (!ctx || !handler) {
        errno = EINVAL;
        return NULL;
    }
    cgs_cmd_server_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    snprintf (self->name, sizeof self->name, "%s", name ? name : "");
    self->handler = handler;
    self->arg = arg;
    self->entries = calloc (S_MAX_ENTRIES, sizeof *self->entries);
    if (!self->entries)
        goto fail;
    if (cache_path) {
        self->cache_path = strdup (cache_path);
        if (!self->cache_path)
            goto fail;
        int rc = s_cache_load (self);
        if (rc < 0) {
            errno = -rc;
            goto fail;
        }
    }
    self->socket = zmq_socket (ctx, ZMQ_ROUTER);
    if (!self->socket)
        goto fail;
    int linger = 0, mandatory = 0;
    zmq_setsockopt (self->socket, ZMQ_LINGER, &linger, sizeof linger);
    // A client that went away loses its reply silently; it will retry.
    zmq_setsockopt (self->socket, ZMQ_ROUTER_MANDATORY, &mandatory, sizeof mandatory);
    // A client's connection over a network gone silent is dropped in seconds.
    int rc = cgs_bus_set_liveness (self->socket);
    if (rc < 0) {
        errno = -rc;
        goto fail;
    }
    return self;
fail:;
    int saved = errno ? errno : ENOMEM;
    cgs_cmd_server_destroy (&self);
    errno = saved;
    return NULL;
}

int cgs_cmd_server_bind (cgs_cmd_server_t *self, const char *endpoint)
{
    int rc = cgs_bus_prepare_endpoint (endpoint);
    if (rc < 0)
        return rc;
    if (zmq_bind (self->socket, endpoint) < 0)
        return -zmq_errno ();
    return 0;
}

void *cgs_cmd_server_socket (cgs_cmd_server_t *self)
{
    return self->socket;
}

void cgs_cmd_server_set_save (cgs_cmd_server_t *self, cgs_cmd_save_fn *save)
{
    self->save = save;
}

int cgs_cmd_server_save_now (cgs_cmd_server_t *self)
{
    int rc = s_cache_write (self);
    if (rc < 0)
        self->write_errors++;
    return rc;
}

void cgs_cmd_server_saved_state (const cgs_cmd_server_t *self, const uint8_t **ret_buf,
                                 size_t *ret_len)
{
    *ret_buf = self->saved_state;
    *ret_len = self->saved_len;
}
const char *cgs_cmd_server_load_error (const cgs_cmd_server_t *self)
{
    return self->load_error;
}
uint64_t cgs_cmd_server_applied (const cgs_cmd_server_t *self)
{
    return self->applied;
}
uint64_t cgs_cmd_server_duplicates (const cgs_cmd_server_t *self)
{
    return self->duplicates;
}
uint64_t cgs_cmd_server_malformed (const cgs_cmd_server_t *self)
{
    return self->malformed;
}
const char *cgs_cmd_server_last_error (const cgs_cmd_server_t *self)
{
    return self->last_error;
}
uint64_t cgs_cmd_server_write_errors (const cgs_cmd_server_t *self)
{
    return self->write_errors;
}

static s_entry_t *s_find (cgs_cmd_server_t *self, const char *client, uint64_t number)
{
    for (size_t i = 0; i < self->nentries; i++) {
        Cgs__Reply *r = self->entries[i].reply;
        if (r->command_number == number && strcmp (r->client_id, client) == 0)
            return &self->entries[i];
    }
    return NULL;
}

/* Keep a copy of reply; evict the client's oldest beyond S_PER_CLIENT and the
 * overall oldest beyond S_MAX_ENTRIES. */
static int s_store (cgs_cmd_server_t *self, const uint8_t *packed, size_t len)
{
    ProtobufCMessage *m = NULL;
    int rc = cgs_msg_decode (&cgs__reply__descriptor, packed, len, NULL, &m);
    if (rc < 0)
        return rc;
    Cgs__Reply *copy = (Cgs__Reply *)m;
    size_t mine = 0, oldest_mine = SIZE_MAX, oldest = 0;
    for (size_t i = 0; i < self->nentries; i++) {
        if (self->entries[i].tick < self->entries[oldest].tick)
            oldest = i;
        if (strcmp (self->entries[i].reply->client_id, copy->client_id) == 0) {
            mine++;
            if (oldest_mine == SIZE_MAX || self->entries[i].tick < self->entries[oldest_mine].tick)
                oldest_mine = i;
        }
    }
    size_t slot = self->nentries;
    if (mine >= S_PER_CLIENT)
        slot = oldest_mine;
    else if (self->nentries == S_MAX_ENTRIES)
        slot = oldest;
    if (slot < self->nentries)
        cgs_cmd_reply_free (&self->entries[slot].reply);
    else
        self->nentries++;
    self->entries[slot].reply = copy;
    self->entries[slot].tick = ++self->tick;
    return (int)slot;
}

/* Drop stored reply slot (its state could not be saved, so it was never acknowledged). */
static void s_forget (cgs_cmd_server_t *self, size_t slot)
{
    cgs_cmd_reply_free (&self->entries[slot].reply);
    self->entries[slot] = self->entries[--self->nentries];
    self->entries[self->nentries].reply = NULL;
}

/* FNV-1a digest of a command's body (the command without its id, number and
 * time), so a reused command number with another body is caught. */
static uint64_t s_digest (Cgs__Command *cmd)
{
    char *id = cmd->client_id;
    uint64_t number = cmd->command_number;
    double sent = cmd->sent_wall_time_s;
    cmd->client_id = (char *)protobuf_c_empty_string;
    cmd->command_number = 0;
    cmd->sent_wall_time_s = 0;
    uint8_t *buf = NULL;
    size_t len = 0;
    uint64_t h = 1469598103934665603ull;
    if (cgs_msg_encode_alloc (&cmd->base, &buf, &len) == 0)
        for (size_t i = 0; i < len; i++) {
            h ^= buf[i];
            h *= 1099511628211ull;
        }
    free (buf);
    cmd->client_id = id;
    cmd->command_number = number;
    cmd->sent_wall_time_s = sent;
    return h;
}

/* Write the stored replies and the service's state in one atomic write. */
static int s_cache_write (cgs_cmd_server_t *self)
{
    if (!self->cache_path)
        return 0;
    Cgs__Reply **arr = malloc ((self->nentries ? self->nentries : 1) * sizeof *arr);
    if (!arr)
        return -ENOMEM;
    for (size_t i = 0; i < self->nentries; i++)
        arr[i] = self->entries[i].reply;
    Cgs__ReplyCache cache = CGS__REPLY_CACHE__INIT;
    cache.n_replies = self->nentries;
    cache.replies = arr;
    uint8_t *state = NULL;
    size_t state_len = 0;
    int rc = self->save ? self->save (self->arg, &state, &state_len) : 0;
    if (rc == 0) {
        cache.service_state.data = state;
        cache.service_state.len = state_len;
        uint8_t *buf = NULL;
        size_t len = 0;
        rc = cgs_msg_encode_alloc (&cache.base, &buf, &len);
        if (rc == 0)
            rc = cgs_state_write (self->cache_path, buf, len);
        free (buf);
    }
    free (state);
    free (arr);
    return rc;
}

static void s_send_reply (cgs_cmd_server_t *self, zmq_msg_t *identity, const uint8_t *buf,
                          size_t len)
{
    zmq_send (self->socket, zmq_msg_data (identity), zmq_msg_size (identity), ZMQ_SNDMORE);
    zmq_send (self->socket, buf, len, 0);
}

static void s_handle (cgs_cmd_server_t *self, zmq_msg_t *identity, zmq_msg_t *payload, bool extra)
{
    Cgs__Reply reply = CGS__REPLY__INIT;
    reply.server = self->name;
    ProtobufCMessage *m = NULL;
    uint8_t *buf = NULL;
    size_t len = 0;
    if (extra || cgs_msg_decode (&cgs__command__descriptor, zmq_msg_data (payload),
                                 zmq_msg_size (payload), NULL, &m) < 0) {
        self->malformed++;
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST;
        reply.error = "malformed command: not a cgs.Command";
        if (cgs_msg_encode_alloc (&reply.base, &buf, &len) == 0)
            s_send_reply (self, identity, buf, len);
        free (buf);
        return;
    }
    Cgs__Command *cmd = (Cgs__Command *)m;
    uint64_t digest = s_digest (cmd);
    s_entry_t *e = s_find (self, cmd->client_id, cmd->command_number);
    if (e && e->reply->body_digest != digest) {
        // Not a retry: the client reused a number for another command.
        self->malformed++;
        char why[300];
        snprintf (why, sizeof why,
                  "command number %llu of client %s was already used for another command",
                  (unsigned long long)cmd->command_number, cmd->client_id);
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST;
        reply.error = why;
        reply.client_id = cmd->client_id;
        reply.command_number = cmd->command_number;
        if (cgs_msg_encode_alloc (&reply.base, &buf, &len) == 0)
            s_send_reply (self, identity, buf, len);
        free (buf);
        cgs_msg_free (&m);
        return;
    }
    if (e) {
        self->duplicates++;
        e->tick = ++self->tick;
        e->reply->duplicate = true;
        if (cgs_msg_encode_alloc (&e->reply->base, &buf, &len) == 0)
            s_send_reply (self, identity, buf, len);
        e->reply->duplicate = false;
        free (buf);
        cgs_msg_free (&m);
        return;
    }
    if (!*cmd->client_id || cmd->command_number == 0) {
        self->malformed++;
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST;
        reply.error = "command without client id or command number";
    } else if (cmd->body_case == CGS__COMMAND__BODY__NOT_SET) {
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        reply.error = "empty command (this server may be older than the client)";
    } else {
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_OK;
        self->handler (self->arg, cmd, &reply);
        self->applied++;
    }
    reply.client_id = cmd->client_id;
    reply.command_number = cmd->command_number;
    reply.server = self->name;
    reply.body_digest = digest;
    bool applied = reply.status == CGS__REPLY_STATUS__REPLY_STATUS_OK ||
                   reply.status == CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    // Store the reply, then write it with the service's state before acknowledging.
    // If that fails the reply is not kept and says so: a retry tries again.
    int slot = -ENOMEM;
    if (applied && cgs_msg_encode_alloc (&reply.base, &buf, &len) == 0)
        slot = s_store (self, buf, len);
    int rc = applied ? (slot >= 0 ? s_cache_write (self) : slot) : 0;
    if (rc < 0) {
        if (slot >= 0)
            s_forget (self, (size_t)slot);
        self->write_errors++;
        snprintf (self->last_error, sizeof self->last_error,
                  "command %s #%llu from %s applied, but the state file %s could not be written: "
                  "%s",
                  cgs_cmd_name (cmd), (unsigned long long)cmd->command_number, cmd->client_id,
                  self->cache_path ? self->cache_path : "(none)", strerror (-rc));
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED;
        reply.error = self->last_error;
    }
    free (buf);
    buf = NULL;
    if (cgs_msg_encode_alloc (&reply.base, &buf, &len) == 0)
        s_send_reply (self, identity, buf, len);
    free (buf);
    cgs_msg_free (&m);
}

int cgs_cmd_server_dispatch (cgs_cmd_server_t *self, int max)
{
    int count = 0;
    while (count < max) {
        zmq_msg_t identity, payload;
        zmq_msg_init (&identity);
        if (zmq_msg_recv (&identity, self->socket, ZMQ_DONTWAIT) < 0) {
            int e = zmq_errno ();
            zmq_msg_close (&identity);
            return e == EAGAIN ? count : (count ? count : -e);
        }
        count++;
        if (!zmq_msg_more (&identity)) { // cannot happen on ROUTER; be safe
            zmq_msg_close (&identity);
            continue;
        }
        zmq_msg_init (&payload);
        zmq_msg_recv (&payload, self->socket, 0);
        bool extra = zmq_msg_more (&payload);
        if (extra) { // drain the frames of a malformed command
            zmq_msg_t drain;
            zmq_msg_init (&drain);
            do
                zmq_msg_recv (&drain, self->socket, 0);
            while (zmq_msg_more (&drain));
            zmq_msg_close (&drain);
        }
        s_handle (self, &identity, &payload, extra);
        zmq_msg_close (&payload);
        zmq_msg_close (&identity);
    }
    return count;
}
