/* mti_params — the MTI radar's parameter file: an ASCII INI file read at
 * start, so values change without recompiling, with the paper's nominal
 * values as defaults (16 GHz, PRF 5 kHz, 200 ns pulse, 30 m range
 * resolution, 3° x 60° beam, 36°/s sweep). Every value is range-checked and
 * the set is checked for consistency (the dwell's coherent intervals must fit
 * in the time the beam takes to sweep one beamwidth; the pulse width must
 * give the stated range resolution). Every error names the file, the line,
 * the section and key, and what was expected. Pure: no logging, no globals.
 *
 * File format (deploy/params/radar.ini documents every key):
 *   [radar]        frequency, PRF, pulse, resolution, beam, sweep, power,
 *                  gain, noise figure, losses, range limits
 *   [scan]         mode = full|sector, sector centre, width and reference
 *   [processing]   fft_size, window, canceller, CFAR cells, pfa, m, n,
 *                  azimuth = beam-split|monopulse
 *   [clutter]      constant-gamma reflectivity, internal motion
 *   [target NAME]  one per radar cross-section class: rcs_m2, swerling
 * A class named `default` is used for entities whose class the file does not
 * name; without one, the built-in `vehicle` class (10 m², Swerling II) is. */
#ifndef MTI_PARAMS_H
#define MTI_PARAMS_H

#include "mti_azimuth.h"

#include <stdbool.h>
#include <stddef.h>

#define MTI_CLASS_NAME_MAX 31 // radar cross-section class names: at most 31 characters
#define MTI_CLASS_MAX      32 // classes in one file
#define MTI_FFT_MAX        1024
#define MTI_REF_CELLS_MAX  128
#define MTI_N_MAX          64 // coherent intervals in one dwell

/* Target fluctuation model. */
typedef enum {
    MTI_SWERLING_0 = 0,       // constant (nonfluctuating, Marcum)
    MTI_SWERLING_1 = 1,       // Rayleigh amplitude, constant over a dwell, independent scan to scan
    MTI_SWERLING_2 = 2,       // Rayleigh amplitude, constant within a coherent interval and
                              // independent from one interval to the next: the radar hops its
                              // frequency between intervals (Swerling II in the interval sense)
    MTI_SWERLING_2_PULSE = 3, // Rayleigh amplitude, independent pulse to pulse (the
                              // textbook case II: no coherent gain in the Doppler FFT)
} mti_swerling_t;

typedef enum {
    MTI_WINDOW_RECT = 0,
    MTI_WINDOW_HANN = 1,
    MTI_WINDOW_HAMMING = 2,
    MTI_WINDOW_BLACKMAN = 3,
} mti_window_t;

/* Clutter filter ahead of the Doppler FFT: pulses it spans. */
typedef enum {
    MTI_CANCELLER_NONE = 1,  // no filter (for checks; not a real MTI setting)
    MTI_CANCELLER_TWO = 2,   // y[k] = x[k] - x[k-1]
    MTI_CANCELLER_THREE = 3, // y[k] = x[k] - 2 x[k-1] + x[k-2]
} mti_canceller_t;

typedef enum {
    MTI_SCAN_FULL = 0,   // full revolutions, clockwise
    MTI_SCAN_SECTOR = 1, // back and forth across a sector; each pass is a scan
} mti_scan_mode_t;

typedef enum {
    MTI_SECTOR_NORTH = 0,   // sector centre is an azimuth clockwise from north
    MTI_SECTOR_HEADING = 1, // sector centre is relative to the UAV's heading
} mti_sector_ref_t;

typedef struct {
    char name[MTI_CLASS_NAME_MAX + 1]; // e.g. "vehicle"
    double rcs_m2;                     // mean radar cross-section, m²
    mti_swerling_t swerling;
} mti_class_t;

