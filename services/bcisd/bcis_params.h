/* bcis_params — the BCIS interrogator's parameter file: an ASCII INI file
 * read at start, with documented defaults (deploy/params/bcis.ini): a Ka-band
 * (38 GHz) scanning interrogator on the UAV and the transponders of friendly
 * ground vehicles, the link's modulation and message lengths, and the
 * propagation (atmosphere, rain, foliage). Every value is range-checked and
 * the set for consistency; every error names the file, the line, the section
 * and key, and what was expected. Pure: no logging, no globals.
 *
 * Sections: [interrogator], [scan], [transponder], [link], [propagation]. */
#ifndef BCIS_PARAMS_H
#define BCIS_PARAMS_H

#include "cgs_scan.h"

#include <stdbool.h>
#include <stddef.h>

typedef enum {
    BCIS_MOD_BPSK = 0, // coherent BPSK: Pb = Q(sqrt(2 Eb/N0))
    BCIS_MOD_QPSK = 1, // coherent Gray-coded QPSK: the same Pb per bit
    BCIS_MOD_BFSK = 2, // non-coherent binary FSK: Pb = exp(-Eb/2N0) / 2
} bcis_modulation_t;

typedef enum {
    BCIS_POL_HORIZONTAL = 0, // polarisation tilt 0 degrees
    BCIS_POL_VERTICAL = 1,   // 90 degrees
    BCIS_POL_CIRCULAR = 2,   // 45 degrees, as ITU-R P.838 takes circular
} bcis_polarization_t;

typedef struct {
    /* [interrogator] */
    double frequency_hz;            // carrier, the hop band's centre (default 38e9)
    double transmit_power_w;        // (default 1)
    double antenna_gain_db;         // on the beam's axis (default 25)
    double azimuth_beamwidth_deg;   // one-way 3 dB (default 6)
    double elevation_beamwidth_deg; // one-way 3 dB (default 40)
    double beam_depression_deg;     // elevation beam centre below the horizon (default 15)
    double noise_figure_db;         // receiver (default 5)
    double losses_db;               // cables and radome, each way (default 2)
    double min_range_m;             // (default 100)
    double max_range_m;             // replies are listened for out to here (default 20000)
    double range_sigma_m;           // range measured from the reply's timing (default 5)
    /* [scan] */
    cgs_scan_mode_t scan_mode;   // full|sector (default full)
    double sector_center_deg;    // (default 0)
    double sector_width_deg;     // (default 90)
    cgs_sector_ref_t sector_ref; // north|heading (default north)
    double scan_rate_dps;        // (default 60)
    /* [transponder] */
    double transponder_power_w;         // (default 0.5)
    double transponder_gain_db;         // omnidirectional (default 3)
    double transponder_noise_figure_db; // (default 6)
    double transponder_losses_db;       // (default 2)
    double antenna_height_m;            // above the ground (default 2.5)
    bool reports_position;              // a reply carries the transponder's position fix
                                        // (default no: range and beam azimuth only)
    double position_sigma_m;            // of that fix, per axis (default 10)
    /* [link] */
    bcis_modulation_t modulation; // bpsk|qpsk|bfsk (default bfsk)
    double data_rate_bps;         // both ways; the noise bandwidth (default 1e6)
    int interrogation_bits;       // message length (default 64)
    int reply_bits;               // (default 128)
    int correctable_bits;         // bit errors a message survives (default 0)
    double noise_temperature_k;   // reference T0 of the noise figures (default 290)
    /* [propagation] */
    double atmospheric_db_per_km;     // gases along the whole path (default 0.12)
    double rain_rate_mmph;            // (default 0)
    double rain_height_m;             // rain below this height, local up (default 3000)
    bcis_polarization_t polarization; // horizontal|vertical|circular (default vertical)
    bool foliage;                     // Weissberger loss in woods (default yes)
} bcis_params_t;

/* Fill p with the documented defaults. */
void bcis_params_defaults (bcis_params_t *p);
/* Read a file over the defaults; 0, or -ENOENT/-EINVAL/-ENOMEM with
 * "file:line: [section] key: reason" in err. *p is written only on success. */
int bcis_params_load (const char *path, bcis_params_t *p, char *err, size_t errlen);
/* The same from text, as if read from a file called name. */
int bcis_params_load_string (const char *name, const char *text, bcis_params_t *p, char *err,
                             size_t errlen);
/* Check a struct's values and consistency; 0 or -EINVAL with the reason. */
int bcis_params_check (const bcis_params_t *p, char *err, size_t errlen);
/* The scan schedule parameters. */
cgs_scan_params_t bcis_params_scan (const bcis_params_t *p);

#endif
