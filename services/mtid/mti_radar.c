/* mti_radar — scan, geometry, radar equation, hits and false alarms of one
 * MTI radar (see mti_radar.h). */
#include "mti_radar.h"
#include "cgs_util.h"
#include "mti_dsp.h"
#include "mti_theory.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_C                   299792458.0
#define S_K_BOLTZ             1.380649e-23
#define S_DEG                 (M_PI / 180.0)
#define S_TGT_UP_M            2.0 // the target's reflecting centre above the ground, for line of sight
#define S_CALIBRATION_SAMPLES 4000 // draws estimating the any-bin crossing probability

#define S_PD_MIN_DB  -30.0 // the truth's Pd table: SINR from here...
#define S_PD_STEP_DB 0.05  // ... in these steps (Pd moves at most about 0.005 a step)
#define S_PD_BINS    1801  // ... to +60 dB

struct mti_radar {
    mti_params_t p;
    const cgs_terrain_t *terrain; // borrowed; NULL: flat ground at 0
    mti_dsp_t *dsp;
    double lambda_m;
    double k_radar;       // Pt tau G^2 lambda^2 / ((4 pi)^3 k T0 F L)
    cgs_scan_t scan;      // the schedule
    double cpi_pfa;       // probability of a crossing in any bin of a target-free CPI
    double gate_pfa;      // false-alarm probability of a gate in a dwell
    uint32_t gates;       // range gates between the limits
    uint32_t next_hit_id; // from 1
    double *cnr;          // 1 + ref_cells
    mti_hit_t *hits;
    size_t hit_count, hit_cap;
    mti_truth_t *truth;
    size_t truth_count, truth_cap;
    // The dwell Pd of a constant and of a Swerling I target (quadratures,
    // milliseconds each), by SINR in S_PD_STEP_DB bins, filled as met (NaN:
    // not yet).
    double pd_table[2][S_PD_BINS];
};

void mti_radar_destroy (mti_radar_t **self_p)
{
    assert (self_p);
    mti_radar_t *self = *self_p;
    if (!self)
        return;
    mti_dsp_destroy (&self->dsp);
    free (self->cnr);
    free (self->hits);
    free (self->truth);
    free (self);
    *self_p = NULL;
}

static double s_db (double x_db)
{
    return pow (10.0, x_db / 10.0);
}

mti_radar_t *mti_radar_new (const mti_params_t *p, const cgs_terrain_t *terrain, uint64_t seed)
{
    if (mti_params_check (p, NULL, 0) < 0)
        return NULL;
    mti_radar_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->terrain = terrain;
    self->next_hit_id = 1;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < S_PD_BINS; i++)
            self->pd_table[k][i] = NAN;
    self->dsp = mti_dsp_new (p, seed);
    self->cnr = calloc ((size_t)p->ref_cells + 1, sizeof (double));
    if (!self->dsp || !self->cnr)
        goto fail;
    self->lambda_m = mti_params_wavelength_m (p);
    double g = s_db (p->antenna_gain_db);
    self->k_radar = p->transmit_power_w * p->pulse_width_s * g * g * self->lambda_m *
                    self->lambda_m /
                    (pow (4.0 * M_PI, 3) * S_K_BOLTZ * p->noise_temperature_k *
                     s_db (p->noise_figure_db) * s_db (p->losses_db));
    cgs_scan_params_t sp = {
        .mode = p->scan_mode == MTI_SCAN_FULL ? CGS_SCAN_FULL : CGS_SCAN_SECTOR,
        .sector_center_deg = p->sector_center_deg,
        .sector_width_deg = p->sector_width_deg,
        .sector_ref = p->sector_ref == MTI_SECTOR_HEADING ? CGS_SECTOR_HEADING : CGS_SECTOR_NORTH,
        .beamwidth_deg = p->azimuth_beamwidth_deg,
        .rate_dps = p->sweep_rate_dps,
    };
    if (cgs_scan_init (&sp, &self->scan) < 0)
        goto fail;
    // The chance of a crossing in any Doppler bin of a CPI, with the
    // correlation the window and canceller put between bins.
    self->cpi_pfa = mti_dsp_any_bin_probability (self->dsp, S_CALIBRATION_SAMPLES);
    self->gate_pfa = mti_theory_m_of_n (self->cpi_pfa, p->m, p->n);
    self->gates = (uint32_t)floor ((p->max_range_m - p->min_range_m) / p->range_resolution_m);
    return self;
