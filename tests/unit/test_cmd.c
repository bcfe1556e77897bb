/* Unit tests of cgs_cmd and cgs_state: replies, duplicates answered from the
 * stored reply (also after the server is recreated from its state file),
 * malformed commands, the timeout error, atomic state files. */
#include "cgs_cmd.h"
#include "cgs_state.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

typedef struct {
    int applied;
    char last[64];
    char detail[64];
} s_app_t;

static void s_handler (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_app_t *app = arg;
    app->applied++;
    snprintf (app->last, sizeof app->last, "%s", cgs_cmd_name (cmd));
    if (cmd->body_case == CGS__COMMAND__BODY_SET_TIME_SCALE &&
        cmd->set_time_scale->time_scale <= 0) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = "time scale must be positive";
        return;
    }
    snprintf (app->detail, sizeof app->detail, "applied %d", app->applied);
    reply->detail = app->detail;
}

/* The service's state as the server saves it with its replies: "applied N". */
static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    s_app_t *app = arg;
    char *text = NULL;
    int n = asprintf (&text, "applied %d", app->applied);
    if (n < 0)
        return -ENOMEM;
    *ret_buf = (uint8_t *)text;
    *ret_len = (size_t)n;
    return 0;
}

typedef struct {
    cgs_cmd_server_t *srv;
    atomic_bool stop;
} s_thread_t;

static void *s_serve (void *arg)
{
    s_thread_t *t = arg;
    while (!atomic_load (&t->stop)) {
        zmq_pollitem_t item = {cgs_cmd_server_socket (t->srv), 0, ZMQ_POLLIN, 0};
        if (zmq_poll (&item, 1, 10) > 0)
            cgs_cmd_server_dispatch (t->srv, 100);
    }
    return NULL;
}

static char s_dir[64];

static int s_setup (void **state)
{
    (void)state;
    snprintf (s_dir, sizeof s_dir, "/tmp/cgs-cmd-XXXXXX");
    return mkdtemp (s_dir) ? 0 : -1;
}

static int s_teardown (void **state)
{
    (void)state;
    char cmd[128];
    snprintf (cmd, sizeof cmd, "rm -rf %s", s_dir);
    return system (cmd);
}

