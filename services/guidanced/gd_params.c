/* gd_params — guidanced's parameter file (see gd_params.h). */
#include "gd_params.h"
#include "cgs_config.h"

#include <errno.h>
#include <stddef.h>
#include <stdio.h>

void gd_params_defaults (gd_params_t *p)
{
    *p = (gd_params_t){
        .timing = GD_TIMING_ROUTE,
        .turn_radius_factor = 1.5,
        .secondary = GD_SECONDARY_PAPER,
        .secondary_scale = 0.25,
        .lead_in_m = 2000,
        .secondary_offset_max_m = 6000,
        .settle_m = 800,
        .horizon_s = 900,
        .runout_m = 1500,
        .arc_step_deg = 15,
        .min_target_speed_mps = 1.0,
        .max_target_speed_mps = 30,
        .threshold_deg = 20,
        .offset_m = 150,
        .significance = 2,
        .align_deg = 20,
        .lost_after_s = 300,
        .handover_m = 400,
        .handover_growth_mps = 20,
        .handover = GD_HANDOVER_LINKS,
        .confirm_margin_m = -25,
        .pick_radius_m = 2000,
        .max_range_m = 20000,
    };
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (gd_params_t, field), lo, hi                                              \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("plan", "turn_radius_factor", turn_radius_factor, 1.0, 10.0),
    S_R ("plan", "secondary_scale", secondary_scale, 0.0, 10.0),
    S_R ("plan", "lead_in_m", lead_in_m, 0.0, 1e5),
    S_R ("plan", "secondary_offset_max_m", secondary_offset_max_m, 0.0, 1e6),
    S_R ("plan", "settle_m", settle_m, 0.0, 1e4),
    S_R ("plan", "horizon_s", horizon_s, 10.0, 86400.0),
    S_R ("plan", "runout_m", runout_m, 0.0, 1e5),
    S_R ("plan", "arc_step_deg", arc_step_deg, 1.0, 90.0),
    S_R ("plan", "min_target_speed_mps", min_target_speed_mps, 0.01, 100.0),
    S_R ("plan", "max_target_speed_mps", max_target_speed_mps, 0.1, 1000.0),
    S_R ("replan", "threshold_deg", threshold_deg, 0.1, 179.0),
    S_R ("replan", "offset_m", offset_m, 1.0, 1e5),
    S_R ("replan", "significance", significance, 0.0, 100.0),
    S_R ("approach", "align_deg", align_deg, 1.0, 90.0),
    S_R ("approach", "lost_after_s", lost_after_s, 1.0, 86400.0),
    S_R ("approach", "handover_m", handover_m, 0.0, 1e5),
    S_R ("approach", "handover_growth_mps", handover_growth_mps, 0.0, 100.0),
    S_R ("approach", "confirm_margin_m", confirm_margin_m, -1e3, 1e4),
    S_R ("designation", "pick_radius_m", pick_radius_m, 1.0, 1e6),
    S_R ("footprint", "max_range_m", max_range_m, 100.0, 1e6),
};
#undef S_R
#define S_NREALS (sizeof s_reals / sizeof s_reals[0])

int gd_params_check (const gd_params_t *p, char *err, size_t errlen)
{
    const char *sec = NULL, *key = NULL;
    char msg[256] = "";
    cgs_config_table_out_of_range (s_reals, S_NREALS, NULL, 0, p, &sec, &key, msg, sizeof msg);
    if (!key && p->timing != GD_TIMING_ROUTE && p->timing != GD_TIMING_ARC) {
        sec = "plan";
        key = "timing";
        snprintf (msg, sizeof msg, "expected route or arc, got %d", (int)p->timing);
    }
    if (!key && p->secondary != GD_SECONDARY_EXTENDED && p->secondary != GD_SECONDARY_PAPER) {
        sec = "plan";
        key = "secondary";
        snprintf (msg, sizeof msg, "expected extended or paper, got %d", (int)p->secondary);
    }
    if (!key && p->handover != GD_HANDOVER_NEAR && p->handover != GD_HANDOVER_LINKS) {
        sec = "approach";
        key = "handover";
        snprintf (msg, sizeof msg, "expected near or links, got %d", (int)p->handover);
    }
    return key ? cgs_config_value_error (NULL, sec, key, msg, err, errlen) : 0;
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    gd_params_t *out = arg, p = *out;
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, S_NREALS, NULL, 0, &p, err, errlen);
    static const char *const timings[] = {"route", "arc", NULL};
    int timing = (int)p.timing;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "plan", "timing", timings, timing, &timing, err, errlen);
    p.timing = (gd_timing_t)timing;
    static const char *const secondaries[] = {"extended", "paper", NULL};
    int secondary = (int)p.secondary;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "plan", "secondary", secondaries, secondary, &secondary, err,
                                  errlen);
    p.secondary = (gd_secondary_t)secondary;
    static const char *const handovers[] = {"near", "links", NULL};
    int handover = (int)p.handover;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "approach", "handover", handovers, handover, &handover, err,
                                  errlen);
    p.handover = (gd_handover_t)handover;
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc < 0)
        return rc;
    *out = p;
    return 0;
}

int gd_params_load (const char *path, gd_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int gd_params_load_string (const char *name, const char *text, gd_params_t *p, char *err,
                           size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}