fail:
    mti_radar_destroy (&self);
    return NULL;
}

void mti_radar_reseed (mti_radar_t *self, uint64_t seed)
{
    mti_dsp_reseed (self->dsp, seed);
    self->next_hit_id = 1;
}

double mti_radar_dwell_s (const mti_radar_t *self)
{
    return self->scan.dwell_s;
}

uint32_t mti_radar_dwells_per_scan (const mti_radar_t *self)
{
    return self->scan.dwells;
}

double mti_radar_gate_pfa (const mti_radar_t *self)
{
    return self->gate_pfa;
}

double mti_radar_cpi_pfa (const mti_radar_t *self)
{
    return self->cpi_pfa;
}

uint32_t mti_radar_gates (const mti_radar_t *self)
{
    return self->gates;
}

struct mti_dsp *mti_radar_dsp (mti_radar_t *self)
{
    return self->dsp;
}

const cgs_scan_t *mti_radar_scan (const mti_radar_t *self)
{
    return &self->scan;
}

void mti_radar_schedule (const mti_radar_t *self, uint64_t k, double heading_deg, mti_dwell_t *ret)
{
    cgs_scan_dwell (&self->scan, k, heading_deg, ret);
}

uint64_t mti_radar_dwell_at (const mti_radar_t *self, double t_s)
{
    return cgs_scan_dwell_at (&self->scan, t_s);
}

static double s_height (const mti_radar_t *self, double e, double n)
{
    return self->terrain ? cgs_terrain_height_clamped (self->terrain, e, n) : 0.0;
}

static cgs_enu_t s_normal (const mti_radar_t *self, double e, double n)
{
    return self->terrain ? cgs_terrain_normal (self->terrain, e, n) : (cgs_enu_t){0, 0, 1};
}

static bool s_los (const mti_radar_t *self, cgs_enu_t a, cgs_enu_t b)
{
    return self->terrain ? cgs_terrain_los (self->terrain, a, b) : true;
}

/* Grazing angle (degrees) at ground point q seen from p: between the line of
 * sight and the surface; <= 0 when the surface faces away. */
static double s_grazing_deg (const mti_radar_t *self, cgs_enu_t p, cgs_enu_t q)
{
    double de = p.e_m - q.e_m, dn = p.n_m - q.n_m, du = p.u_m - q.u_m;
    double r = sqrt (de * de + dn * dn + du * du);
    if (r <= 0)
        return 90.0;
    cgs_enu_t nrm = s_normal (self, q.e_m, q.n_m);
    double s = (de * nrm.e_m + dn * nrm.n_m + du * nrm.u_m) / r;
    return asin (fmax (-1.0, fmin (1.0, s))) / S_DEG;
}

static double s_el_gain (const mti_radar_t *self, double off_deg)
{
    double x = off_deg / self->p.elevation_beamwidth_deg;
    return exp (-8.0 * M_LN2 * x * x);
}

double mti_radar_snr (const mti_radar_t *self, double rcs_m2, double r_m, double depression_off_deg)
{
    double r2 = r_m * r_m;
    return self->k_radar * rcs_m2 * s_el_gain (self, depression_off_deg) / (r2 * r2);
}

double mti_radar_cnr (const mti_radar_t *self, double r_m, double psi_deg,
                      double depression_off_deg)
{
    if (!(psi_deg > 0))
        return 0;
    double psi = fmin (psi_deg, 80.0) * S_DEG; // the patch formula fails looking straight down
    double sigma0 = s_db (self->p.clutter_gamma_db) * sin (psi);
    double area =
        r_m * self->p.azimuth_beamwidth_deg * S_DEG * self->p.range_resolution_m / cos (psi);
    return mti_radar_snr (self, sigma0 * area, r_m, depression_off_deg);
}

