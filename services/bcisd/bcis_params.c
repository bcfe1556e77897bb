/* bcis_params — the BCIS parameter file (see bcis_params.h). */
#include "bcis_params.h"
#include "cgs_config.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>

void bcis_params_defaults (bcis_params_t *p)
{
    *p = (bcis_params_t){
        .frequency_hz = 38e9,
        .transmit_power_w = 1,
        .antenna_gain_db = 25,
        .azimuth_beamwidth_deg = 6,
        .elevation_beamwidth_deg = 40,
        .beam_depression_deg = 15,
        .noise_figure_db = 5,
        .losses_db = 2,
        .min_range_m = 100,
        .max_range_m = 20000,
        .range_sigma_m = 5,
        .scan_mode = CGS_SCAN_FULL,
        .sector_center_deg = 0,
        .sector_width_deg = 90,
        .sector_ref = CGS_SECTOR_NORTH,
        .scan_rate_dps = 60,
        .transponder_power_w = 0.5,
        .transponder_gain_db = 3,
        .transponder_noise_figure_db = 6,
        .transponder_losses_db = 2,
        .antenna_height_m = 2.5,
        .position_sigma_m = 10,
        .modulation = BCIS_MOD_BFSK,
        .data_rate_bps = 1e6,
        .interrogation_bits = 64,
        .reply_bits = 128,
        .correctable_bits = 0,
        .noise_temperature_k = 290,
        .atmospheric_db_per_km = 0.12,
        .rain_rate_mmph = 0,
        .rain_height_m = 3000,
        .polarization = BCIS_POL_VERTICAL,
        .foliage = true,
    };
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (bcis_params_t, field), lo, hi                                            \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("interrogator", "frequency_hz", frequency_hz, 1e9, 95e9),
    S_R ("interrogator", "transmit_power_w", transmit_power_w, 1e-6, 1e4),
    S_R ("interrogator", "antenna_gain_db", antenna_gain_db, -10, 60),
    S_R ("interrogator", "azimuth_beamwidth_deg", azimuth_beamwidth_deg, 0.1, 360),
    S_R ("interrogator", "elevation_beamwidth_deg", elevation_beamwidth_deg, 0.1, 180),
    S_R ("interrogator", "beam_depression_deg", beam_depression_deg, -90, 90),
    S_R ("interrogator", "noise_figure_db", noise_figure_db, 0, 30),
    S_R ("interrogator", "losses_db", losses_db, 0, 40),
    S_R ("interrogator", "min_range_m", min_range_m, 0, 1e6),
    S_R ("interrogator", "max_range_m", max_range_m, 1, 1e6),
    S_R ("interrogator", "range_sigma_m", range_sigma_m, 0, 1000),
    S_R ("scan", "sector_center_deg", sector_center_deg, -360, 360),
    S_R ("scan", "sector_width_deg", sector_width_deg, 0.1, 360),
    S_R ("scan", "rate_dps", scan_rate_dps, 0.1, 3600),
    S_R ("transponder", "transmit_power_w", transponder_power_w, 1e-6, 1e4),
    S_R ("transponder", "antenna_gain_db", transponder_gain_db, -10, 40),
    S_R ("transponder", "noise_figure_db", transponder_noise_figure_db, 0, 30),
    S_R ("transponder", "losses_db", transponder_losses_db, 0, 40),
    S_R ("transponder", "antenna_height_m", antenna_height_m, 0.1, 100),
    S_R ("transponder", "position_sigma_m", position_sigma_m, 0, 1000),
    S_R ("link", "data_rate_bps", data_rate_bps, 1, 1e10),
    S_R ("link", "noise_temperature_k", noise_temperature_k, 1, 10000),
    S_R ("propagation", "atmospheric_db_per_km", atmospheric_db_per_km, 0, 100),
    S_R ("propagation", "rain_rate_mmph", rain_rate_mmph, 0, 300),
    S_R ("propagation", "rain_height_m", rain_height_m, 0, 20000),
};
#undef S_R

static const cgs_config_int_t s_ints[] = {
    {"link", "interrogation_bits", offsetof (bcis_params_t, interrogation_bits), 1, 100000},
    {"link", "reply_bits", offsetof (bcis_params_t, reply_bits), 1, 100000},
    {"link", "correctable_bits", offsetof (bcis_params_t, correctable_bits), 0, 100000},
};

#define S_NREALS (sizeof s_reals / sizeof s_reals[0])
#define S_NINTS  (sizeof s_ints / sizeof s_ints[0])

