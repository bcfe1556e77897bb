/* test_im_png — imagerd's PNG files:
 *   - a frame written and read back is the same, byte for byte (odd sizes,
 *     every alpha), an existing file is replaced, no NAME.tmp is left;
 *   - writing into a missing folder, reading a missing file or one that is
 *     not a PNG fail with a message naming the file;
 *   - the writer thread: every frame it queued is on disk, intact, when
 *     destroy returns (nothing lost: its final counts have written =
 *     queued), queued + dropped = submitted, a
 *     dropped frame is never written; with a queue of one and the thread
 *     held (its NAME.tmp a FIFO nobody reads yet), a full queue drops
 *     deterministically and counts it; a failed write is counted with its
 *     reason; bad arguments are refused.
 * Each case works in a fresh folder under /tmp, removed afterwards.
 * Needs -Iservices/imagerd (and -Icommon). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <stdbool.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "im_png.h"

/* ---- helpers ----------------------------------------------------------------------- */

typedef struct {
    char dir[64]; // a fresh temporary folder
} s_tmp_t;

static int s_setup (void **state)
{
    s_tmp_t *t = calloc (1, sizeof *t);
    if (!t)
        return -1;
    snprintf (t->dir, sizeof t->dir, "/tmp/test_im_png.XXXXXX");
    if (!mkdtemp (t->dir)) {
        free (t);
        return -1;
    }
    *state = t;
    return 0;
}

static int s_remove (const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    return remove (path);
}

static int s_teardown (void **state)
{
    s_tmp_t *t = *state;
    nftw (t->dir, s_remove, 16, FTW_DEPTH | FTW_PHYS);
    free (t);
    return 0;
}

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static uint8_t s_byte (void)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    return (uint8_t)((s_rng * 0x2545F4914F6CDD1Dull) >> 56);
}

/* A frame of noise (hard to compress: the writer takes a while). */
static uint8_t *s_frame (int w, int h)
{
    size_t n = (size_t)w * (size_t)h * 4;
    uint8_t *f = malloc (n);
    assert_non_null (f);
    for (size_t i = 0; i < n; i++)
        f[i] = s_byte ();
    return f;
}

static bool s_exists (const char *path)
{
    struct stat st;
    return lstat (path, &st) == 0;
}

/* The file at path is a PNG of exactly this frame. */
static void s_assert_png (const char *path, const uint8_t *rgba, int w, int h)
{
    uint8_t *back = NULL;
    int bw = 0, bh = 0;
    char err[512] = "";
    if (im_png_read (path, &back, &bw, &bh, err, sizeof err) != 0)
        fail_msg ("%s", err);
    assert_int_equal (bw, w);
    assert_int_equal (bh, h);
    int same = memcmp (back, rgba, (size_t)w * (size_t)h * 4) == 0;
    free (back);
    if (!same)
        fail_msg ("%s: not the frame written", path);
}

/* Files in dir whose name ends with suffix. */
static int s_count_suffix (const char *dir, const char *suffix)
{
    DIR *d = opendir (dir);
    assert_non_null (d);
    int n = 0;
    size_t ls = strlen (suffix);
    for (struct dirent *e; (e = readdir (d));) {
        size_t l = strlen (e->d_name);
        n += l >= ls && strcmp (e->d_name + l - ls, suffix) == 0;
    }
    closedir (d);
    return n;
}

/* ---- write and read ---------------------------------------------------------------------- */

static void test_round_trip (void **state)
{
    s_tmp_t *t = *state;
    const int sizes[][2] = {{37, 23}, {1, 1}, {640, 480}, {3, 200}};
    char path[256], err[512] = "";
    snprintf (path, sizeof path, "%s/frame.png", t->dir);
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        int w = sizes[i][0], h = sizes[i][1];
        uint8_t *f = s_frame (w, h);
        // Every alpha, and the extremes, in the first pixels.
        for (int k = 0; k < w * h && k < 256; k++)
            f[4 * k + 3] = (uint8_t)k;
        f[0] = 0, f[1] = 255;
        // The same path each time: an existing file is replaced.
        if (im_png_write (path, f, w, h, err, sizeof err) != 0)
            fail_msg ("%s", err);
        s_assert_png (path, f, w, h);
        free (f);
    }
    assert_int_equal (s_count_suffix (t->dir, ".tmp"), 0);
    assert_int_equal (s_count_suffix (t->dir, ".png"), 1);
}

