/* st_view — the picture's JSON view (see st_state.h): the "state" message
 * pushed to every page, built with json-c from what st_state.c keeps, and
 * the footprint as drawn. Pure. */
#include "st_state.h"
#include "st_state_impl.h"

#include "cgs_entities.h"
#include "cgs_json.h"
#include "cgs_msg.h"

#include <json-c/json.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- footprint -------------------------------------------------------------------- */

void st_footprint_scaled (const double corners_en[8], const double center_en[2], unsigned scale,
                          double ret_en[8])
{
    double k = (scale == 5 || scale == 10) ? (double)scale : 1.0;
    for (int i = 0; i < 4; i++) {
        ret_en[2 * i] = center_en[0] + k * (corners_en[2 * i] - center_en[0]);
        ret_en[2 * i + 1] = center_en[1] + k * (corners_en[2 * i + 1] - center_en[1]);
    }
}

/* ---- JSON ------------------------------------------------------------------------- */

static const char *s_status_name (int s)
{
    switch (s) {
    case CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED:
        return "confirmed";
    case CGS__TRACK_STATUS__TRACK_STATUS_COASTING:
        return "coasting";
    default:
        return "tentative";
    }
}

static const char *s_mode_name (int m)
{
    switch (m) {
    case CGS__UAV_MODE__UAV_MODE_ROUTE:
        return "route";
    case CGS__UAV_MODE__UAV_MODE_TRANSIT:
        return "transit";
    default:
        return "loiter";
    }
}

static const char *s_image_mode_name (int m)
{
    switch (m) {
    case CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE:
        return "visible";
    case CGS__IMAGE_MODE__IMAGE_MODE_INFRARED:
        return "infrared";
    case CGS__IMAGE_MODE__IMAGE_MODE_SAR:
        return "sar";
    default:
        return "unknown";
    }
}

static const char *s_stare_name (int s)
{
    switch (s) {
    case CGS__STARE_MODE__STARE_MODE_POINT:
        return "point";
    case CGS__STARE_MODE__STARE_MODE_TARGET:
        return "target";
    default:
        return "off";
    }
}

static const char *s_intercept_state_name (int s)
{
    return cgs_msg_enum_short (&cgs__intercept_state__descriptor, s, "IDLE");
}

static const char *s_force_name (cgs_force_t f)
{
    switch (f) {
    case CGS_FORCE_FRIENDLY:
        return "friendly";
    case CGS_FORCE_HOSTILE:
        return "opposing";
    case CGS_FORCE_NEUTRAL:
        return "neutral";
    default:
        return "other";
    }
}

static const char *s_kind_name (cgs_kind_t k)
{
    switch (k) {
    case CGS_KIND_TRACKED:
        return "tracked";
    case CGS_KIND_WHEELED:
        return "wheeled";
    case CGS_KIND_AIR:
        return "air";
    case CGS_KIND_PERSON:
        return "person";
    default:
        return "other";
    }
}

static json_object *s_m (double v) // metres, to the decimetre
{
    return cgs_json_fixed (v, 1);
}

static json_object *s_xy (st_xy_t p)
{
    json_object *a = json_object_new_array_ext (2);
    json_object_array_add (a, s_m (p.e));
    json_object_array_add (a, s_m (p.n));
    return a;
}

/* How the UAV's camera is set (uav.sensor), or NULL (null) when not told. */
static json_object *s_json_camera (const st_uav_t *u)
{
    if (!u->has_camera)
        return NULL;
    const st_camera_t *c = &u->camera;
    json_object *o = json_object_new_object ();
    cgs_json_add (o, "depression_deg", cgs_json_fixed (c->depression_deg, 2));
    cgs_json_add (o, "hfov_deg", cgs_json_fixed (c->hfov_deg, 2));
    cgs_json_add (o, "vfov_deg", cgs_json_fixed (c->vfov_deg, 2));
    cgs_json_add (o, "stabilized", json_object_new_boolean (c->stabilized));
    cgs_json_add (o, "stare", json_object_new_string (s_stare_name (c->stare)));
    cgs_json_add (o, "stare_point", c->has_point ? s_xy (c->point) : NULL);
    cgs_json_add (o, "staring", json_object_new_boolean (c->staring));
    cgs_json_add (o, "at_gimbal_limit", json_object_new_boolean (c->at_limit));
    json_object *g = json_object_new_object ();
    cgs_json_add (g, "azimuth_limit_deg", cgs_json_fixed (c->az_limit_deg, 1));
    cgs_json_add (g, "elevation_min_deg", cgs_json_fixed (c->el_min_deg, 1));
    cgs_json_add (g, "elevation_max_deg", cgs_json_fixed (c->el_max_deg, 1));
    cgs_json_add (o, "gimbal", g);
    return o;
}

