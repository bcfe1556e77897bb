/* Unit tests of cgs_service: the constructor's return convention (--version,
 * a bad option, an unknown instance), what the accessors report with --check
 * and for a running service, and the one-process-per-instance lock. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_service.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct {
    char dir[64];    // a fresh temporary folder
    char path[128];  // dir/ex.ini
    char state[128]; // dir/state
} s_tmp_t;

static int s_setup (void **state)
{
    s_tmp_t *t = calloc (1, sizeof *t);
    if (!t)
        return -1;
    snprintf (t->dir, sizeof t->dir, "/tmp/test_service.XXXXXX");
    if (!mkdtemp (t->dir)) {
        free (t);
        return -1;
    }
    snprintf (t->path, sizeof t->path, "%s/ex.ini", t->dir);
    snprintf (t->state, sizeof t->state, "%s/state", t->dir);
    FILE *f = fopen (t->path, "w");
    if (!f) {
        rmdir (t->dir);
        free (t);
        return -1;
    }
    fputs ("[exercise]\n"
           "origin = geo 35.96 -121.23 0\n"
           "time_scale = 4\n"
           "[service trackerd]\n"
           "publish = inproc://test_service.trackerd\n"
           "[service trackerd.b]\n"
           "publish = inproc://test_service.trackerd.b\n"
           "params = /etc/mscgs/trk.ini\n",
           f);
    fclose (f);
    *state = t;
    return 0;
}

static int s_teardown (void **state)
{
    s_tmp_t *t = *state;
    char path[160];
    snprintf (path, sizeof path, "%s/trackerd.lock", t->state);
    unlink (path);
    snprintf (path, sizeof path, "%s/trackerd.fault", t->state); // the debug build's
    unlink (path);
    rmdir (t->state);
    unlink (t->path);
    rmdir (t->dir);
    free (t);
    return 0;
}

static const cgs_service_info_t s_info = {.program = "trackerd", .summary = "test"};

// cgs_service_new on the given arguments (argv[0] added).
static int s_new (int argc, const char **args, cgs_service_t **ret_svc)
{
    char *argv[16] = {"trackerd"};
    assert_true (argc < 15);
    for (int i = 0; i < argc; i++)
        argv[i + 1] = (char *)args[i];
    return cgs_service_new (&s_info, argc + 1, argv, ret_svc);
}

static void test_version_and_errors (void **state)
{
    s_tmp_t *t = *state;
    cgs_service_t *svc = NULL;
    assert_int_equal (s_new (1, (const char *[]){"--version"}, &svc), 1);
    assert_null (svc);
    const char *unknown[] = {"--exercise", t->path, "--instance", "nope", "--check"};
    assert_int_equal (s_new (5, unknown, &svc), -ENOENT);
    assert_null (svc);
    assert_int_equal (s_new (2, (const char *[]){"--time-scale", "0"}, &svc), -EINVAL);
    assert_null (svc);
    cgs_service_destroy (&svc); // accepts NULL
}

static void test_check_only (void **state)
{
    s_tmp_t *t = *state;
    cgs_service_t *svc = NULL;
    const char *args[] = {"--exercise", t->path, "--instance", "trackerd.b", "--check", "-v", "-v"};
    assert_int_equal (s_new (7, args, &svc), 0);
    assert_non_null (svc);
    assert_true (cgs_service_check_only (svc));
    assert_string_equal (cgs_service_instance_name (svc), "trackerd.b");
    assert_string_equal (cgs_service_exercise_path (svc), t->path);
    assert_string_equal (cgs_service_instance (svc)->name, "trackerd.b");
    assert_non_null (cgs_service_exercise (svc));
    assert_string_equal (cgs_service_params_path (svc), "/etc/mscgs/trk.ini");
    assert_string_equal (cgs_service_scenario_path (svc), "");
    assert_true (cgs_service_time_scale (svc) == 4);
    assert_false (cgs_service_time_scale_given (svc));
    assert_int_equal (cgs_service_verbose (svc), 2);
    // Nothing runs with --check: no context, loop, health or sockets.
    assert_null (cgs_service_ctx (svc));
    assert_null (cgs_service_loop (svc));
    assert_null (cgs_service_health (svc));
    assert_null (cgs_service_pub (svc));
    assert_null (cgs_service_sub (svc));
    assert_null (cgs_service_cmd_server (svc));
    assert_null (cgs_service_curve (svc));
    cgs_service_destroy (&svc);
    assert_null (svc);
}

static void test_running (void **state)
{
    s_tmp_t *t = *state;
    cgs_service_t *svc = NULL;
    const char *args[] = {"--exercise", t->path,      "--state-dir", t->state,       "--params",
                          "p.ini",      "--scenario", "s.ini",       "--time-scale", "2.5"};
    assert_int_equal (s_new (10, args, &svc), 0);
    assert_false (cgs_service_check_only (svc));
    assert_string_equal (cgs_service_instance_name (svc), "trackerd");
    assert_string_equal (cgs_service_params_path (svc), "p.ini");
    assert_string_equal (cgs_service_scenario_path (svc), "s.ini");
    assert_true (cgs_service_time_scale (svc) == 2.5);
    assert_true (cgs_service_time_scale_given (svc));
    assert_int_equal (cgs_service_verbose (svc), 0);
    assert_string_equal (cgs_service_state_dir (svc), t->state); // absolute already
    assert_non_null (cgs_service_ctx (svc));
    assert_non_null (cgs_service_loop (svc));
    assert_non_null (cgs_service_health (svc));
    assert_non_null (cgs_service_pub (svc));
    assert_null (cgs_service_sub (svc));
    assert_null (cgs_service_cmd_server (svc));
    assert_false (cgs_service_commands_held (svc));
    cgs_service_set_sim_time (svc, 12.5);

    // A second copy of the instance is refused while the first holds the lock.
    cgs_service_t *again = NULL;
    const char *args2[] = {"--exercise", t->path, "--state-dir", t->state};
    assert_int_equal (s_new (4, args2, &again), -EBUSY);
    assert_null (again);
    cgs_service_destroy (&svc);
    assert_null (svc);
    // ... and taken once the first is gone.
    assert_int_equal (s_new (4, args2, &again), 0);
    cgs_service_destroy (&again);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown (test_version_and_errors, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_check_only, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_running, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
