/* bcis_link — the BCIS link budget and its error probabilities (see bcis_link.h). */
#include "bcis_link.h"

#include <gsl/gsl_cdf.h>
#include <math.h>

#define S_C       299792458.0
#define S_K_BOLTZ 1.380649e-23
#define S_DEG     (M_PI / 180.0)

double bcis_fspl_db (double f_hz, double d_m)
{
    return 20.0 * log10 (4.0 * M_PI * d_m * f_hz / S_C);
}

/* log10 k or alpha by P.838-3's regression: sum of Gaussians in log10 f plus
 * a line; n terms a, b, c, then m and the constant. */
static double s_fit (const double *a, const double *b, const double *c, int n, double m, double k,
                     double f_ghz)
{
    double x = log10 (f_ghz), sum = 0;
    for (int j = 0; j < n; j++) {
        double z = (x - b[j]) / c[j];
        sum += a[j] * exp (-z * z);
    }
    return sum + m * x + k;
}

void bcis_p838 (double f_ghz, double *ret_kh, double *ret_ah, double *ret_kv, double *ret_av)
{
    // Recommendation ITU-R P.838-3, tables 1 to 4.
    static const double kh_a[] = {-5.33980, -0.35351, -0.23789, -0.94158},
                        kh_b[] = {-0.10008, 1.26970, 0.86036, 0.64552},
                        kh_c[] = {1.13098, 0.45400, 0.15354, 0.16817};
    static const double kv_a[] = {-3.80595, -3.44965, -0.39902, 0.50167},
                        kv_b[] = {0.56934, -0.22911, 0.73042, 1.07319},
                        kv_c[] = {0.81061, 0.51059, 0.11899, 0.27195};
    static const double ah_a[] = {-0.14318, 0.29591, 0.32177, -5.37610, 16.1721},
                        ah_b[] = {1.82442, 0.77564, 0.63773, -0.96230, -3.29980},
                        ah_c[] = {-0.55187, 0.19822, 0.13164, 1.47828, 3.43990};
    static const double av_a[] = {-0.07771, 0.56727, -0.20238, -48.2991, 48.5833},
                        av_b[] = {2.33840, 0.95545, 1.14520, 0.791669, 0.791459},
                        av_c[] = {-0.76284, 0.54039, 0.26809, 0.116226, 0.116479};
    *ret_kh = pow (10.0, s_fit (kh_a, kh_b, kh_c, 4, -0.18961, 0.71147, f_ghz));
    *ret_kv = pow (10.0, s_fit (kv_a, kv_b, kv_c, 4, -0.16398, 0.63297, f_ghz));
    *ret_ah = s_fit (ah_a, ah_b, ah_c, 5, 0.67849, -1.95537, f_ghz);
    *ret_av = s_fit (av_a, av_b, av_c, 5, -0.053739, 0.83433, f_ghz);
}

double bcis_rain_db_per_km (double f_ghz, double rate_mmph, double elevation_deg, double tau_deg)
{
    if (rate_mmph <= 0)
        return 0;
    double kh, ah, kv, av;
    bcis_p838 (f_ghz, &kh, &ah, &kv, &av);
    double ce = cos (elevation_deg * S_DEG), w = ce * ce * cos (2.0 * tau_deg * S_DEG);
    double k = (kh + kv + (kh - kv) * w) / 2.0;
    double alpha = (kh * ah + kv * av + (kh * ah - kv * av) * w) / (2.0 * k);
    return k * pow (rate_mmph, alpha);
}

double bcis_foliage_db (double f_ghz, double depth_m)
{
    if (depth_m <= 0)
        return 0;
    double ff = pow (f_ghz, 0.284);
    return depth_m <= 14.0 ? 0.45 * ff * depth_m : 1.33 * ff * pow (depth_m, 0.588);
}

double bcis_pattern_db (double off_deg, double beamwidth_deg)
{
    double x = off_deg / beamwidth_deg;
    return 12.0 * x * x;
}

double bcis_ber (bcis_modulation_t m, double ebn0)
{
    if (m == BCIS_MOD_BFSK)
        return 0.5 * exp (-ebn0 / 2.0);
    return 0.5 * erfc (sqrt (ebn0)); // Q(sqrt(2 Eb/N0))
}

double bcis_message_p (double ber, int bits, int correctable)
{
    if (ber <= 0)
        return 1;
    if (correctable == 0)
        return exp ((double)bits * log1p (-ber));
    return gsl_cdf_binomial_P ((unsigned int)correctable, ber, (unsigned int)bits);
}

double bcis_tilt_deg (bcis_polarization_t pol)
{
    return pol == BCIS_POL_HORIZONTAL ? 0.0 : pol == BCIS_POL_VERTICAL ? 90.0 : 45.0;
}

static double s_dbw (double w)
{
    return 10.0 * log10 (w);
}

void bcis_budget (const bcis_params_t *p, const bcis_geometry_t *g, bcis_budget_t *ret)
{
    bcis_budget_t b = {0};
    double f_ghz = p->frequency_hz / 1e9;
    b.fspl_db = bcis_fspl_db (p->frequency_hz, g->range_m);
    b.atmospheric_db = p->atmospheric_db_per_km * g->range_m / 1000.0;
    b.rain_db_per_km = bcis_rain_db_per_km (f_ghz, p->rain_rate_mmph, g->elevation_deg,
                                            bcis_tilt_deg (p->polarization));
    b.rain_db = b.rain_db_per_km * g->rain_path_m / 1000.0;
    b.foliage_db = p->foliage ? bcis_foliage_db (f_ghz, g->foliage_m) : 0;
    b.pattern_db = bcis_pattern_db (g->az_off_deg, p->azimuth_beamwidth_deg) +
                   bcis_pattern_db (g->el_off_deg, p->elevation_beamwidth_deg);
    b.path_loss_db = b.fspl_db + b.atmospheric_db + b.rain_db + b.foliage_db;
    double rb_db = s_dbw (p->data_rate_bps), kt_db = s_dbw (S_K_BOLTZ * p->noise_temperature_k);
    // Up: the interrogation, interrogator to transponder.
    b.up_eirp_dbw = s_dbw (p->transmit_power_w) + p->antenna_gain_db - p->losses_db - b.pattern_db;
    b.up_rx_dbw =
        b.up_eirp_dbw - b.path_loss_db + p->transponder_gain_db - p->transponder_losses_db;
    b.up_noise_dbw = kt_db + p->transponder_noise_figure_db + rb_db;
    b.up_ebn0_db = b.up_rx_dbw - b.up_noise_dbw;
    // Down: the reply, through the same path and the same beam.
    b.down_eirp_dbw =
        s_dbw (p->transponder_power_w) + p->transponder_gain_db - p->transponder_losses_db;
    b.down_rx_dbw =
        b.down_eirp_dbw - b.path_loss_db + p->antenna_gain_db - b.pattern_db - p->losses_db;
    b.down_noise_dbw = kt_db + p->noise_figure_db + rb_db;
    b.down_ebn0_db = b.down_rx_dbw - b.down_noise_dbw;
    b.up_ber = bcis_ber (p->modulation, pow (10.0, b.up_ebn0_db / 10.0));
    b.down_ber = bcis_ber (p->modulation, pow (10.0, b.down_ebn0_db / 10.0));
    b.p_up = bcis_message_p (b.up_ber, p->interrogation_bits, p->correctable_bits);
    b.p_down = bcis_message_p (b.down_ber, p->reply_bits, p->correctable_bits);
    b.p_reply = b.p_up * b.p_down;
    *ret = b;
}