double mti_radar_clutter_sigma_hz (const mti_radar_t *self, double v_mps, double alpha_deg)
{
    double lam = self->lambda_m, th = self->p.azimuth_beamwidth_deg;
    double s_int = 2.0 * self->p.clutter_internal_mps / lam;
    double s_pm = 0.3 * th * S_DEG * 2.0 * v_mps / lam * fabs (sin (alpha_deg * S_DEG));
    double s_scan = 0.265 * self->p.sweep_rate_dps / th;
    return sqrt (s_int * s_int + s_pm * s_pm + s_scan * s_scan);
}

static int s_add_hit (mti_radar_t *self, mti_hit_t *h)
{
    if (cgs_grow ((void **)&self->hits, &self->hit_cap, self->hit_count + 1, sizeof *h) < 0)
        return -ENOMEM;
    h->hit_id = self->next_hit_id++;
    if (self->next_hit_id == 0)
        self->next_hit_id = 1;
    self->hits[self->hit_count++] = *h;
    return 0;
}

/* Measured hit from a true range (gate centre) and azimuth with noise: the
 * azimuth by the parameters' method (mti_azimuth.h), sinr the interval's
 * SINR in the detection's bin for a target at the beam's centre,
 * fluctuation each interval's target power over its mean. */
static void s_measure (mti_radar_t *self, const mti_dwell_t *d, cgs_enu_t p, double r, double az,
                       double sinr, const double *fluctuation, mti_hit_t *h)
{
    double dr = self->p.range_resolution_m, th = self->p.azimuth_beamwidth_deg;
    h->range_m = (floor (r / dr) + 0.5) * dr;
    h->range_sigma_m = dr / sqrt (12.0);
    int n = self->p.n;
    if (self->p.azimuth == MTI_AZIMUTH_MONOPULSE || n < 2) {
        // One interval cannot split the beam: the beam's width is what is known.
        h->azimuth_sigma_deg = n < 2 ? th / sqrt (12.0) : mti_azimuth_monopulse_sigma (th, sinr);
        h->azimuth_deg = cgs_wrap360 (az + h->azimuth_sigma_deg * mti_dsp_gaussian (self->dsp));
    } else {
        // The beam sweeps from az_from to az_to; looks are measured clockwise.
        double dir = remainder (d->az_to_deg - d->az_from_deg, 360.0) >= 0 ? 1.0 : -1.0;
        double u = remainder (az - d->az_center_deg, 360.0), b = 8.0 * M_LN2 / (th * th);
        double x[MTI_N_MAX], y[MTI_N_MAX];
        for (int c = 0; c < n; c++) {
            x[c] = dir * mti_azimuth_look_deg (d->width_deg, n, c);
            double a = sqrt (fmax (sinr, 0) * fluctuation[c] * exp (-b * (u - x[c]) * (u - x[c])));
            double re = a + M_SQRT1_2 * mti_dsp_gaussian (self->dsp),
                   im = M_SQRT1_2 * mti_dsp_gaussian (self->dsp);
            y[c] = fmax (re * re + im * im, 1e-300);
        }
        double est, sigma;
        if (mti_azimuth_beam_split (y, x, n, th, d->width_deg, MTI_AZIMUTH_LN_EXP_VAR, &est,
                                    &sigma) < 0) {
            est = 0; // cannot happen with n >= 2 looks apart; the dwell's centre if it did
            sigma = th / sqrt (12.0);
        }
        h->azimuth_deg = cgs_wrap360 (d->az_center_deg + est);
        h->azimuth_sigma_deg = sigma;
    }
    (void)cgs_terrain_at_slant_range (self->terrain, p, h->azimuth_deg, h->range_m, &h->position);
}

/* The dwell's detection probability (m of its n coherent intervals) in a
 * bin of expected SINR, by the target's fluctuation model (mti_theory).
 * The closed form is cheap for a target drawn anew each interval; the
 * constant and the Swerling I target need quadratures, so theirs are taken
 * at the SINR rounded to S_PD_STEP_DB and kept. */
