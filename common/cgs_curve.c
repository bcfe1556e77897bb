/* cgs_curve — CURVE security with a ZAP handler (see cgs_curve.h). */
#include "cgs_curve.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

#define S_KEY     41  // Z85 key and its NUL
#define S_ALLOWED 256 // keys the ZAP handler admits

typedef struct s_peer {
    const cgs_curve_t *curve;
    char server_key[S_KEY];
    struct s_peer *next;
} s_peer_t;

struct cgs_curve {
    char public_key[S_KEY], secret_key[S_KEY]; // this side's pair
    char allowed[S_ALLOWED][S_KEY];
    size_t nallowed;
    void *zap; // REP socket at inproc://zeromq.zap.01
    uint64_t admitted, refused;
    pthread_mutex_t lock; // peers
    s_peer_t *peers;
};

static bool s_z85 (const char *k)
{
    uint8_t bin[32];
    return k && strlen (k) == 40 && zmq_z85_decode (bin, k) != NULL;
}

/* The secret key: the first line of path, 40 Z85 characters. */
static int s_read_secret (const char *path, char ret[S_KEY], char *err, size_t errlen,
                          const char *what)
{
    FILE *f = fopen (path, "r");
    if (!f) {
        snprintf (err, errlen, "%s: cannot read %s: %s", what, path, strerror (errno));
        return -errno;
    }
    char line[128] = "";
    bool got = fgets (line, sizeof line, f) != NULL;
    fclose (f);
    line[strcspn (line, "\r\n")] = '\0';
    if (!got || !s_z85 (line)) {
        snprintf (err, errlen,
                  "%s: %s must hold a CURVE secret key (40 Z85 characters) on its first line", what,
                  path);
        return -EINVAL;
    }
    snprintf (ret, S_KEY, "%s", line);
    return 0;
}

static void s_allow (cgs_curve_t *self, const char *key)
{
    for (size_t i = 0; i < self->nallowed; i++)
        if (strcmp (self->allowed[i], key) == 0)
            return;
    if (self->nallowed < S_ALLOWED)
        snprintf (self->allowed[self->nallowed++], S_KEY, "%s", key);
}

int cgs_curve_load (cgs_exercise_t *ex, const char *instance, cgs_curve_t **ret_curve, char *err,
                    size_t errlen)
{
    *ret_curve = NULL;
    if (!cgs_exercise_uses_curve (ex))
        return 0;
    // The keys themselves were checked when the exercise was loaded.
    const char *path = cgs_exercise_path (ex);
    cgs_curve_t *self = calloc (1, sizeof *self);
    if (!self) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    pthread_mutex_init (&self->lock, NULL);
    int rc = 0;
    for (size_t i = 0; i < cgs_exercise_instance_count (ex); i++)
        s_allow (self, cgs_exercise_instance (ex, i)->public_key);
    if (*cgs_exercise_client_public_key (ex))
        s_allow (self, cgs_exercise_client_public_key (ex));
    for (size_t i = 0; i < cgs_exercise_allowed_count (ex); i++)
        s_allow (self, cgs_exercise_allowed (ex, i));
    // This side's own pair.
    char what[256];
    const char *secret_file;
    if (instance) {
        const cgs_instance_t *in = cgs_exercise_find (ex, instance);
        if (!in) {
            snprintf (err, errlen, "%s: no [service %s]", path, instance);
            rc = -EINVAL;
            goto fail;
        }
        snprintf (what, sizeof what, "%s: [service %s] secret_key_file", path, instance);
        snprintf (self->public_key, S_KEY, "%s", in->public_key);
        secret_file = in->secret_key_file;
    } else {
        if (!*cgs_exercise_client_public_key (ex)) {
            snprintf (err, errlen,
                      "%s: the exercise uses CURVE: give [curve] client_public_key and "
                      "client_secret_key_file for the tools (mscgs keygen)",
                      path);
            rc = -EINVAL;
            goto fail;
        }
        snprintf (what, sizeof what, "%s: [curve] client_secret_key_file", path);
        snprintf (self->public_key, S_KEY, "%s", cgs_exercise_client_public_key (ex));
        secret_file = cgs_exercise_client_secret_key_file (ex);
    }
    if ((rc = s_read_secret (secret_file, self->secret_key, err, errlen, what)) < 0)
        goto fail;
    char derived[S_KEY];
    if (zmq_curve_public (derived, self->secret_key) != 0 ||
        strcmp (derived, self->public_key) != 0) {
        snprintf (err, errlen, "%s: the secret key does not belong to the public key %s", what,
                  self->public_key);
        rc = -EINVAL;
        goto fail;
    }
    *ret_curve = self;
    return 0;
fail:
    cgs_curve_destroy (&self);
    return rc;
}

void cgs_curve_destroy (cgs_curve_t **self_p)
{
    cgs_curve_t *self = self_p ? *self_p : NULL;
    if (!self)
        return;
    if (self->zap)
        zmq_close (self->zap);
    for (s_peer_t *p = self->peers, *next; p; p = next) {
        next = p->next;
        free (p);
    }
    pthread_mutex_destroy (&self->lock);
    memset (self->secret_key, 0, sizeof self->secret_key);
    free (self);
    *self_p = NULL;
}

static int s_opt (void *socket, int option, const void *value, size_t len)
{
    return zmq_setsockopt (socket, option, value, len) == 0 ? 0 : -zmq_errno ();
}