/* The live mode of the UAV's imaging sensor (its latest image's), or NULL. */
static json_object *s_json_sensor_mode (const st_state_t *self, uint32_t uav_id)
{
    for (int i = 0; i < ST_UAVS_MAX; i++)
        if (self->sensor_modes[i].valid && self->sensor_modes[i].uav_id == uav_id)
            return json_object_new_string (s_image_mode_name (self->sensor_modes[i].mode));
    return NULL;
}

static json_object *s_json_uavs (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        const st_uav_t *u = &self->uavs[i];
        if (!u->valid)
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (u->id));
        cgs_json_add (o, "name", json_object_new_string (u->name));
        cgs_json_add (o, "e", s_m (u->e));
        cgs_json_add (o, "n", s_m (u->n));
        cgs_json_add (o, "alt_agl_m", s_m (u->alt_agl_m));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (u->heading_deg, 1));
        cgs_json_add (o, "airspeed_mps", cgs_json_fixed (u->airspeed_mps, 1));
        cgs_json_add (o, "ground_speed_mps", cgs_json_fixed (u->ground_speed_mps, 1));
        cgs_json_add (o, "cmd_alt_agl_m", s_m (u->cmd_alt_agl_m));
        cgs_json_add (o, "cmd_airspeed_mps", cgs_json_fixed (u->cmd_airspeed_mps, 1));
        cgs_json_add (o, "mode", json_object_new_string (s_mode_name (u->mode)));
        json_object *l = json_object_new_object ();
        cgs_json_add (l, "e", s_m (u->loiter_e));
        cgs_json_add (l, "n", s_m (u->loiter_n));
        cgs_json_add (l, "radius_m", s_m (u->loiter_radius_m));
        cgs_json_add (o, "loiter", l);
        cgs_json_add (o, "camera", s_json_camera (u));
        cgs_json_add (o, "sensor_mode", s_json_sensor_mode (self, u->id));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_hits (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (size_t i = 0; i < self->radar_count; i++) {
        const st_radar_t *r = &self->radars[i];
        // As the paper's display: the current scan yellow, the ones before
        // it grey. The current scan is the newest that has ended (its end
        // marker came, or a later scan began: the marker was lost); a scan
        // still in progress is drawn when it ends, so that each vehicle has
        // one yellow hit.
        size_t shown = r->count;
        if (shown > 0 && !r->scans[shown - 1].complete)
            shown--;
        for (size_t j = 0; j < shown; j++) {
            const st_scan_t *s = &r->scans[j];
            json_object *o = json_object_new_object ();
            cgs_json_add (o, "uav_id", json_object_new_int64 (r->uav_id));
            cgs_json_add (o, "scan", json_object_new_int64 (s->number));
            cgs_json_add (o, "current", json_object_new_boolean (j + 1 == shown));
            json_object *xy = json_object_new_array_ext ((int)(2 * s->count));
            for (size_t k = 0; k < s->count; k++) {
                json_object_array_add (xy, s_m (s->hits[k].e));
                json_object_array_add (xy, s_m (s->hits[k].n));
            }
            cgs_json_add (o, "xy", xy);
            json_object *ids = json_object_new_array_ext ((int)s->count);
            for (size_t k = 0; k < s->count; k++)
                json_object_array_add (ids, json_object_new_int64 (s->hits[k].id));
            cgs_json_add (o, "ids", ids);
            json_object_array_add (a, o);
        }
    }
    return a;
}