static double s_pd_dwell (mti_radar_t *self, mti_swerling_t model, double sinr)
{
    double t = mti_dsp_threshold (self->dsp);
    int nr = self->p.ref_cells, m = self->p.m, n = self->p.n;
    if (model != MTI_SWERLING_0 && (model != MTI_SWERLING_1 || (m == 1 && n == 1)))
        // a new draw each interval (or each pulse, sinr then without coherent gain)
        return mti_theory_m_of_n (mti_theory_pd_swerling_cacfar (sinr, t, nr), m, n);
    double db = sinr > 0 ? 10 * log10 (sinr) : S_PD_MIN_DB;
    long i = lround ((db - S_PD_MIN_DB) / S_PD_STEP_DB);
    i = i < 0 ? 0 : i >= S_PD_BINS ? S_PD_BINS - 1 : i;
    double *pd = &self->pd_table[model == MTI_SWERLING_1][i];
    if (isnan (*pd)) {
        double s = pow (10, (S_PD_MIN_DB + (double)i * S_PD_STEP_DB) / 10);
        *pd = model == MTI_SWERLING_1
                  ? mti_theory_pd_swerling1_m_of_n (s, t, nr, m, n)
                  : mti_theory_m_of_n (mti_theory_pd_constant_cacfar (s, t, nr), m, n);
    }
    return *pd;
}

static int s_target (mti_radar_t *self, const mti_dwell_t *d, const mti_platform_t *plat,
                     const mti_target_t *tg, double sigma_hz)
{
    const mti_params_t *p = &self->p;
    cgs_enu_t a = plat->position, q = tg->position;
    double de = q.e_m - a.e_m, dn = q.n_m - a.n_m, du = q.u_m - a.u_m;
    double g = hypot (de, dn), r = sqrt (de * de + dn * dn + du * du);
    if (r < p->min_range_m || r > p->max_range_m || g <= 0)
        return 0;
    double az = cgs_wrap360 (atan2 (de, dn) / S_DEG);
    if (!cgs_dwell_contains (d, az))
        return 0;
    double off = atan2 (-du, g) / S_DEG - p->beam_depression_deg;
    if (fabs (off) > p->elevation_beamwidth_deg)
        return 0;
    if (cgs_grow ((void **)&self->truth, &self->truth_cap, self->truth_count + 1,
                  sizeof (mti_truth_t)) < 0)
        return -ENOMEM;
    mti_truth_t *tr = &self->truth[self->truth_count++];
    double vr = (tg->velocity.e_m * de + tg->velocity.n_m * dn + tg->velocity.u_m * du) / r;
    *tr = (mti_truth_t){
        .entity_id = tg->id, .range_m = r, .radial_velocity_mps = vr, .snr_db = -INFINITY};
    cgs_enu_t top = {q.e_m, q.n_m, q.u_m + S_TGT_UP_M};
    if (!s_los (self, a, top))
        return 0; // hidden: no return
    tr->visible = true;
    const mti_class_t *cls = mti_params_class (p, tg->rcs_class ? tg->rcs_class : "", NULL);
    double snr = mti_radar_snr (self, cls->rcs_m2, r, off);
    // Clutter: the target's cell, then the reference cells on both sides.
    self->cnr[0] = mti_radar_cnr (self, r, s_grazing_deg (self, a, q), off);
    int half = p->ref_cells / 2;
    for (int i = 1; i <= half; i++)
        for (int side = -1; side <= 1; side += 2) {
            double rc = r + side * (p->guard_cells + i) * p->range_resolution_m;
            double cnr = 0;
            cgs_enu_t c;
            if (rc > 0 && cgs_terrain_at_slant_range (self->terrain, a, az, rc,
                                                      &c)) { // no clutter short of the ground
                cgs_enu_t c_up = {c.e_m, c.n_m, c.u_m + 0.5};
                double off_c = atan2 (a.u_m - c.u_m, hypot (c.e_m - a.e_m, c.n_m - a.n_m)) / S_DEG -
                               p->beam_depression_deg;
                if (s_los (self, a, c_up))
                    cnr = mti_radar_cnr (self, rc, s_grazing_deg (self, a, c), off_c);
            }
            self->cnr[side < 0 ? i : half + i] = cnr;
        }
    double f = -2.0 * vr / self->lambda_m;
    mti_dsp_input_t in = {.snr = snr,
                          .doppler_hz = f,
                          .swerling = cls->swerling,
                          .clutter_sigma_hz = sigma_hz,
                          .cnr = self->cnr};
    mti_dsp_result_t res;
    int rc = mti_dsp_dwell (self->dsp, &in, &res);
    if (rc < 0)
        return rc;
    double nz, cl, sg;
    mti_dsp_bin_response (self->dsp, mti_dsp_bin_of (self->dsp, f), f,
                          cls->swerling == MTI_SWERLING_2_PULSE, &nz, &cl, &sg);
    double sinr = snr * sg / (nz + self->cnr[0] * cl);
    tr->snr_db = 10.0 * log10 (sinr);
    tr->pd = s_pd_dwell (self, cls->swerling, sinr);
    if (!res.detected)
        return 0;
    mti_hit_t h = {.entity_id = tg->id};
    s_measure (self, d, a, r, az, sinr, res.fluctuation, &h);
    h.radial_velocity_mps = -res.doppler_hz * self->lambda_m / 2.0;
    h.snr_db = 10.0 * log10 (res.ratio);
    if (s_add_hit (self, &h) < 0)
        return -ENOMEM;
    // The truth array may not have moved (hits are a separate array).
    tr->detected = true;
    tr->hit_id = h.hit_id;
    return 0;
}