static void test_call_and_duplicates (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    char cache[128], ep[128];
    snprintf (cache, sizeof cache, "%s/srv.replies", s_dir);
    snprintf (ep, sizeof ep, "ipc://%s/srv.cmd", s_dir);
    s_app_t app = {0};
    s_thread_t th = {.srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app)};
    assert_non_null (th.srv);
    cgs_cmd_server_set_save (th.srv, s_save);
    const uint8_t *saved = NULL;
    size_t saved_len = 1;
    cgs_cmd_server_saved_state (th.srv, &saved, &saved_len);
    assert_int_equal (saved_len, 0);
    assert_int_equal (cgs_cmd_server_bind (th.srv, ep), 0);
    pthread_t tid;
    pthread_create (&tid, NULL, s_serve, &th);

    cgs_cmd_client_t *cl = cgs_cmd_client_new (ctx, ep, "tester");
    assert_memory_equal (cgs_cmd_client_id (cl), "tester@", 7);
    Cgs__Ping ping = CGS__PING__INIT;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char err[256] = "";
    assert_int_equal (cgs_cmd_client_call (cl, &cmd, 2000, 3, &reply, err, sizeof err), 0);
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_OK);
    assert_int_equal (reply->command_number, 1);
    assert_string_equal (reply->detail, "applied 1");
    assert_string_equal (reply->server, "srv");
    assert_false (reply->duplicate);
    cgs_cmd_reply_free (&reply);
    assert_null (reply);

    // A refused command gets an explicit error reply.
    Cgs__SetTimeScale ts = CGS__SET_TIME_SCALE__INIT;
    ts.time_scale = -1;
    cmd.body_case = CGS__COMMAND__BODY_SET_TIME_SCALE;
    cmd.set_time_scale = &ts;
    assert_int_equal (cgs_cmd_client_call (cl, &cmd, 2000, 3, &reply, err, sizeof err), 0);
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_ERROR);
    assert_string_equal (reply->error, "time scale must be positive");
    cgs_cmd_reply_free (&reply);
    assert_int_equal (app.applied, 2);

    // The same client id and number again (a retry): answered, not applied.
    void *dealer = zmq_socket (ctx, ZMQ_DEALER);
    assert_int_equal (zmq_connect (dealer, ep), 0);
    Cgs__Command dup = CGS__COMMAND__INIT;
    dup.client_id = (char *)cgs_cmd_client_id (cl);
    dup.command_number = 1;
    dup.body_case = CGS__COMMAND__BODY_PING;
    dup.ping = &ping;
    uint8_t buf[256];
    size_t len = cgs_msg_encode (&dup.base, buf);
    assert_int_equal (zmq_send (dealer, buf, len, 0), (int)len);
    int n = zmq_recv (dealer, buf, sizeof buf, 0);
    assert_true (n > 0);
    ProtobufCMessage *m = NULL;
    assert_int_equal (cgs_msg_decode (&cgs__reply__descriptor, buf, (size_t)n, NULL, &m), 0);
    Cgs__Reply *r = (Cgs__Reply *)m;
    assert_true (r->duplicate);
    assert_string_equal (r->detail, "applied 1");
    cgs_msg_free (&m);
    assert_int_equal (app.applied, 2);

    // Garbage gets BAD_REQUEST and is counted.
    assert_int_equal (zmq_send (dealer, "\xff\xff\xff", 3, 0), 3);
    n = zmq_recv (dealer, buf, sizeof buf, 0);
    assert_int_equal (cgs_msg_decode (&cgs__reply__descriptor, buf, (size_t)n, NULL, &m), 0);
    assert_int_equal (((Cgs__Reply *)m)->status, CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST);
    cgs_msg_free (&m);

    // The same number for another command is not a retry: refused, not applied.
    Cgs__Pause pause = CGS__PAUSE__INIT;
    Cgs__Command reused = CGS__COMMAND__INIT;
    reused.client_id = (char *)cgs_cmd_client_id (cl);
    reused.command_number = 1;
    reused.body_case = CGS__COMMAND__BODY_PAUSE;
    reused.pause = &pause;
    len = cgs_msg_encode (&reused.base, buf);
    assert_int_equal (zmq_send (dealer, buf, len, 0), (int)len);
    n = zmq_recv (dealer, buf, sizeof buf, 0);
    assert_int_equal (cgs_msg_decode (&cgs__reply__descriptor, buf, (size_t)n, NULL, &m), 0);
    assert_int_equal (((Cgs__Reply *)m)->status, CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST);
    assert_non_null (strstr (((Cgs__Reply *)m)->error, "already used for another command"));
    cgs_msg_free (&m);
    assert_int_equal (app.applied, 2);

    atomic_store (&th.stop, true);
    pthread_join (tid, NULL);
    assert_int_equal (cgs_cmd_server_applied (th.srv), 2);
    assert_int_equal (cgs_cmd_server_duplicates (th.srv), 1);
    assert_int_equal (cgs_cmd_server_malformed (th.srv), 2);
    cgs_cmd_server_destroy (&th.srv);

    // A new server over the same state file answers the old command from storage.
    s_app_t app2 = {0};
    th.srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app2);
    th.stop = false;
    assert_string_equal (cgs_cmd_server_load_error (th.srv), "");
    // The state saved with the last reply comes back: both commands were applied.
    cgs_cmd_server_saved_state (th.srv, &saved, &saved_len);
    assert_int_equal (saved_len, strlen ("applied 2"));
    assert_memory_equal (saved, "applied 2", saved_len);
    assert_int_equal (cgs_cmd_server_bind (th.srv, ep), 0);
    pthread_create (&tid, NULL, s_serve, &th);
    // A client that restarted with the same id: its command 1 is a duplicate.
    // (It retries over a fresh socket, since the first send may meet the old
    // server's dead connection.)
    cgs_cmd_client_t *again = cgs_cmd_client_new_exact (ctx, ep, cgs_cmd_client_id (cl), 1);
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    assert_int_equal (cgs_cmd_client_call (again, &cmd, 300, 10, &reply, err, sizeof err), 0);
    assert_true (reply->duplicate);
    assert_string_equal (reply->detail, "applied 1");
    cgs_cmd_reply_free (&reply);
    cgs_cmd_client_destroy (&again);
    assert_int_equal (app2.applied, 0);
    atomic_store (&th.stop, true);
    pthread_join (tid, NULL);
    cgs_cmd_server_destroy (&th.srv);
    cgs_cmd_server_destroy (&th.srv);

    zmq_close (dealer);
    cgs_cmd_client_destroy (&cl);
    zmq_ctx_term (ctx);
}