static json_object *s_json_bcis (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (size_t i = 0; i < self->bcis_count; i++) {
        const st_bcis_t *b = &self->bcis[i];
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "uav_id", json_object_new_int64 (b->uav_id));
        cgs_json_add (o, "id", json_object_new_int64 (b->id));
        cgs_json_add (o, "marking", json_object_new_string (b->marking));
        cgs_json_add (o, "e", s_m (b->e));
        cgs_json_add (o, "n", s_m (b->n));
        cgs_json_add (o, "age_s", cgs_json_fixed (fmax (0, self->now_s - b->time_s), 2));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_tracks (const st_state_t *self)
{
    json_object *a = json_object_new_array_ext ((int)self->track_count);
    for (size_t i = 0; i < self->track_count; i++) {
        const st_track_t *t = &self->tracks[i];
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (t->id));
        cgs_json_add (o, "uav_id", json_object_new_int64 (t->uav_id));
        cgs_json_add (o, "status", json_object_new_string (s_status_name (t->status)));
        cgs_json_add (o, "identity",
                      json_object_new_string (
                          t->identity == CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY ? "friendly"
                                                                                      : "unknown"));
        cgs_json_add (o, "e", s_m (t->e));
        cgs_json_add (o, "n", s_m (t->n));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (t->heading_deg, 1));
        cgs_json_add (o, "speed_mps", cgs_json_fixed (t->speed_mps, 1));
        cgs_json_add (o, "hits", json_object_new_int64 (t->hits));
        cgs_json_add (o, "last_hit", t->has_last_hit ? s_xy (t->last_hit) : NULL);
        cgs_json_add (o, "last_hit_id",
                      t->has_last_hit ? json_object_new_int64 (t->last_hit_id) : NULL);
        cgs_json_add (o, "friendly_id", json_object_new_int64 (t->friendly_id));
        json_object_array_add (a, o);
    }
    return a;
}

static const st_uav_t *s_uav_find (const st_state_t *self, uint32_t id)
{
    for (int i = 0; i < ST_UAVS_MAX; i++)
        if (self->uavs[i].valid && self->uavs[i].id == id)
            return &self->uavs[i];
    return NULL;
}

static json_object *s_corners (const double en[8])
{
    json_object *a = json_object_new_array_ext (8);
    for (int i = 0; i < 8; i++)
        json_object_array_add (a, s_m (en[i]));
    return a;
}

static json_object *s_json_intercepts (st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        const st_intercept_t *x = &self->intercepts[i];
        if (!x->valid)
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "uav_id", json_object_new_int64 (x->uav_id));
        cgs_json_add (o, "track_id", json_object_new_int64 (x->track_id));
        cgs_json_add (o, "state", json_object_new_string (s_intercept_state_name (x->state)));
        cgs_json_add (
            o, "method",
            json_object_new_string (x->method == CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS
                                        ? "mti-hits"
                                        : "head-on"));
        json_object *route = json_object_new_array_ext ((int)(2 * x->route_count));
        for (size_t k = 0; k < x->route_count; k++) {
            json_object_array_add (route, s_m (x->route[k].e));
            json_object_array_add (route, s_m (x->route[k].n));
        }
        cgs_json_add (o, "route", route);
        if (x->has_footprint) {
            double shown[8];
            st_footprint_scaled (x->footprint, x->center, x->scale, shown);
            cgs_json_add (o, "footprint", s_corners (x->footprint));
            cgs_json_add (o, "footprint_display", s_corners (shown));
        } else {
            cgs_json_add (o, "footprint", NULL);
            cgs_json_add (o, "footprint_display", NULL);
        }
        cgs_json_add (o, "scale",
                      json_object_new_int64 (x->scale == 5 || x->scale == 10 ? x->scale : 1));
        cgs_json_add (o, "waypoint", x->has_waypoint ? s_xy (x->waypoint) : NULL);
        cgs_json_add (o, "secondary", x->has_secondary ? s_xy (x->secondary) : NULL);
        cgs_json_add (o, "time_to_go_s", cgs_json_fixed (x->time_to_go_s, 1));
        cgs_json_add (o, "t_pred_s", cgs_json_fixed (x->t_pred_s, 1));
        cgs_json_add (o, "replans", json_object_new_int64 (x->replans));
        cgs_json_add (o, "reason", json_object_new_string (x->reason));
        cgs_json_add (o, "target_in_footprint", json_object_new_boolean (x->target_in_footprint));
        // Ground range from the UAV to the designated track, when both are known.
        const st_uav_t *u = s_uav_find (self, x->uav_id);
        const st_track_t *t = x->track_id ? st_state__track_find (self, x->track_id) : NULL;
        cgs_json_add (o, "range_m", u && t ? s_m (hypot (t->e - u->e, t->n - u->n)) : NULL);
        cgs_json_add (o, "designation", json_object_new_int64 ((int64_t)x->designation));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_truth (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    size_t cursor = 0;
    const cgs_entity_state_t *s;
    while ((s = cgs_entities_next (self->truth, &cursor))) {
        if (!s->active || s_uav_find (self, s->id))
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (s->id));
        cgs_json_add (o, "marking", json_object_new_string (s->marking));
        cgs_json_add (o, "force", json_object_new_string (s_force_name (s->force)));
        cgs_json_add (o, "kind", json_object_new_string (s_kind_name (s->kind)));
        cgs_json_add (o, "e", s_m (s->position.e_m));
        cgs_json_add (o, "n", s_m (s->position.n_m));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (s->heading_deg, 1));
        cgs_json_add (o, "speed_mps", cgs_json_fixed (hypot (s->velocity.e_m, s->velocity.n_m), 1));
        cgs_json_add (o, "external", json_object_new_boolean (s->external));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_image (const st_state_t *self)
{
    if (!self->has_image || !self->image_shown)
        return NULL;
    json_object *o = json_object_new_object ();
    char url[96];
    snprintf (url, sizeof url, "/image/latest.png?frame=%llu",
              (unsigned long long)self->image_shown_frame);
    cgs_json_add (o, "uav_id", json_object_new_int64 (self->image_uav));
    cgs_json_add (o, "frame", json_object_new_int64 ((int64_t)self->image_shown_frame));
    cgs_json_add (o, "url", json_object_new_string (url));
    cgs_json_add (o, "mode", json_object_new_string (s_image_mode_name (self->image_mode)));
    cgs_json_add (o, "target_in_view", json_object_new_boolean (self->image_target_in_view));
    // The camera's newest footprint (the KLV of the video gives the same one).
    cgs_json_add (o, "footprint", self->has_image_fp ? s_corners (self->image_fp) : NULL);
    cgs_json_add (o, "footprint_frame",
                  self->has_image_fp ? json_object_new_int64 ((int64_t)self->image_fp_frame)
                                     : NULL);
    return o;
}