static int s_false_alarms (mti_radar_t *self, const mti_dwell_t *d, const mti_platform_t *plat)
{
    const mti_params_t *p = &self->p;
    // Only gates that reach the ground (range beyond the UAV's height) hold
    // cells to test.
    double agl = plat->position.u_m - s_height (self, plat->position.e_m, plat->position.n_m);
    double first = ceil ((agl - p->min_range_m) / p->range_resolution_m);
    uint32_t g0 = first > 0 ? (first < self->gates ? (uint32_t)first : self->gates) : 0;
    uint32_t gates = self->gates - g0;
    unsigned int count = gates ? mti_dsp_binomial (self->dsp, self->gate_pfa, gates) : 0;
    double t = mti_dsp_threshold (self->dsp);
    double lo = cgs_dwell_lo_deg (d);
    double steady[MTI_N_MAX]; // a false alarm's echo, as beam splitting sees it
    for (int c = 0; c < MTI_N_MAX; c++)
        steady[c] = 1.0;
    for (unsigned int i = 0; i < count; i++) {
        uint32_t gate = g0 + (uint32_t)(mti_dsp_uniform (self->dsp) * gates);
        double r = p->min_range_m + (gate + 0.5) * p->range_resolution_m;
        double az = cgs_wrap360 (lo + mti_dsp_uniform (self->dsp) * d->width_deg);
        int bin = (int)(mti_dsp_uniform (self->dsp) * p->fft_size);
        // An exceedance X > T Z: given it, Z ~ Gamma(N, 1 / (1 + T)) (the
        // crossing tilts Z by exp(-T Z)) and X - T Z is exponential (memoryless).
        double z = mti_dsp_gamma (self->dsp, p->ref_cells) / (1.0 + t);
        double x = t * z - log (1.0 - mti_dsp_uniform (self->dsp));
        double ratio = x / (z / p->ref_cells);
        mti_hit_t h = {.entity_id = 0};
        s_measure (self, d, plat->position, r, az, ratio, steady, &h);
        h.radial_velocity_mps = -mti_dsp_bin_hz (self->dsp, bin) * self->lambda_m / 2.0;
        h.snr_db = 10.0 * log10 (ratio);
        if (s_add_hit (self, &h) < 0)
            return -ENOMEM;
    }
    return (int)count;
}

/* Targets the radar does not resolve: two hits of one dwell in the same
 * range gate and the same or the next Doppler bin (the window spreads one
 * echo's peak over its neighbours, and the noise picks which wins) are one
 * echo. The stronger's hit
 * stands for both, its azimuth the power-weighted mean of the two (where
 * the beam splitting puts a two-scatterer echo), on the ground there; the
 * weaker's truth says it was merged. (Each target's detection is still
 * decided alone: the summed echo is not re-detected.) */