static const char *const s_scan_names[] = {"full", "sector", NULL};
static const char *const s_ref_names[] = {"north", "heading", NULL};
static const char *const s_mod_names[] = {"bpsk", "qpsk", "bfsk", NULL};
static const char *const s_pol_names[] = {"horizontal", "vertical", "circular", NULL};

/* The consistency of the set, after each value's own range. cfg (may be
 * NULL) places the error on the key's line. */
static int s_check (cgs_config_t *cfg, const bcis_params_t *p, char *err, size_t errlen)
{
    const char *sec = NULL, *key = NULL;
    char msg[256] = "";
    cgs_config_table_out_of_range (s_reals, S_NREALS, s_ints, S_NINTS, p, &sec, &key, msg,
                                   sizeof msg);
    if (key) {
    } else if (p->max_range_m <= p->min_range_m) {
        sec = "interrogator", key = "max_range_m";
        snprintf (msg, sizeof msg, "must exceed min_range_m (%g m), got %g m", p->min_range_m,
                  p->max_range_m);
    } else if (p->correctable_bits >= p->interrogation_bits ||
               p->correctable_bits >= p->reply_bits) {
        sec = "link", key = "correctable_bits";
        snprintf (msg, sizeof msg,
                  "must be fewer than the bits of either message (%d and %d), got %d",
                  p->interrogation_bits, p->reply_bits, p->correctable_bits);
    } else if (p->scan_mode == CGS_SCAN_SECTOR && p->sector_width_deg < p->azimuth_beamwidth_deg) {
        sec = "scan", key = "sector_width_deg";
        snprintf (msg, sizeof msg, "must be at least the azimuth beamwidth (%g deg), got %g deg",
                  p->azimuth_beamwidth_deg, p->sector_width_deg);
    } else if ((unsigned)p->modulation > BCIS_MOD_BFSK) {
        sec = "link", key = "modulation";
        snprintf (msg, sizeof msg, "expected bpsk, qpsk or bfsk, got value %d", (int)p->modulation);
    } else if ((unsigned)p->polarization > BCIS_POL_CIRCULAR) {
        sec = "propagation", key = "polarization";
        snprintf (msg, sizeof msg, "expected horizontal, vertical or circular, got value %d",
                  (int)p->polarization);
    } else if ((unsigned)p->scan_mode > CGS_SCAN_SECTOR) {
        sec = "scan", key = "mode";
        snprintf (msg, sizeof msg, "expected full or sector, got value %d", (int)p->scan_mode);
    } else if ((unsigned)p->sector_ref > CGS_SECTOR_HEADING) {
        sec = "scan", key = "sector_reference";
        snprintf (msg, sizeof msg, "expected north or heading, got value %d", (int)p->sector_ref);
    }
    return key ? cgs_config_value_error (cfg, sec, key, msg, err, errlen) : 0;
}

int bcis_params_check (const bcis_params_t *p, char *err, size_t errlen)
{
    return s_check (NULL, p, err, errlen);
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    bcis_params_t *out = arg, p = *out;
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, S_NREALS, s_ints, S_NINTS, &p, err, errlen);
    int scan = p.scan_mode, ref = p.sector_ref, mod = p.modulation, pol = p.polarization;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "scan", "mode", s_scan_names, scan, &scan, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "scan", "sector_reference", s_ref_names, ref, &ref, err,
                                  errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "link", "modulation", s_mod_names, mod, &mod, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "propagation", "polarization", s_pol_names, pol, &pol, err,
                                  errlen);
    if (rc == 0)
        rc =
            cgs_config_get_bool (cfg, "propagation", "foliage", p.foliage, &p.foliage, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "transponder", "reports_position", p.reports_position,
                                  &p.reports_position, err, errlen);
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc < 0)
        return rc;
    p.scan_mode = (cgs_scan_mode_t)scan;
    p.sector_ref = (cgs_sector_ref_t)ref;
    p.modulation = (bcis_modulation_t)mod;
    p.polarization = (bcis_polarization_t)pol;
    if ((rc = s_check (cfg, &p, err, errlen)) < 0)
        return rc;
    *out = p;
    return 0;
}

int bcis_params_load (const char *path, bcis_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int bcis_params_load_string (const char *name, const char *text, bcis_params_t *p, char *err,
                             size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}

cgs_scan_params_t bcis_params_scan (const bcis_params_t *p)
{
    return (cgs_scan_params_t){
        .mode = p->scan_mode,
        .sector_center_deg = p->sector_center_deg,
        .sector_width_deg = p->sector_width_deg,
        .sector_ref = p->sector_ref,
        .beamwidth_deg = p->azimuth_beamwidth_deg,
        .rate_dps = p->scan_rate_dps,
    };
}
