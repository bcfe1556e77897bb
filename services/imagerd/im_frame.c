/* im_frame — a frame's camera, target and overlay (see im_frame.h). */
#include "im_frame.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>

int im_frame_camera (const im_params_t *p, const im_uav_t *u, double t, const cgs_enu_t *stare_at,
                     im_camera_t *ret)
{
    if (!u->valid)
        return -EINVAL;
    double dt = isfinite (t - u->time_s) ? t - u->time_s : 0.0;
    im_camera_in_t in = {
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
        .stabilized = p->stabilized,
    };
    im_camera_t cam;
    int rc = im_camera_make (&in, &cam);
    if (rc < 0)
        return rc;
    if (stare_at)
        im_camera_stare (&cam, *stare_at); // a target straight below keeps the fixed boresight
    *ret = cam;
    return 0;
}

void im_frame_target (const im_camera_t *cam, const cgs_terrain_t *terrain, const im_entity_t *ents,
                      size_t n, bool have_track, cgs_enu_t track_at, double gate_m,
                      im_target_t *ret)
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
        out.projected = im_camera_project (cam, c, &out.px_x, &out.px_y, &depth);
        if (out.projected)
            out.size_px = len / depth / cam->tan_h * cam->width_px / 2;
        if (im_camera_in_view (cam, c)) {
            out.occluded = terrain && !cgs_terrain_los (terrain, cam->eye, c);
            out.in_view = !out.occluded;
        }
    }
    *ret = out;
}

size_t im_frame_labels (const im_camera_t *cam, const cgs_terrain_t *terrain,
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
        if (!im_camera_in_view (cam, top) || !im_camera_project (cam, top, &x, &y, &depth) ||
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

void im_frame_overlay (double t_s, const im_uav_t *u, const im_camera_t *cam,
                       const im_footprint_t *fp, const cgs_geo_t *frame, char lines[4][96])
{
    int h = (int)floor (t_s / 3600), m = (int)floor (fmod (t_s, 3600) / 60);
    double s = fmod (t_s, 60);
    snprintf (lines[0], 96, "T+%02d:%02d:%04.1f  HDG %03.0f  DEP %.0f", h, m, s, cam->heading_deg,
              -cam->pitch_deg);
    snprintf (lines[1], 96, "ALT %.0f M AGL  %.0f M", u->altitude_agl_m, cam->eye.u_m);
    double dx = fp->center.e_m - cam->eye.e_m, dy = fp->center.n_m - cam->eye.n_m;
    double dz = fp->center.u_m - cam->eye.u_m;
    snprintf (lines[2], 96, "SLANT %.0f M%s", sqrt (dx * dx + dy * dy + dz * dz),
              fp->clipped ? "  NO GROUND" : "");
    cgs_geodetic_t g;
    char mgrs[48];
    if (frame && cgs_geo_enu_to_geodetic (frame, fp->center, &g) == 0 &&
        cgs_geo_to_mgrs (g, 5, mgrs, sizeof mgrs) == 0)
        snprintf (lines[3], 96, "CTR %s", mgrs);
    else
        snprintf (lines[3], 96, "CTR E %.0f N %.0f", fp->center.e_m, fp->center.n_m);
}