int cgs_curve_server (const cgs_curve_t *self, void *socket)
{
    if (!self)
        return 0;
    int one = 1, rc;
    if ((rc = s_opt (socket, ZMQ_ZAP_DOMAIN, "mscgs", 5)) < 0 ||
        (rc = s_opt (socket, ZMQ_CURVE_SERVER, &one, sizeof one)) < 0 ||
        (rc = s_opt (socket, ZMQ_CURVE_SECRETKEY, self->secret_key, 40)) < 0)
        return rc;
    return 0;
}

int cgs_curve_client (const cgs_curve_t *self, void *socket, const char *server_key)
{
    if (!self)
        return 0;
    if (!s_z85 (server_key))
        return -EINVAL;
    int rc;
    if ((rc = s_opt (socket, ZMQ_CURVE_SERVERKEY, server_key, 40)) < 0 ||
        (rc = s_opt (socket, ZMQ_CURVE_PUBLICKEY, self->public_key, 40)) < 0 ||
        (rc = s_opt (socket, ZMQ_CURVE_SECRETKEY, self->secret_key, 40)) < 0)
        return rc;
    return 0;
}

static int s_peer_hook (void *socket, void *arg)
{
    const s_peer_t *p = arg;
    return cgs_curve_client (p->curve, socket, p->server_key);
}

int cgs_curve_protect_client (cgs_curve_t *self, cgs_cmd_client_t *client, const char *server_key)
{
    if (!self)
        return 0;
    if (!s_z85 (server_key))
        return -EINVAL;
    s_peer_t *p = calloc (1, sizeof *p);
    if (!p)
        return -ENOMEM;
    p->curve = self;
    snprintf (p->server_key, S_KEY, "%s", server_key);
    pthread_mutex_lock (&self->lock);
    p->next = self->peers;
    self->peers = p;
    pthread_mutex_unlock (&self->lock);
    cgs_cmd_client_set_socket_hook (client, s_peer_hook, p);
    return 0;
}

int cgs_curve_zap_bind (cgs_curve_t *self, void *ctx)
{
    if (!self)
        return 0;
    self->zap = zmq_socket (ctx, ZMQ_REP);
    if (!self->zap)
        return -zmq_errno ();
    int linger = 0;
    zmq_setsockopt (self->zap, ZMQ_LINGER, &linger, sizeof linger);
    if (zmq_bind (self->zap, "inproc://zeromq.zap.01") != 0) {
        int rc = -zmq_errno ();
        zmq_close (self->zap);
        self->zap = NULL;
        return rc;
    }
    return 0;
}

void *cgs_curve_zap_socket (cgs_curve_t *self)
{
    return self ? self->zap : NULL;
}

/* One frame of a ZAP request into buf (NUL-terminated when text); its size, or -1. */
static int s_frame (void *socket, char *buf, size_t size, bool *ret_more)
{
    int n = zmq_recv (socket, buf, size - 1, ZMQ_DONTWAIT);
    if (n < 0)
        return -1;
    if ((size_t)n > size - 1)
        n = (int)size - 1; // truncated: ZAP fields are short
    buf[n] = '\0';
    int more = 0;
    size_t ml = sizeof more;
    zmq_getsockopt (socket, ZMQ_RCVMORE, &more, &ml);
    *ret_more = more != 0;
    return n;
}

int cgs_curve_zap_handle (cgs_curve_t *self)
{
    if (!self || !self->zap)
        return 0;
    int handled = 0;
    for (;;) {
        // version, request id, domain, address, identity, mechanism, credentials
        char f[7][256];
        int len[7] = {0};
        bool more = true;
        int k = 0;
        for (; k < 7 && more; k++)
            if ((len[k] = s_frame (self->zap, f[k], sizeof f[k], &more)) < 0)
                break;
        if (k == 0 && len[0] < 0)
            return handled; // nothing waiting
        while (more) {      // extra frames: drain
            char junk[64];
            if (s_frame (self->zap, junk, sizeof junk, &more) < 0)
                break;
        }
        bool ok = false;
        const char *why = "not a CURVE client";
        if (k >= 7 && strcmp (f[0], "1.0") == 0 && strcmp (f[5], "CURVE") == 0 && len[6] == 32) {
            char z85[S_KEY];
            zmq_z85_encode (z85, (const uint8_t *)f[6], 32);
            why = "key not listed in the exercise";
            for (size_t i = 0; i < self->nallowed && !ok; i++)
                ok = strcmp (self->allowed[i], z85) == 0;
        }
        if (ok)
            self->admitted++;
        else
            self->refused++;
        const char *status = ok ? "200" : "400", *text = ok ? "OK" : why;
        zmq_send (self->zap, "1.0", 3, ZMQ_SNDMORE);
        zmq_send (self->zap, k >= 2 ? f[1] : "", k >= 2 ? (size_t)len[1] : 0, ZMQ_SNDMORE);
        zmq_send (self->zap, status, 3, ZMQ_SNDMORE);
        zmq_send (self->zap, text, strlen (text), ZMQ_SNDMORE);
        zmq_send (self->zap, "", 0, ZMQ_SNDMORE); // user id
        zmq_send (self->zap, "", 0, 0);           // metadata
        handled++;
    }
}

uint64_t cgs_curve_admitted (const cgs_curve_t *self)
{
    return self ? self->admitted : 0;
}

uint64_t cgs_curve_refused (const cgs_curve_t *self)
{
    return self ? self->refused : 0;
}

const char *cgs_curve_public_key (const cgs_curve_t *self)
{
    return self ? self->public_key : "";
}
