/* uavsim_camera — each UAV's imaging sensor settings (see uavsim_camera.h). */
#include "uavsim_camera.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

void uavsim_camera_init (uavsim_camera_t *c, const cgs_scenario_uav_t *su)
{
    *c = (uavsim_camera_t){
        .depression_deg = su->sensor_depression_deg,
        .hfov_deg = su->sensor_hfov_deg,
        .vfov_deg = su->sensor_vfov_deg,
        .stabilized = su->sensor_stabilized,
        .stare = su->sensor_stare_target ? UAVSIM_STARE_TARGET : UAVSIM_STARE_OFF,
    };
}

/* The vertical field of view for a horizontal one: the scenario's aspect,
 * tan(β/2)/tan(γ/2), kept. */
static double s_vfov (const cgs_scenario_uav_t *su, double hfov_deg)
{
    const double r = M_PI / 360.0;
    double k = tan (su->sensor_vfov_deg * r) / tan (su->sensor_hfov_deg * r);
    return atan (k * tan (hfov_deg * r)) / r;
}

int uavsim_camera_set (uavsim_camera_t *c, const cgs_scenario_uav_t *su,
                       const cgs_terrain_t *terrain, const uavsim_camera_cmd_t *cmd, char *why,
                       size_t whylen)
{
    uavsim_camera_t n = *c;
    const uint32_t all = UAVSIM_CAMERA_SET_DEPRESSION | UAVSIM_CAMERA_SET_FOV |
                         UAVSIM_CAMERA_SET_STABILIZED | UAVSIM_CAMERA_SET_STARE;
    if (!cmd->set || (cmd->set & ~all)) {
        snprintf (why, whylen, "camera refused: nothing to set (set bits 1 to 15, got %u)",
                  (unsigned)cmd->set);
        return -EINVAL;
    }
    if (cmd->set & UAVSIM_CAMERA_SET_DEPRESSION) {
        if (!(cmd->depression_deg >= su->sensor_depression_min_deg &&
              cmd->depression_deg <= su->sensor_depression_max_deg)) {
            snprintf (why, whylen,
                      "camera refused: depression %.6g deg is outside the scenario's "
                      "%.6g..%.6g deg",
                      cmd->depression_deg, su->sensor_depression_min_deg,
                      su->sensor_depression_max_deg);
            return -EINVAL;
        }
        n.depression_deg = cmd->depression_deg;
    }
    if (cmd->set & UAVSIM_CAMERA_SET_FOV) {
        if (!(cmd->hfov_deg >= su->sensor_hfov_min_deg &&
              cmd->hfov_deg <= su->sensor_hfov_max_deg)) {
            snprintf (why, whylen,
                      "camera refused: field of view %.6g deg is outside the scenario's "
                      "%.6g..%.6g deg",
                      cmd->hfov_deg, su->sensor_hfov_min_deg, su->sensor_hfov_max_deg);
            return -EINVAL;
        }
        n.hfov_deg = cmd->hfov_deg;
        n.vfov_deg = s_vfov (su, cmd->hfov_deg);
    }
    if (cmd->set & UAVSIM_CAMERA_SET_STABILIZED)
        n.stabilized = cmd->stabilized;
    if (cmd->set & UAVSIM_CAMERA_SET_STARE) {
        switch (cmd->stare) {
        case UAVSIM_STARE_OFF:
        case UAVSIM_STARE_TARGET:
            break;
        case UAVSIM_STARE_POINT: {
            double h;
            if (!isfinite (cmd->stare_point.e_m) || !isfinite (cmd->stare_point.n_m) ||
                (terrain && cgs_terrain_height (terrain, cmd->stare_point.e_m, cmd->stare_point.n_m,
                                                &h) < 0)) {
                snprintf (why, whylen,
                          "camera refused: the stare point (%.6g, %.6g) is not on the terrain",
                          cmd->stare_point.e_m, cmd->stare_point.n_m);
                return -EINVAL;
            }
            n.stare_point =
                (cgs_enu_t){cmd->stare_point.e_m, cmd->stare_point.n_m, terrain ? h : 0.0};
            break;
        }
        default:
            snprintf (why, whylen, "camera refused: unknown stare mode %d", (int)cmd->stare);
            return -EINVAL;
        }
        n.stare = cmd->stare;
    }
    *c = n;
    return 0;
}

void uavsim_camera_target (uavsim_camera_t *c, bool have, cgs_enu_t p, cgs_enu_t v, double t_s)
{
    bool ok = have && isfinite (p.e_m) && isfinite (p.n_m) && isfinite (v.e_m) &&
              isfinite (v.n_m) && isfinite (t_s);
    c->have_target = ok;
    if (ok) {
        c->target = p;
        c->target_vel = v;
        c->target_t_s = t_s;
    }
}

bool uavsim_camera_stare_at (const uavsim_camera_t *c, const cgs_terrain_t *terrain, double t_s,
                             cgs_enu_t *ret)
{
    if (c->stare == UAVSIM_STARE_POINT) {
        *ret = c->stare_point;
        return true;
    }
    if (c->stare != UAVSIM_STARE_TARGET || !c->have_target)
        return false;
    double dt = isfinite (t_s - c->target_t_s) ? t_s - c->target_t_s : 0.0;
    cgs_enu_t p = {c->target.e_m + c->target_vel.e_m * dt, c->target.n_m + c->target_vel.n_m * dt,
                   0};
    p.u_m = cgs_terrain_height_clamped (terrain, p.e_m, p.n_m);
    *ret = p;
    return true;
}

static void s_put (uint8_t *out, size_t *at, double d)
{
    memcpy (out + *at, &d, sizeof d);
    *at += sizeof d;
}

static double s_get (const uint8_t *buf, size_t *at)
{
    double d;
    memcpy (&d, buf + *at, sizeof d);
    *at += sizeof d;
    return d;
}

void uavsim_camera_save (const uavsim_camera_t *c, uint8_t out[UAVSIM_CAMERA_SAVED])
{
    size_t at = 0;
    s_put (out, &at, c->depression_deg);
    s_put (out, &at, c->hfov_deg);
    s_put (out, &at, c->stabilized ? 1.0 : 0.0);
    s_put (out, &at, (double)c->stare);
    s_put (out, &at, c->stare_point.e_m);
    s_put (out, &at, c->stare_point.n_m);
}

int uavsim_camera_load (uavsim_camera_t *c, const cgs_scenario_uav_t *su, const uint8_t *buf,
                        size_t len)
{
    if (len != UAVSIM_CAMERA_SAVED)
        return -EPROTO;
    size_t at = 0;
    double dep = s_get (buf, &at), hfov = s_get (buf, &at), stab = s_get (buf, &at);
    double stare = s_get (buf, &at), e = s_get (buf, &at), n = s_get (buf, &at);
    if (!(dep >= 0 && dep <= 90) || !(hfov > 0 && hfov < 180) || (stab != 0 && stab != 1) ||
        (stare != 0 && stare != 1 && stare != 2) || !isfinite (e) || !isfinite (n))
        return -EPROTO;
    uavsim_camera_t x;
    uavsim_camera_init (&x, su);
    x.depression_deg = dep;
    x.hfov_deg = hfov;
    x.vfov_deg = s_vfov (su, hfov);
    x.stabilized = stab == 1;
    x.stare = (uavsim_stare_t)stare;
    x.stare_point = (cgs_enu_t){e, n, c->stare_point.u_m};
    x.have_target = c->have_target, x.target = c->target, x.target_vel = c->target_vel;
    x.target_t_s = c->target_t_s;
    *c = x;
    return 0;
}