/* A periodic checkpoint: save_now writes the service's state as it is now. */
static void test_save_now_writes_current_state (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    char cache[128];
    snprintf (cache, sizeof cache, "%s/ckpt.state", s_dir);
    s_app_t app = {.applied = 41};
    cgs_cmd_server_t *srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app);
    cgs_cmd_server_set_save (srv, s_save);
    assert_int_equal (cgs_cmd_server_save_now (srv), 0);
    app.applied = 42;
    assert_int_equal (cgs_cmd_server_save_now (srv), 0);
    cgs_cmd_server_destroy (&srv);
    srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app);
    const uint8_t *saved = NULL;
    size_t len = 0;
    cgs_cmd_server_saved_state (srv, &saved, &len);
    assert_int_equal (len, strlen ("applied 42"));
    assert_memory_equal (saved, "applied 42", len);
    cgs_cmd_server_destroy (&srv);
    // Without a state file there is nothing to write, and that is not an error.
    srv = cgs_cmd_server_new (ctx, "srv", NULL, s_handler, &app);
    assert_int_equal (cgs_cmd_server_save_now (srv), 0);
    cgs_cmd_server_destroy (&srv);
    zmq_ctx_term (ctx);
}

/* A state file that cannot be written: the command is answered NOT_SAVED with
 * the reason, is not stored, and a retry applies it again. */
static void test_unsaved_command_is_not_acknowledged (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    char cache[128], ep[128];
    snprintf (cache, sizeof cache, "%s/blocked.state", s_dir);
    snprintf (ep, sizeof ep, "ipc://%s/blocked.cmd", s_dir);
    s_app_t app = {0};
    s_thread_t th = {.srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app)};
    assert_non_null (th.srv);
    assert_int_equal (mkdir (cache, 0755), 0); // a folder where the file should go
    cgs_cmd_server_set_save (th.srv, s_save);
    assert_int_equal (cgs_cmd_server_bind (th.srv, ep), 0);
    pthread_t tid;
    pthread_create (&tid, NULL, s_serve, &th);
    cgs_cmd_client_t *cl = cgs_cmd_client_new_exact (ctx, ep, "blocked-client", 1);
    Cgs__Ping ping = CGS__PING__INIT;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char err[256];
    assert_int_equal (cgs_cmd_client_call (cl, &cmd, 2000, 3, &reply, err, sizeof err), 0);
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED);
    assert_non_null (strstr (reply->error, "could not be written"));
    cgs_cmd_reply_free (&reply);
    // The same command again (a retry): applied again, since nothing was kept.
    cgs_cmd_client_t *retry = cgs_cmd_client_new_exact (ctx, ep, "blocked-client", 1);
    assert_int_equal (cgs_cmd_client_call (retry, &cmd, 2000, 3, &reply, err, sizeof err), 0);
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED);
    assert_false (reply->duplicate);
    cgs_cmd_reply_free (&reply);
    atomic_store (&th.stop, true);
    pthread_join (tid, NULL);
    assert_int_equal (app.applied, 2);
    assert_int_equal (cgs_cmd_server_write_errors (th.srv), 2);
    assert_non_null (strstr (cgs_cmd_server_last_error (th.srv), "blocked.state"));
    cgs_cmd_server_destroy (&th.srv);
    cgs_cmd_client_destroy (&cl);
    cgs_cmd_client_destroy (&retry);
    zmq_ctx_term (ctx);
}

