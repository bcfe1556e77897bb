/* st_params — stationd's parameter file (deploy/params/station.ini): where the
 * web server listens, the operators' access token, the web page's folder, the
 * push rate, how long the map keeps hits and BCIS replies, the shaded relief
 * and the command timeouts. Every value is range-checked; errors name the
 * file, the line, the section and key. Pure. */
#ifndef ST_PARAMS_H
#define ST_PARAMS_H

#include <stdbool.h>
#include <stddef.h>

#define ST_TOKEN_MAX 256

typedef struct {
    // [http]
    char listen_address[64];  // address the web server binds (default 127.0.0.1)
    int port;                 // TCP port (default 8080; 0: the kernel picks one)
    char token[ST_TOKEN_MAX]; // operators' access token ("" none; from token or token_file)
    bool token_from_file;     // it came from token_file
    char web_root[4096];      // the page's folder ("" the one installed beside stationd)
    int threads;              // web server threads; each open page holds one (default 16)
    double write_timeout_s;   // a browser that takes longer to read a push is dropped (10)
    // [display]
    double push_hz;        // state pushes to each browser per wall second (default 5)
    int history_scans;     // complete scans of hits kept grey behind the current (20)
    double bcis_timeout_s; // BCIS replies shown this long, simulation seconds (5)
    double track_stale_s;  // a track not updated this long is dropped (60)
    double truth_stale_s;  // a ground-truth entity not heard this long is dropped (30)
    // [relief]
    double sun_azimuth_deg;   // the relief's light, clockwise from north (315)
    double sun_elevation_deg; // above the horizon (45)
    double z_factor;          // vertical exaggeration (1)
    int max_pixels;           // the picture's longer side at most this (4096)
    // [commands]
    double command_timeout_s; // wait this long for guidanced or uavsim (1)
    int command_attempts;     // tries before a command is reported unanswered (3)
} st_params_t;

/* The defaults (deploy/params/station.ini documents each). */
void st_params_defaults (st_params_t *p);
/* Read a parameter file over *p; on error *p is unchanged. 0, or a negative
 * errno with err filled ("file:line: [section] key: ..."). */
int st_params_load (const char *path, st_params_t *p, char *err, size_t errlen);
/* The same from text (name stands for the file name in errors). */
int st_params_load_string (const char *name, const char *text, st_params_t *p, char *err,
                           size_t errlen);
/* Whether address (IPv4 or IPv6 text) is a loopback address. */
bool st_params_is_loopback (const char *address);

#endif