static void test_write_missing_folder (void **state)
{
    s_tmp_t *t = *state;
    char path[256], err[512] = "";
    snprintf (path, sizeof path, "%s/nope/frame.png", t->dir);
    uint8_t *f = s_frame (8, 8);
    int rc = im_png_write (path, f, 8, 8, err, sizeof err);
    free (f);
    assert_int_equal (rc, -ENOENT);
    assert_non_null (strstr (err, "nope/frame.png"));
    assert_non_null (strstr (err, strerror (ENOENT)));
    assert_false (s_exists (path));
}

static void test_read_errors (void **state)
{
    s_tmp_t *t = *state;
    char path[256], err[512] = "";
    uint8_t *buf = NULL;
    int w = -1, h = -1;
    snprintf (path, sizeof path, "%s/missing.png", t->dir);
    assert_true (im_png_read (path, &buf, &w, &h, err, sizeof err) < 0);
    assert_non_null (strstr (err, "missing.png"));
    assert_null (buf);
    // Not a PNG.
    snprintf (path, sizeof path, "%s/text.png", t->dir);
    FILE *fp = fopen (path, "w");
    assert_non_null (fp);
    fputs ("this is not a PNG file, only its name says so\n", fp);
    fclose (fp);
    err[0] = 0;
    assert_true (im_png_read (path, &buf, &w, &h, err, sizeof err) < 0);
    assert_non_null (strstr (err, "text.png"));
    assert_null (buf);
    // A PNG cut short.
    uint8_t *f = s_frame (64, 64);
    snprintf (path, sizeof path, "%s/cut.png", t->dir);
    assert_int_equal (im_png_write (path, f, 64, 64, err, sizeof err), 0);
    free (f);
    assert_int_equal (truncate (path, 200), 0);
    err[0] = 0;
    assert_true (im_png_read (path, &buf, &w, &h, err, sizeof err) < 0);
    assert_non_null (strstr (err, "cut.png"));
}

/* ---- the writer thread --------------------------------------------------------------------- */

/* Submit n frames as fast as possible into a writer with a queue of depth:
 * each submit 0 (queued) or -EAGAIN (dropped), and the counts agree; after
 * destroy exactly the queued frames are on disk, each intact, and no .tmp. */
static void s_burst (const char *dir, size_t depth, int n, int w, int h)
{
    char err[512] = "";
    im_png_writer_t *wr = im_png_writer_new (dir, depth, err, sizeof err);
    if (!wr)
        fail_msg ("%s", err);
    uint8_t **frames = calloc ((size_t)n, sizeof *frames);
    int *rcs = calloc ((size_t)n, sizeof *rcs);
    assert_non_null (frames);
    assert_non_null (rcs);
    uint64_t queued = 0, dropped = 0;
    for (int i = 0; i < n; i++) {
        frames[i] = s_frame (w, h);
        char name[64];
        snprintf (name, sizeof name, "frame-%08d.png", i);
        // Submitted from a scratch copy, wiped and freed at once: the writer
        // must have taken its own copy.
        uint8_t *scratch = malloc ((size_t)w * (size_t)h * 4);
        assert_non_null (scratch);
        memcpy (scratch, frames[i], (size_t)w * (size_t)h * 4);
        rcs[i] = im_png_writer_submit (wr, scratch, w, h, name);
        memset (scratch, 0xee, (size_t)w * (size_t)h * 4);
        free (scratch);
        assert_true (rcs[i] == 0 || rcs[i] == -EAGAIN);
        queued += rcs[i] == 0;
        dropped += rcs[i] == -EAGAIN;
    }
    im_png_stats_t st;
    im_png_writer_stats (wr, &st);
    assert_int_equal (st.queued, queued);
    assert_int_equal (st.dropped, dropped);
    assert_int_equal (st.queued + st.dropped, (uint64_t)n);
    assert_true (st.written <= st.queued);
    assert_int_equal (st.failed, 0);
    im_png_stats_t fin;
    memset (&fin, 0x5a, sizeof fin);
    im_png_writer_destroy (&wr, &fin);
    assert_null (wr);
    // Everything queued was written before destroy returned.
    assert_int_equal (fin.queued, queued);
    assert_int_equal (fin.dropped, dropped);
    assert_int_equal (fin.written, queued);
    assert_int_equal (fin.failed, 0);
    im_png_writer_destroy (&wr, &fin); // NULL is harmless
    im_png_writer_destroy (NULL, NULL);
    // Every queued frame is on disk, intact; no dropped one is.
    int on_disk = 0;
    for (int i = 0; i < n; i++) {
        char path[256];
        snprintf (path, sizeof path, "%s/frame-%08d.png", dir, i);
        if (rcs[i] == 0) {
            s_assert_png (path, frames[i], w, h);
            on_disk++;
        } else {
            assert_false (s_exists (path));
        }
        free (frames[i]);
    }
    free (frames);
    free (rcs);
    assert_int_equal ((uint64_t)on_disk, queued);
    assert_int_equal (s_count_suffix (dir, ".png"), on_disk);
    assert_int_equal (s_count_suffix (dir, ".tmp"), 0);
}