static json_object *s_json_video (const st_state_t *self)
{
    if (!self->has_video)
        return NULL;
    json_object *o = json_object_new_object ();
    cgs_json_add (o, "uav_id", json_object_new_int64 (self->video_uav));
    cgs_json_add (o, "url", json_object_new_string ("/video"));
    cgs_json_add (o, "frames", json_object_new_int64 ((int64_t)self->video_frames));
    cgs_json_add (o, "frame_period_s",
                  self->video_period_s > 0 ? cgs_json_fixed (self->video_period_s, 4) : NULL);
    return o;
}

char *st_state_json (st_state_t *self, uint64_t seq, size_t *ret_len)
{
    json_object *o = json_object_new_object ();
    if (!o)
        return NULL;
    cgs_json_add (o, "type", json_object_new_string ("state"));
    cgs_json_add (o, "seq", json_object_new_int64 ((int64_t)seq));
    cgs_json_add (o, "sim_time_s", cgs_json_fixed (self->now_s, 2));
    cgs_json_add (o, "uavs", s_json_uavs (self));
    cgs_json_add (o, "hits", s_json_hits (self));
    cgs_json_add (o, "bcis", s_json_bcis (self));
    cgs_json_add (o, "tracks", s_json_tracks (self));
    cgs_json_add (o, "intercepts", s_json_intercepts (self));
    cgs_json_add (o, "truth", s_json_truth (self));
    cgs_json_add (o, "image", s_json_image (self));
    cgs_json_add (o, "video", s_json_video (self));
    cgs_json_add (o, "time_scale",
                  self->time_scale > 0 ? cgs_json_fixed (self->time_scale, 3) : NULL);
    cgs_json_add (o, "paused", json_object_new_boolean (self->paused));
    cgs_json_add (o, "replay", self->replay ? json_object_get (self->replay) : NULL);
    size_t len = 0;
    const char *text = json_object_to_json_string_length (o, JSON_C_TO_STRING_PLAIN, &len);
    char *out = text ? malloc (len + 1) : NULL;
    if (out) {
        memcpy (out, text, len + 1);
        if (ret_len)
            *ret_len = len;
    }
    json_object_put (o);
    return out;
}
