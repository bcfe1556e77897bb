/* bcis_interrogator — the scanning BCIS interrogator on one UAV: its scan
 * schedule (cgs_scan: full revolutions or a sector, at its rate), and per
 * dwell one interrogation in the beam's direction, answered by the friendly
 * transponders it reaches.
 *
 * Per entity in the dwell's azimuth sector, within the range limits and
 * within one elevation beamwidth of the beam's centre:
 *   - only a friendly entity carrying a transponder can answer; hostile,
 *     neutral and unknown entities never do, whatever they carry;
 *   - blocked when the terrain cuts the line from the interrogator's antenna
 *     to the transponder's (antenna_height_m above the ground): no reply;
 *   - otherwise the link budget (bcis_link) gives Eb/N0 both ways, and the
 *     messages are simulated symbol by symbol: each of the interrogation's
 *     bits is detected in Gaussian noise at the uplink's Eb/N0 (coherently for
 *     BPSK/QPSK, by comparing the energies of the two tones for non-coherent
 *     BFSK); a transponder that decodes it with at most correctable_bits errors
 *     replies, and the interrogator decodes the reply the same way. A message
 *     whose expected bit errors are below 1e-12 is taken as whole without
 *     drawing (the draw would not change it in a trillion messages);
 *   - a reply carries the responder's identity and marking, the range
 *     measured from the reply's timing (sigma range_sigma_m), the beam's
 *     azimuth (the responder is somewhere in the dwell's sector: sigma the
 *     dwell's width over √12), both links' Eb/N0, and where that range and
 *     azimuth put it on the ground (cgs_terrain_at_slant_range). With
 *     reports_position the transponder also sends its own position fix
 *     (true position plus Gaussian noise of position_sigma_m on each of
 *     east, north and up), and the reply gives that instead.
 * Pure: no sockets, clocks, globals or logging. */
#ifndef BCIS_INTERROGATOR_H
#define BCIS_INTERROGATOR_H

#include "bcis_link.h"
#include "bcis_params.h"
#include "cgs_geo.h"
#include "cgs_scan.h"
#include "cgs_scenario.h"
#include "cgs_terrain.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct bcis_interrogator bcis_interrogator_t;

/* A ground entity at the dwell's centre time. */
typedef struct {
    uint32_t id;
    cgs_enu_t position; // on the ground
    cgs_force_t force;
    bool transponder;
    const char *marking; // may be NULL
} bcis_entity_t;

typedef struct {
    uint32_t responder_id;
    char marking[CGS_MARKING_MAX + 1];
    cgs_enu_t position;       // where the reply puts the responder (see position_fix)
    bool position_fix;        // position is the transponder's fix, not range and azimuth
    double position_sigma_m;  // of a fix, per axis
    double range_m;           // measured
    double range_sigma_m;     // of range_m
    double azimuth_deg;       // the beam's, clockwise from north
    double azimuth_sigma_deg; // of the responder's azimuth about it
    double snr_up_db;         // Eb/N0 of the interrogation at the transponder
    double snr_down_db;       // Eb/N0 of the reply at the interrogator
} bcis_reply_t;

/* What became of one friendly transponder in the beam (for tests, health and scoring). */
typedef struct {
    uint32_t entity_id;
    bool blocked;  // terrain cut the line of sight
    bool heard;    // the transponder decoded the interrogation
    bool answered; // and the interrogator decoded its reply
    bcis_geometry_t geometry;
    bcis_budget_t budget; // not filled when blocked
} bcis_truth_t;

/* A dwell's outcome; arrays owned by the interrogator, valid until the next dwell. */
typedef struct {
    const bcis_reply_t *replies;
    size_t reply_count;
    const bcis_truth_t *truth; // the friendly transponders in the beam
    size_t truth_count;
    size_t in_beam; // entities of any force in the beam
} bcis_dwell_out_t;

/* An interrogator with these parameters over this terrain (borrowed; NULL:
 * flat open ground at height 0), seeded; NULL on bad parameters or no memory. */
bcis_interrogator_t *bcis_interrogator_new (const bcis_params_t *p, const cgs_terrain_t *terrain,
                                            uint64_t seed);
/* Free; accepts NULL; sets *self_p to NULL. */
void bcis_interrogator_destroy (bcis_interrogator_t **self_p);
/* Its scan schedule. */
const cgs_scan_t *bcis_interrogator_scan (const bcis_interrogator_t *self);
/* Interrogate once in dwell d from the antenna at uav (local frame): the
 * entities (any number; those not in the beam are skipped) as they are at
 * the dwell's centre time. 0, or -ENOMEM. */
int bcis_interrogator_dwell (bcis_interrogator_t *self, const cgs_dwell_t *d, cgs_enu_t uav,
                             const bcis_entity_t *entities, size_t n, bcis_dwell_out_t *ret);
/* The geometry of the path from uav to a transponder on the ground at
 * ground (its antenna antenna_height_m above), toward beam azimuth az_deg;
 * false when the terrain blocks it. */
bool bcis_interrogator_geometry (const bcis_interrogator_t *self, cgs_enu_t uav, cgs_enu_t ground,
                                 double beam_az_deg, bcis_geometry_t *ret);
/* One message of bits bits sent at Eb/N0 ebn0_db, detected symbol by
 * symbol with the parameters' modulation: true when it arrives with at most
 * correctable_bits errors. */
bool bcis_interrogator_send (bcis_interrogator_t *self, double ebn0_db, int bits);

#endif