/* Deep queues keep everything; a queue of one under a burst of big frames
 * drops some (whatever the timing, the counts agree). The folder is created
 * when missing, parents too. */
static void test_writer_nothing_lost (void **state)
{
    s_tmp_t *t = *state;
    char dir[256];
    snprintf (dir, sizeof dir, "%s/deep", t->dir);
    s_burst (dir, 64, 40, 64, 48);
    snprintf (dir, sizeof dir, "%s/new/sub/one", t->dir);
    s_burst (dir, 1, 30, 320, 240);
    snprintf (dir, sizeof dir, "%s/three", t->dir);
    s_burst (dir, 3, 30, 160, 120);
}

/* A queue of one, its thread held: the first frame's NAME.tmp is a FIFO, so
 * the thread blocks opening it until this test reads the other end. Of the
 * next two frames, one at least finds the queue full (the first frame is
 * either still queued or being written, and the one after it waits behind
 * it): dropped and counted, never written; nothing is written while the
 * thread is held. Released, the thread writes the first frame into the
 * FIFO (read here: a whole PNG of it) and the queued one to its file. */
static void test_writer_drops_when_full (void **state)
{
    s_tmp_t *t = *state;
    char dir[256], fifo[320], err[512] = "";
    snprintf (dir, sizeof dir, "%s/held", t->dir);
    im_png_writer_t *wr = im_png_writer_new (dir, 1, err, sizeof err);
    if (!wr)
        fail_msg ("%s", err);
    snprintf (fifo, sizeof fifo, "%s/held.png.tmp", dir);
    assert_int_equal (mkfifo (fifo, 0600), 0);
    const int w = 40, h = 30;
    uint8_t *f0 = s_frame (w, h), *f1 = s_frame (w, h), *f2 = s_frame (w, h);
    assert_int_equal (im_png_writer_submit (wr, f0, w, h, "held.png"), 0); // the queue was empty
    int rc1 = im_png_writer_submit (wr, f1, w, h, "f1.png");
    int rc2 = im_png_writer_submit (wr, f2, w, h, "f2.png");
    assert_true (rc1 == 0 || rc1 == -EAGAIN);
    assert_true (rc2 == 0 || rc2 == -EAGAIN);
    assert_true (rc1 == -EAGAIN || rc2 == -EAGAIN);
    im_png_stats_t st;
    im_png_writer_stats (wr, &st);
    assert_int_equal (st.queued + st.dropped, 3);
    assert_int_equal (st.dropped, (rc1 == -EAGAIN) + (rc2 == -EAGAIN));
    assert_true (st.dropped >= 1);
    assert_int_equal (st.written, 0);
    assert_int_equal (st.failed, 0);
    // Release: read the first frame's PNG out of the FIFO.
    int fd = open (fifo, O_RDONLY);
    assert_true (fd >= 0);
    size_t cap = 1 << 16, len = 0;
    uint8_t *png = malloc (cap);
    assert_non_null (png);
    for (;;) {
        if (len == cap) {
            cap *= 2;
            png = realloc (png, cap);
            assert_non_null (png);
        }
        ssize_t n = read (fd, png + len, cap - len);
        assert_true (n >= 0);
        if (n == 0)
            break;
        len += (size_t)n;
    }
    close (fd);
    im_png_writer_destroy (&wr, &st);
    assert_int_equal (st.queued + st.dropped, 3);
    assert_int_equal (st.written, st.queued);
    assert_int_equal (st.failed, 0);
    // What came through the FIFO is the first frame.
    char copy[320];
    snprintf (copy, sizeof copy, "%s/fifo-copy.png", t->dir);
    FILE *fp = fopen (copy, "wb");
    assert_non_null (fp);
    assert_int_equal (fwrite (png, 1, len, fp), len);
    fclose (fp);
    free (png);
    s_assert_png (copy, f0, w, h);
    // The queued one of the other two is on disk; the dropped one is not.
    char p1[320], p2[320];
    snprintf (p1, sizeof p1, "%s/f1.png", dir);
    snprintf (p2, sizeof p2, "%s/f2.png", dir);
    if (rc1 == 0)
        s_assert_png (p1, f1, w, h);
    else
        assert_false (s_exists (p1));
    if (rc2 == 0)
        s_assert_png (p2, f2, w, h);
    else
        assert_false (s_exists (p2));
    assert_int_equal (s_count_suffix (dir, ".tmp"), 0);
    free (f0), free (f1), free (f2);
}

