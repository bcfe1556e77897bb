/* st_web — stationd's embedded web server (CivetWeb): serves the page's
 * folder, the shaded relief and the latest sensor image over HTTP, and keeps
 * one WebSocket per open page. A push thread sends the newest picture to
 * every page (a page that reads slower than the pushes come skips to the
 * newest, never queues); each page's requests are handed, in that page's own
 * CivetWeb thread, to the caller's request function, which answers that page
 * alone with st_web_send.
 *
 * The live video is a second WebSocket, /video, read-only (no token): each
 * frame's MPEG transport stream bytes go to every video page as one binary
 * message, from a writer thread of that page's own, so a slow page delays
 * only itself. A page starts at a keyframe; what waits for it is bounded
 * (S_VIDEO_QUEUE_FRAMES frames, S_VIDEO_QUEUE_BYTES bytes, a frame waiting
 * S_VIDEO_BEHIND_S; and the socket's send buffer, S_VIDEO_SNDBUF): a page
 * behind that is dropped and skips to the next keyframe, counted.
 *
 * CivetWeb runs its own threads, so this module is where threads share
 * memory: the list of pages, the newest picture and the image path, under one
 * mutex that is never held across a network write (a slow page delays the
 * push thread, up to write_timeout_s, never the caller's loop). A page whose
 * write fails or times out is closed. Operators are the pages that gave the
 * configured token (?token= on the WebSocket URL), or every page when there
 * is none. A WebSocket whose Origin is not the Host it asked, or, on a
 * loopback server, whose Host is not a loopback name of this port (DNS
 * rebinding), is refused, so another web site open in the operator's
 * browser cannot command the UAV; /video has the same checks. At most
 * threads - 2 WebSockets (pages and video pages together: each holds a
 * CivetWeb thread) are open at once, so two threads always serve files. No logging: errors are
 * returned, counted and kept for the caller. */
#ifndef ST_WEB_H
#define ST_WEB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct st_web st_web_t;
typedef struct st_web_conn st_web_conn_t;

typedef struct {
    const char *listen_address; // IPv4 or IPv6 address
    int port;                   // 0: the kernel picks one (see st_web_port)
    const char *web_root;       // the page's folder
    int threads;                // CivetWeb worker threads
    double write_timeout_s;     // a page that takes longer to read is dropped
    const char *token;          // operators' token, "" for none
    const uint8_t *relief_png;  // the relief picture (copied), NULL for none
    size_t relief_len;
    const char *hello_operator; // the first message each new page gets (copied),
    const char *hello_viewer;   // by whether it is an operator's
} st_web_config_t;

/* A page's request (one WebSocket text message), called in that page's
 * thread: operator says whether it gave the token. */
typedef void (st_web_request_fn) (void *arg, st_web_conn_t *conn, const char *text, size_t len,
                                  bool operator);
/* A page went away: free what the request function kept in its user data. */
typedef void (st_web_close_fn) (void *arg, void *user);

typedef struct {
    uint64_t pages;          // open now
    uint64_t pages_total;    // opened since start
    uint64_t refused;        // WebSocket upgrades refused (foreign Origin or Host)
    uint64_t full;           // WebSocket upgrades refused: as many pages as threads allow
    uint64_t oversized;      // page messages refused for their size (or fragmented)
    uint64_t pushes;         // pictures written to a page
    uint64_t skipped;        // pictures replaced before the push thread could send them
    uint64_t write_errors;   // writes that failed (the page is then closed)
    uint64_t requests;       // messages from pages
    uint64_t max_push_bytes; // the largest picture
    double last_push_s;      // wall seconds the latest round of pushes took
    /* The live video (/video). */
    uint64_t video_pages;       // open now
    uint64_t video_pages_total; // opened since start
    uint64_t video_frames;      // frames handed to st_web_video_publish
    uint64_t video_sent;        // frames written to a page
    uint64_t video_bytes;       // bytes written to pages
    uint64_t video_dropped;     // frames a page missed because it fell behind
    uint64_t video_behind;      // times a page fell behind (its queue was dropped)
    uint64_t video_restarts;    // streams started over (another UAV, imagerd restarted)
} st_web_stats_t;

/* Start serving. NULL with the reason in err (the port in use, no folder, ...). */
st_web_t *st_web_new (const st_web_config_t *cfg, st_web_request_fn *request,
                      st_web_close_fn *close_fn, void *arg, char *err, size_t errlen);
/* Stop the server and the push thread, close every page; accepts NULL; nulls the pointer. */
void st_web_destroy (st_web_t **self_p);
/* The port it listens on. */
int st_web_port (const st_web_t *self);
/* Hand a new picture to the push thread (takes ownership of json, malloc'd). */
void st_web_publish (st_web_t *self, char *json, size_t len);
/* The file /image/latest.png serves ("" none). */
void st_web_set_image (st_web_t *self, const char *path);
/* One video frame's transport stream bytes (copied) to every /video page:
 * keyframe says they start with PAT, PMT and an IDR picture, where a page
 * that has just opened, or that fell behind, starts. Never blocks on a page. */
void st_web_video_publish (st_web_t *self, const uint8_t *ts, size_t len, bool keyframe);
/* The stream changed (another UAV, a restarted imagerd): every /video page
 * is closed, so each starts a new player on the new stream. */
void st_web_video_restart (st_web_t *self);
/* Send text to one page, from its request function; 0 or -EPIPE. */
int st_web_send (st_web_conn_t *conn, const char *text, size_t len);
/* The request function's own data for this page (NULL at first). */
void *st_web_conn_user (const st_web_conn_t *conn);
void st_web_conn_set_user (st_web_conn_t *conn, void *user);
/* The page's address, for messages. */
const char *st_web_conn_peer (const st_web_conn_t *conn);
/* Counters and the latest error CivetWeb reported ("" none; copied into err). */
void st_web_stats (st_web_t *self, st_web_stats_t *ret, char *err, size_t errlen);

#endif