/* A state file that exists but cannot be read stops the server from
 * starting (rather than starting empty and losing it). */
static void test_unreadable_state_refuses_to_start (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    char cache[128];
    snprintf (cache, sizeof cache, "%s/unreadable.state", s_dir);
    assert_int_equal (mkdir (cache, 0755), 0); // reading a folder fails with EISDIR
    s_app_t app = {0};
    errno = 0;
    assert_null (cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app));
    assert_int_equal (errno, EISDIR);
    zmq_ctx_term (ctx);
}

static void test_silence_gives_a_clear_error (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    char ep[128];
    snprintf (ep, sizeof ep, "ipc://%s/nobody.cmd", s_dir);
    cgs_cmd_client_t *cl = cgs_cmd_client_new (ctx, ep, NULL);
    assert_non_null (strchr (cgs_cmd_client_id (cl), ':'));
    Cgs__Ping ping = CGS__PING__INIT;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char err[256] = "";
    assert_int_equal (cgs_cmd_client_call (cl, &cmd, 50, 2, &reply, err, sizeof err), -ETIMEDOUT);
    assert_null (reply);
    assert_non_null (strstr (err, "no reply from ipc://"));
    assert_non_null (strstr (err, "after 2 attempts"));
    cgs_cmd_client_destroy (&cl);
    zmq_ctx_term (ctx);
}

static void test_damaged_cache_is_set_aside (void **state)
{
    (void)state;
    char cache[128], bad[140];
    snprintf (cache, sizeof cache, "%s/damaged.replies", s_dir);
    snprintf (bad, sizeof bad, "%s.bad", cache);
    assert_int_equal (cgs_state_write (cache, "\xff\xff\xff\xff", 4), 0);
    void *ctx = zmq_ctx_new ();
    s_app_t app = {0};
    cgs_cmd_server_t *srv = cgs_cmd_server_new (ctx, "srv", cache, s_handler, &app);
    assert_non_null (srv);
    assert_non_null (strstr (cgs_cmd_server_load_error (srv), "not a command server state file"));
    assert_int_equal (access (bad, F_OK), 0);
    assert_int_equal (access (cache, F_OK), -1);
    cgs_cmd_server_destroy (&srv);
    zmq_ctx_term (ctx);
}

static void test_state_files_are_atomic_and_readable (void **state)
{
    (void)state;
    char path[128];
    snprintf (path, sizeof path, "%s/deep/er/state.bin", s_dir);
    assert_int_equal (cgs_state_write (path, "hello", 5), 0);
    assert_int_equal (cgs_state_write (path, "world!", 6), 0);
    void *data = NULL;
    size_t len = 0;
    assert_int_equal (cgs_state_read (path, 1024, &data, &len), 0);
    assert_int_equal (len, 6);
    assert_string_equal (data, "world!");
    free (data);
    assert_int_equal (cgs_state_read (path, 3, &data, &len), -EFBIG);
    char missing[140];
    snprintf (missing, sizeof missing, "%s/none", s_dir);
    assert_int_equal (cgs_state_read (missing, 10, &data, &len), -ENOENT);
    // No temporary file is left behind.
    char cmd[256];
    snprintf (cmd, sizeof cmd, "test $(ls %s/deep/er | wc -l) -eq 1", s_dir);
    assert_int_equal (system (cmd), 0);
    char buf[8];
    assert_int_equal (cgs_state_path (buf, sizeof buf, "abc", "defgh"), -ENAMETOOLONG);
    assert_int_equal (cgs_state_path (buf, sizeof buf, "ab", "cd"), 0);
    assert_string_equal (buf, "ab/cd");
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_call_and_duplicates),
        cmocka_unit_test (test_save_now_writes_current_state),
        cmocka_unit_test (test_unsaved_command_is_not_acknowledged),
        cmocka_unit_test (test_unreadable_state_refuses_to_start),
        cmocka_unit_test (test_silence_gives_a_clear_error),
        cmocka_unit_test (test_damaged_cache_is_set_aside),
        cmocka_unit_test (test_state_files_are_atomic_and_readable),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
