/* im_frame — a frame's camera, target and overlay (see im_frame.h). */
#include "im_frame.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>

int im_frame_camera (const im_params_t *p, const im_uav_t *u, double t, cgs_camera_t *ret)
{
    if (!u->valid)
        return -EINVAL;
    double dt = isfinite (t - u->time_s) ? t - u->time_s : 0.0;
    cgs_camera_in_t in = {
        .position = {u->position.e_m + u->velocity.e_m * dt, u->position.n_m + u->velocity.n_m * dt,
                     u->position.u_m + u->velocity.u_m * dt},
        .heading_deg = u->heading_deg,
        .pitch_deg = u->pitch_deg,
        .roll_deg = u->roll_deg,
        .depression_deg = u->depression_deg,
        .hfov_deg = u->hfov_deg,
        .vfov_deg = u->vfov_deg,
        .width_px = p->width_px,
        .height_px = p->height_px,
        .near_m = p->near_m,
        .far_m = p->max_range_m,
        .point = u->point,
    };
    return cgs_camera_make (&in, ret);
}

void im_frame_target (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                      const im_entity_t *ents, size_t n, bool have_track, cgs_enu_t track_at,
                      double gate_m, im_target_t *ret)
{
    im_target_t out = {0};
    const im_entity_t *best = NULL;
    double best_d = gate_m;
    for (size_t i = 0; have_track && i < n; i++) {
        if (ents[i].kind == CGS_KIND_AIR)
            continue;
        double d = hypot (ents[i].position.e_m - track_at.e_m, ents[i].position.n_m - track_at.n_m);
        if (d <= best_d)
            best = &ents[i], best_d = d;
    }
    if (best) {
        double len, wid, hgt;
        im_model_extent (best->kind, &len, &wid, &hgt);
        cgs_enu_t c = {best->position.e_m, best->position.n_m, best->position.u_m + hgt / 2};
        out.known = true;
        out.entity_id = best->id;
        out.slant_m = sqrt ((c.e_m - cam->eye.e_m) * (c.e_m - cam->eye.e_m) +
                            (c.n_m - cam->eye.n_m) * (c.n_m - cam->eye.n_m) +
                            (c.u_m - cam->eye.u_m) * (c.u_m - cam->eye.u_m));
        double depth;
        out.projected = cgs_camera_project (cam, c, &out.px_x, &out.px_y, &depth);
        if (out.projected)
            out.size_px = len / depth / cam->tan_h * cam->width_px / 2;
        if (cgs_camera_in_view (cam, c)) {
            out.occluded = terrain && !cgs_terrain_los (terrain, cam->eye, c);
            out.in_view = !out.occluded;
        }
    }
    *ret = out;
}

size_t im_frame_labels (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                        const im_entity_t *ents, size_t n, im_label_t *ret, size_t cap)
{
    size_t lim = cap < IM_LABELS_MAX ? cap : IM_LABELS_MAX, k = 0;
    double dist[IM_LABELS_MAX];
    for (size_t i = 0; i < n; i++) {
        const im_entity_t *e = &ents[i];
        if (e->kind == CGS_KIND_AIR)
            continue;
        double len, wid, hgt;
        im_model_extent (e->kind, &len, &wid, &hgt);
        cgs_enu_t top = {e->position.e_m, e->position.n_m, e->position.u_m + hgt};
        double x, y, depth;
        if (!cgs_camera_in_view (cam, top) || !cgs_camera_project (cam, top, &x, &y, &depth) ||
            (terrain && !cgs_terrain_los (terrain, cam->eye, top)))
            continue;
        if (k == lim && (lim == 0 || depth >= dist[k - 1]))
            continue;                      // full, and farther than the farthest kept
        size_t at = k < lim ? k++ : k - 1; // full: it takes the farthest's place
        for (; at > 0 && dist[at - 1] > depth; at--) {
            ret[at] = ret[at - 1];
            dist[at] = dist[at - 1];
        }
        ret[at] = (im_label_t){e, x, y};
        dist[at] = depth;
    }
    return k;
}

void im_frame_status_lines (const im_entity_t *e, char lines[3][24])
{
    static const char *const forces[] = {"UNKNOWN", "FRIENDLY", "HOSTILE", "NEUTRAL"};
    snprintf (lines[0], 24, "%s", e->marking && *e->marking ? e->marking : "?");
    snprintf (lines[1], 24, "%s",
              (unsigned)e->force < sizeof forces / sizeof *forces ? forces[e->force] : "?");
    snprintf (lines[2], 24, "%.0f KM/H", isfinite (e->speed_mps) ? e->speed_mps * 3.6 : 0.0);
}