static void s_merge_unresolved (mti_radar_t *self, cgs_enu_t antenna)
{
    double dr = self->p.range_resolution_m;
    double dv = fabs (mti_dsp_bin_hz (self->dsp, 1) - mti_dsp_bin_hz (self->dsp, 0)) *
                self->lambda_m / 2;                    // one Doppler bin, in radial velocity
    double span = self->p.prf_hz * self->lambda_m / 2; // the bins wrap around: λ·PRF/2
    for (size_t i = 0; i < self->hit_count; i++)
        for (size_t j = i + 1; j < self->hit_count;) {
            mti_hit_t *a = &self->hits[i], *b = &self->hits[j];
            if (a->entity_id == 0 || b->entity_id == 0 ||
                fabs (a->range_m - b->range_m) >= 0.5 * dr ||
                fabs (remainder (a->radial_velocity_mps - b->radial_velocity_mps, span)) >=
                    1.5 * dv) {
                j++;
                continue;
            }
            if (b->snr_db > a->snr_db) { // the stronger stays, in slot i (ids stay:
                mti_hit_t t = *a;        // slot 0 keeps the dwell's first, which
                *a = *b;                 // s_shuffle_hits numbers from)
                *b = t;
                uint32_t id = a->hit_id;
                a->hit_id = b->hit_id;
                b->hit_id = id;
            }
            double wa = pow (10, a->snr_db / 10), wb = pow (10, b->snr_db / 10);
            double d = remainder (b->azimuth_deg - a->azimuth_deg, 360.0);
            a->azimuth_deg = cgs_wrap360 (a->azimuth_deg + d * wb / (wa + wb));
            a->snr_db = 10 * log10 (wa + wb); // the echo's power: what a third weighs against
            (void)cgs_terrain_at_slant_range (self->terrain, antenna, a->azimuth_deg, a->range_m,
                                              &a->position);
            for (size_t k = 0; k < self->truth_count; k++) {
                mti_truth_t *tr = &self->truth[k];
                if ((tr->detected && tr->entity_id == b->entity_id) ||
                    tr->merged_with == b->entity_id) {
                    tr->detected = false;
                    tr->hit_id = 0;
                    tr->merged_with = a->entity_id; // its hit id is given with the ids
                }
            }
            self->hits[j] = self->hits[--self->hit_count];
            j = i + 1; // slot i changed: every other hit is weighed against it again
        }
}

/* Put the dwell's hits in random order and number them in that order, so
 * neither the order nor the ids tell targets from false alarms. */
static void s_shuffle_hits (mti_radar_t *self)
{
    size_t n = self->hit_count;
    if (n == 0)
        return;
    uint32_t first = self->hits[0].hit_id;
    for (size_t i = n - 1; i > 0; i--) {
        size_t j = (size_t)(mti_dsp_uniform (self->dsp) * (double)(i + 1));
        if (j > i)
            j = i;
        mti_hit_t tmp = self->hits[i];
        self->hits[i] = self->hits[j];
        self->hits[j] = tmp;
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t id = first + (uint32_t)i;
        if (id < first) // wrapped past 0
            id += 1;
        self->hits[i].hit_id = id;
        if (self->hits[i].entity_id == 0)
            continue;
        for (size_t k = 0; k < self->truth_count; k++) {
            if (self->truth[k].entity_id == self->hits[i].entity_id && self->truth[k].detected)
                self->truth[k].hit_id = id;
            if (self->truth[k].merged_with == self->hits[i].entity_id)
                self->truth[k].merged_into = id;
        }
    }
}

int mti_radar_dwell (mti_radar_t *self, const mti_dwell_t *d, const mti_platform_t *plat,
                     const mti_target_t *targets, size_t n, mti_dwell_out_t *ret)
{
    self->hit_count = 0;
    self->truth_count = 0;
    // One clutter spectrum per dwell, at the beam's centre.
    double v = hypot (plat->velocity.e_m, plat->velocity.n_m);
    double track = atan2 (plat->velocity.e_m, plat->velocity.n_m) / S_DEG;
    double sigma = mti_radar_clutter_sigma_hz (self, v, d->az_center_deg - track);
    for (size_t i = 0; i < n; i++) {
        int rc = s_target (self, d, plat, &targets[i], sigma);
        if (rc < 0)
            return rc;
    }
    s_merge_unresolved (self, plat->position);
    int fa = s_false_alarms (self, d, plat);
    if (fa < 0)
        return fa;
    s_shuffle_hits (self);
    *ret = (mti_dwell_out_t){.hits = self->hits,
                             .hit_count = self->hit_count,
                             .truth = self->truth,
                             .truth_count = self->truth_count,
                             .false_alarms = (uint32_t)fa};
    return 0;
}