/* A write that fails (the folder gone) is counted with its reason; the
 * thread carries on. */
static void test_writer_failure_counted (void **state)
{
    s_tmp_t *t = *state;
    char dir[256], err[512] = "";
    snprintf (dir, sizeof dir, "%s/gone", t->dir);
    im_png_writer_t *wr = im_png_writer_new (dir, 4, err, sizeof err);
    if (!wr)
        fail_msg ("%s", err);
    assert_int_equal (rmdir (dir), 0);
    uint8_t *f = s_frame (16, 16);
    assert_int_equal (im_png_writer_submit (wr, f, 16, 16, "lost.png"), 0);
    im_png_stats_t st;
    // Wait (no time limit: the runner's) for the thread to have tried.
    do {
        sched_yield ();
        im_png_writer_stats (wr, &st);
    } while (st.written + st.failed < st.queued);
    assert_int_equal (st.failed, 1);
    assert_int_equal (st.written, 0);
    assert_non_null (strstr (st.last_error, "lost.png"));
    // The folder back: the next frame is written.
    assert_int_equal (mkdir (dir, 0755), 0);
    assert_int_equal (im_png_writer_submit (wr, f, 16, 16, "kept.png"), 0);
    im_png_writer_destroy (&wr, &st);
    assert_int_equal (st.queued, 2);
    assert_int_equal (st.written, 1);
    assert_int_equal (st.failed, 1);
    char path[320];
    snprintf (path, sizeof path, "%s/kept.png", dir);
    s_assert_png (path, f, 16, 16);
    free (f);
}

static void test_writer_bad_arguments (void **state)
{
    s_tmp_t *t = *state;
    char dir[256], err[512] = "";
    snprintf (dir, sizeof dir, "%s/q", t->dir);
    assert_null (im_png_writer_new (dir, 0, err, sizeof err));
    assert_true (strlen (err) > 0);
    // A folder under a regular file cannot be made.
    char file[256];
    snprintf (file, sizeof file, "%s/plain", t->dir);
    FILE *fp = fopen (file, "w");
    assert_non_null (fp);
    fclose (fp);
    snprintf (dir, sizeof dir, "%s/plain/sub", t->dir);
    err[0] = 0;
    assert_null (im_png_writer_new (dir, 2, err, sizeof err));
    assert_non_null (strstr (err, dir));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown (test_round_trip, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_write_missing_folder, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_read_errors, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_writer_nothing_lost, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_writer_drops_when_full, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_writer_failure_counted, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_writer_bad_arguments, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