void im_frame_overlay (double t_s, const im_uav_t *u, const cgs_camera_t *cam,
                       const cgs_footprint_t *fp, const cgs_geo_t *frame, char lines[4][96])
{
    int h = (int)floor (t_s / 3600), m = (int)floor (fmod (t_s, 3600) / 60);
    double s = fmod (t_s, 60);
    snprintf (lines[0], 96, "T+%02d:%02d:%04.1f  HDG %03.0f  DEP %.0f", h, m, s, cam->heading_deg,
              -cam->pitch_deg);
    snprintf (lines[1], 96, "ALT %.0f M AGL  %.0f M", u->altitude_agl_m, cam->eye.u_m);
    cgs_enu_t ctr = cgs_footprint_center_enu (fp);
    double dx = ctr.e_m - cam->eye.e_m, dy = ctr.n_m - cam->eye.n_m;
    double dz = ctr.u_m - cam->eye.u_m;
    snprintf (lines[2], 96, "SLANT %.0f M%s", sqrt (dx * dx + dy * dy + dz * dz),
              fp->clipped ? "  NO GROUND" : "");
    cgs_geodetic_t g;
    char mgrs[48];
    if (frame && cgs_geo_enu_to_geodetic (frame, ctr, &g) == 0 &&
        cgs_geo_to_mgrs (g, 5, mgrs, sizeof mgrs) == 0)
        snprintf (lines[3], 96, "CTR %s", mgrs);
    else
        snprintf (lines[3], 96, "CTR E %.0f N %.0f", ctr.e_m, ctr.n_m);
}

static double s_dot3 (cgs_enu_t a, cgs_enu_t b)
{
    return a.e_m * b.e_m + a.n_m * b.n_m + a.u_m * b.u_m;
}

int im_frame_klv (const cgs_camera_t *cam, const cgs_footprint_t *fp, const im_uav_t *u,
                  const cgs_geo_t *frame, double unix_time_s, const char *mission_id,
                  bool has_target, cgs_enu_t target, uint32_t track_id, im_klv_frame_t *ret)
{
    im_klv_frame_reset (ret);
    cgs_geodetic_t g;
    if (!frame || cgs_geo_enu_to_geodetic (frame, cam->eye, &g) < 0)
        return -EINVAL;
    ret->unix_time_s = unix_time_s;
    snprintf (ret->mission_id, sizeof ret->mission_id, "%s", mission_id ? mission_id : "");
    ret->platform_heading_deg = u->heading_deg;
    ret->platform_pitch_deg = u->pitch_deg;
    ret->platform_roll_deg = u->roll_deg;
    ret->sensor_lat_deg = g.lat_deg;
    ret->sensor_lon_deg = g.lon_deg;
    ret->sensor_true_alt_m = ret->sensor_hae_m = g.height_m;
    ret->hfov_deg = u->hfov_deg;
    ret->vfov_deg = u->vfov_deg;
    // The platform's body axes: the camera's axes with no depression, not levelled.
    cgs_camera_in_t in = {.position = cam->eye,
                          .heading_deg = u->heading_deg,
                          .pitch_deg = u->pitch_deg,
                          .roll_deg = u->roll_deg,
                          .hfov_deg = u->hfov_deg,
                          .vfov_deg = u->vfov_deg,
                          .width_px = 1,
                          .height_px = 1,
                          .near_m = 1,
                          .far_m = 2};
    cgs_camera_t body;
    if (cgs_camera_make (&in, &body) == 0) {
        const double deg = 180.0 / M_PI;
        double x = s_dot3 (cam->forward, body.forward), y = s_dot3 (cam->forward, body.right);
        double z = s_dot3 (cam->forward, body.up);
        double az = atan2 (y, x);
        ret->sensor_rel_az_deg = fmod (az * deg + 360.0, 360.0);
        ret->sensor_rel_el_deg = atan2 (z, hypot (x, y)) * deg;
        // The gimbal's right and up after azimuth and elevation, in the local frame.
        cgs_enu_t rg = {-sin (az) * body.forward.e_m + cos (az) * body.right.e_m,
                        -sin (az) * body.forward.n_m + cos (az) * body.right.n_m,
                        -sin (az) * body.forward.u_m + cos (az) * body.right.u_m};
        cgs_enu_t ug = {rg.n_m * cam->forward.u_m - rg.u_m * cam->forward.n_m,
                        rg.u_m * cam->forward.e_m - rg.e_m * cam->forward.u_m,
                        rg.e_m * cam->forward.n_m - rg.n_m * cam->forward.e_m};
        double roll = atan2 (-s_dot3 (cam->right, ug), s_dot3 (cam->right, rg)) * deg;
        ret->sensor_rel_roll_deg = fmod (roll + 360.0, 360.0);
    }
    if (fp->clipped) // a ray met no ground: no frame centre, corners or slant range on it
        goto target;
    cgs_enu_t ctr = cgs_footprint_center_enu (fp);
    cgs_enu_t d = {ctr.e_m - cam->eye.e_m, ctr.n_m - cam->eye.n_m, ctr.u_m - cam->eye.u_m};
    ret->slant_range_m = sqrt (s_dot3 (d, d));
    if (cgs_geo_enu_to_geodetic (frame, ctr, &g) == 0) {
        ret->frame_center_lat_deg = g.lat_deg;
        ret->frame_center_lon_deg = g.lon_deg;
        ret->frame_center_elev_m = g.height_m;
    }
    static const int order[4] = {1, 2, 3, 0}; // far-left, far-right, near-right, near-left
    for (int i = 0; i < 4; i++)
        if (cgs_geo_enu_to_geodetic (frame, cgs_footprint_corner_enu (fp, order[i]), &g) == 0) {
            ret->corner_lat_deg[i] = g.lat_deg;
            ret->corner_lon_deg[i] = g.lon_deg;
        }
target:
    if (has_target) {
        ret->has_target = true;
        ret->track_id = track_id;
        if (cgs_geo_enu_to_geodetic (frame, target, &g) == 0) {
            ret->target_lat_deg = g.lat_deg;
            ret->target_lon_deg = g.lon_deg;
        }
    }
    return 0;
}
