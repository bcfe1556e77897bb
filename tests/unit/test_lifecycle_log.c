/* Unit tests of cgs_lifecycle (signals set the stop and reload flags; the
 * systemd calls are harmless outside systemd), cgs_log (one line per message
 * with the syslog priority prefix journald reads) and cgs_topics. */
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_topics.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_signals_set_flags (void **state)
{
    (void)state;
    assert_int_equal (cgs_lifecycle_init (), 0);
    assert_false (cgs_lifecycle_stopping ());
    assert_false (cgs_lifecycle_take_reload ());
    raise (SIGHUP);
    assert_false (cgs_lifecycle_stopping ());
    assert_true (cgs_lifecycle_take_reload ());
    assert_false (cgs_lifecycle_take_reload ()); // once per signal
    raise (SIGPIPE);                             // ignored, not fatal
    raise (SIGTERM);
    assert_true (cgs_lifecycle_stopping ());
    assert_int_equal (cgs_lifecycle_stop_signal (), SIGTERM);
}

static void test_notify_outside_systemd_is_harmless (void **state)
{
    (void)state;
    unsetenv ("NOTIFY_SOCKET");
    unsetenv ("WATCHDOG_USEC");
    cgs_notify_ready ("ready");
    cgs_notify_status ("%d tracks", 3);
    cgs_notify_watchdog ();
    cgs_notify_stopping ();
    assert_int_equal (cgs_notify_watchdog_usec (), 0);
    setenv ("WATCHDOG_USEC", "2000000", 1);
    char pid[32];
    snprintf (pid, sizeof pid, "%ld", (long)getpid ());
    setenv ("WATCHDOG_PID", pid, 1);
    assert_int_equal (cgs_notify_watchdog_usec (), 2000000);
    unsetenv ("WATCHDOG_USEC");
    unsetenv ("WATCHDOG_PID");
}

/* Run fn with stderr sent to a file; returns what was written. */
static char *s_capture_stderr (void (*fn) (void))
{
    char path[] = "/tmp/cgs-log-XXXXXX";
    int fd = mkstemp (path);
    assert_true (fd >= 0);
    int saved = dup (STDERR_FILENO);
    dup2 (fd, STDERR_FILENO);
    fn ();
    dup2 (saved, STDERR_FILENO);
    close (saved);
    char *buf = calloc (1, 4096);
    lseek (fd, 0, SEEK_SET);
    ssize_t n = read (fd, buf, 4095);
    assert_true (n >= 0);
    close (fd);
    unlink (path);
    return buf;
}

static void s_log_some (void)
{
    cgs_log_init ("mtid.uav1", LOG_INFO);
    cgs_log (LOG_ERR, "terrain %s: no such file", "x.tif");
    cgs_log (LOG_DEBUG, "not shown at LOG_INFO");
    cgs_log (LOG_WARNING, "ignored %d malformed", 2);
    char big[3000];
    memset (big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    cgs_log (LOG_INFO, "%s", big); // cut to one line, still ended by a newline
}

static void test_log_lines_have_priority_prefixes (void **state)
{
    (void)state;
    char *out = s_capture_stderr (s_log_some);
    const char *want = "<3>mtid.uav1: terrain x.tif: no such file\n"
                       "<4>mtid.uav1: ignored 2 malformed\n"
                       "<6>mtid.uav1: aaaa";
    assert_memory_equal (out, want, strlen (want));
    assert_null (strstr (out, "not shown"));
    size_t len = strlen (out);
    assert_true (len > 2000 && out[len - 1] == '\n');
    int lines = 0;
    for (size_t i = 0; i < len; i++)
        lines += out[i] == '\n';
    assert_int_equal (lines, 3);
    free (out);
}

static void test_topics_catalogue (void **state)
{
    (void)state;
    assert_int_equal (cgs_topics_count (), 14);
    const cgs_topic_t *t = cgs_topics_find ("entity");
    assert_non_null (t);
    assert_true (cgs_topics_published_by (t, "uavsim"));
    assert_true (cgs_topics_published_by (t, "gateway"));
    assert_false (cgs_topics_published_by (t, "gate")); // whole names only
    assert_false (cgs_topics_published_by (t, "mtid"));
    assert_true (cgs_topics_published_by (cgs_topics_find ("health"), "anything"));
    assert_null (cgs_topics_find ("mti.sca"));
    assert_null (cgs_topics_at (14));
    assert_true (cgs_topics_published_by (cgs_topics_find ("video"), "imagerd"));
    assert_false (cgs_topics_published_by (cgs_topics_find ("video"), "stationd"));
    // Every name is unique.
    for (size_t i = 0; i < cgs_topics_count (); i++)
        for (size_t k = i + 1; k < cgs_topics_count (); k++)
            assert_string_not_equal (cgs_topics_at (i)->name, cgs_topics_at (k)->name);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_signals_set_flags),
        cmocka_unit_test (test_notify_outside_systemd_is_harmless),
        cmocka_unit_test (test_log_lines_have_priority_prefixes),
        cmocka_unit_test (test_topics_catalogue),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
