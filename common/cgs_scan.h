/* cgs_scan — the azimuth scan schedule of a stepped scanning sensor (the MTI
 * radar, the BCIS interrogator): full revolutions clockwise, or back and forth
 * across a sector (each pass a scan) whose centre is an azimuth or is relative
 * to the platform's heading.
 *
 * The swept span (360 degrees, or the sector) is cut into D = floor(span /
 * beamwidth) dwells of equal width (at least one beamwidth), each lasting
 * width / rate. Dwell k of the exercise runs from k * dwell time of simulation
 * time, so the schedule is a pure function of time: a restarted service scans
 * on where it should. A plain value: no allocation, no state beyond the
 * parameters. */
#ifndef CGS_SCAN_H
#define CGS_SCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum {
    CGS_SCAN_FULL = 0,   // full revolutions, clockwise
    CGS_SCAN_SECTOR = 1, // back and forth across a sector; each pass is a scan
} cgs_scan_mode_t;

typedef enum {
    CGS_SECTOR_NORTH = 0,   // the sector centre is an azimuth, clockwise from north
    CGS_SECTOR_HEADING = 1, // the sector centre is relative to the platform's heading
} cgs_sector_ref_t;

typedef struct {
    cgs_scan_mode_t mode;
    double sector_center_deg; // sector mode: centre
    double sector_width_deg;  // sector mode: width, at least one beamwidth
    cgs_sector_ref_t sector_ref;
    double beamwidth_deg; // azimuth beamwidth: no dwell is narrower
    double rate_dps;      // azimuth scan rate, degrees per second
} cgs_scan_params_t;

/* One dwell of the schedule. */
typedef struct {
    uint64_t index;     // dwell number since simulation time 0
    uint32_t scan;      // scan (or sector pass) number, from 1
    uint32_t dwell;     // dwell within its scan, from 0
    uint32_t dwells;    // dwells per scan
    double start_s;     // simulation time the dwell starts
    double end_s;       // and ends
    double az_from_deg; // azimuth swept from, clockwise from north, [0, 360)
    double az_to_deg;   // to (the beam moves from az_from to az_to)
    double az_center_deg;
    double width_deg; // az_from to az_to, degrees
    bool scan_start;  // first dwell of its scan
    bool scan_end;    // last dwell of its scan
} cgs_dwell_t;

typedef struct {
    cgs_scan_params_t p;
    double span_deg;  // swept span: 360, or the sector's width
    uint32_t dwells;  // per scan
    double dwell_deg; // width of one dwell
    double dwell_s;   // its duration
} cgs_scan_t;

/* Set up the schedule; 0, or -EINVAL (non-finite or non-positive beamwidth
 * or rate, a sector narrower than the beam or wider than 360). *ret is
 * written only on success. */
int cgs_scan_init (const cgs_scan_params_t *p, cgs_scan_t *ret);
/* Dwell number k; heading_deg orients a heading-referenced sector. */
void cgs_scan_dwell (const cgs_scan_t *self, uint64_t k, double heading_deg, cgs_dwell_t *ret);
/* Number of the dwell in progress at simulation time t (0 for t < 0 or NaN). */
uint64_t cgs_scan_dwell_at (const cgs_scan_t *self, double t_s);
/* True when azimuth az_deg lies in the dwell's sector [lo, lo + width). */
bool cgs_dwell_contains (const cgs_dwell_t *d, double az_deg);
/* The dwell sector's anticlockwise edge (its start when read clockwise). */
double cgs_dwell_lo_deg (const cgs_dwell_t *d);
/* Where a service is in the schedule as simulation time passes: each dwell
 * is run once, after it has ended. */
typedef struct {
    bool started;     // a time has been seen
    uint64_t next;    // the next dwell to run
    uint64_t skipped; // dwells skipped in all, to catch up
} cgs_scan_pace_t;

typedef enum {
    CGS_PACE_RUN = 0,   // run the dwells from pace->next up to *ret_end
    CGS_PACE_START = 1, // the first time seen: nothing to run, the scan starts here
    CGS_PACE_BACK = 2,  // time went back (a restarted clock): nothing to run, the scan follows
} cgs_pace_t;

/* Simulation time is now t_s: the dwells that have ended since the last
 * call are pace->next .. *ret_end - 1, but no further back than history_s
 * (older dwells would find no entity history) and no more than a scan; the
 * dwells passed over are added to pace->skipped and *ret_skipped (0 when
 * none). The caller runs them, advancing pace->next. */
cgs_pace_t cgs_scan_pace (const cgs_scan_t *self, cgs_scan_pace_t *pace, double t_s,
                          double history_s, uint64_t *ret_end, uint64_t *ret_skipped);
/* An angle in degrees wrapped to [0, 360). */
double cgs_wrap360 (double a_deg);

#endif