typedef struct {
    /* [radar] */
    double frequency_hz;            // centre frequency (default 16e9)
    double prf_hz;                  // pulse repetition frequency (default 5000)
    double pulse_width_s;           // (default 200e-9)
    double range_resolution_m;      // (default 30 = c * pulse width / 2)
    double azimuth_beamwidth_deg;   // one-way 3 dB (default 3)
    double elevation_beamwidth_deg; // one-way 3 dB (default 60)
    double beam_depression_deg;     // elevation beam centre below the horizon (default 30)
    double sweep_rate_dps;          // azimuth scan rate, degrees per second (default 36)
    double transmit_power_w;        // peak (default 20000)
    double antenna_gain_db;         // one-way, on boresight (default 24)
    double noise_figure_db;         // (default 4)
    double losses_db;               // system losses, two-way (default 5)
    double noise_temperature_k;     // reference temperature (default 290)
    double min_range_m;             // (default 500)
    double max_range_m;             // (default 20000)
    /* [scan] */
    mti_scan_mode_t scan_mode;   // (default full)
    double sector_center_deg;    // (default 0)
    double sector_width_deg;     // (default 90), at least one beamwidth
    mti_sector_ref_t sector_ref; // (default north)
    /* [processing] */
    int fft_size;              // pulses coherently integrated, a power of two (default 64)
    mti_window_t window;       // (default hamming)
    mti_canceller_t canceller; // (default two-pulse)
    int ref_cells;             // CFAR reference cells, even, split about the cell (default 16)
    int guard_cells;           // CFAR guard cells each side (default 2)
    double pfa;                // design false-alarm probability per range-Doppler cell (1e-4)
    int m;                     // crossings needed (default 2) ...
    int n;                     // ... of this many coherent intervals per dwell (default 4)
    mti_azimuth_t azimuth;     // how a hit's azimuth is measured (default monopulse)
    /* [clutter] */
    double clutter_gamma_db;     // constant-gamma reflectivity: sigma0 = gamma sin(grazing) (-15)
    double clutter_internal_mps; // std of internal clutter motion, m/s (default 0.1)
    /* [target NAME] */
    mti_class_t classes[MTI_CLASS_MAX];
    size_t class_count;
} mti_params_t;

/* Fill p with the defaults: the values above and the classes vehicle (10 m²,
 * Swerling I), tank (20 m², Swerling I), truck (15 m², Swerling I), person
 * (1 m², Swerling I), car (5 m², Swerling I) and reflector (10 m², constant). */
void mti_params_defaults (mti_params_t *p);
/* Read a parameter file over the defaults: keys absent keep their defaults;
 * a [target NAME] section replaces or adds that class. 0, or
 * -ENOENT/-EINVAL with "file:line: [section] key: reason" in err; *p is
 * written only on success. */
int mti_params_load (const char *path, mti_params_t *p, char *err, size_t errlen);
/* The same from text, as if read from a file called name. */
int mti_params_load_string (const char *name, const char *text, mti_params_t *p, char *err,
                            size_t errlen);
/* Check a set of parameters for consistency (what load checks after reading);
 * 0 or -EINVAL with the reason in err. */
int mti_params_check (const mti_params_t *p, char *err, size_t errlen);

/* Derived values. */
double mti_params_wavelength_m (const mti_params_t *p);
/* Pulses each coherent interval spans: fft_size plus the canceller's memory. */
int mti_params_cpi_pulses (const mti_params_t *p);
/* Time the beam takes to sweep one azimuth beamwidth, seconds. */
double mti_params_dwell_s (const mti_params_t *p);
/* The class named name, else `default`, else the first class; never NULL
 * when class_count > 0. *ret_known (may be NULL) says whether name matched. */
const mti_class_t *mti_params_class (const mti_params_t *p, const char *name, bool *ret_known);
/* A fluctuation model by the name a parameter file gives it ("0" or
 * "constant", "1", "2", "2-pulse"; case-insensitive): 0, or -EINVAL. */
int mti_swerling_parse (const char *text, mti_swerling_t *ret);
/* Its name: "0", "1", "2" or "2-pulse" ("?" for no model). */
const char *mti_swerling_name (mti_swerling_t model);

#endif
