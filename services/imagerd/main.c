/* imagerd — the imaging sensor of one UAV: follows the UAV (`uav`), the
 * entities (`entity`), the intercept (`intercept`) and the designated track
 * (`track`), renders what the sensor sees at a configured rate of
 * simulation time, and publishes each frame's camera, footprint and where
 * the designated target is on `image`. PNG files go to the output folder at
 * a configured rate, on request (the `snapshot` command), and as latest.png
 * for the map display, written by a thread off the rendering path. The
 * camera, scene, renderer and post-processing are in im_*.c; the OpenGL
 * context in ctx/ (one backend per build); this file wires them to the bus. */
#include "cgs_ckpt.h"
#include "cgs_entities.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_sensor.h"
#include "cgs_service.h"
#include "cgs_camera.h"
#include "im_ctx.h"
#include "im_frame.h"
#include "im_params.h"
#include "im_png.h"
#include "im_post.h"
#include "im_render.h"
#include "im_geotiff.h"
#include "im_sar.h"
#include "im_sar_aim.h"
#include "im_scene.h"
#include "im_video.h"
#include "im_vout.h"

#include <arpa/inet.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_STALE_S 10.0 // an entity not heard of for this long (simulation time) is forgotten
#define S_MAX_FPS                                                                                  \
    30.0 // frames due faster than this on average (wall clock) are skipped and counted
#define S_GATE_M     150.0 // the designated track's vehicle is the ground entity this near it
#define S_PNG_QUEUE  8     // frames waiting for the PNG writer before one is dropped
#define S_MOVING_MPS 0.5   // a vehicle this fast has its engine running

typedef struct {
    cgs_service_t *svc;
    cgs_sensor_t sensor; // its UAV, scenario and terrain
    im_params_t params;
    im_mode_t mode; // the sensor's mode now: the parameters' at first, then as commanded
    char out_dir[4096];
    char latest_path[4096 + 16]; // out_dir/latest.png, absolute
    im_ctx_t *ctx;
    im_renderer_t *ren;
    im_post_t post;
    im_png_writer_t *png;
    cgs_entities_t *ents;
    im_entity_t *draw;
    size_t draw_cap;
    im_uav_t uav;
    /* The intercept and its designated track. */
    uint32_t track_id;
    bool have_track;
    cgs_enu_t track_pos, track_vel;
    double track_t;
    double track_cov[16]; // its covariance (east, north, ve, vn), row-major
    bool have_cov;
    int sar_how; // chips as configured (1), widened by the SAR's measurement (2) or the track (3)
    im_sar_gmti_t sar_gmti; // the SAR's measurement of the designated target
    uint64_t sar_rng;       // its noise
    uint64_t sar_gmti_hits, sar_gmti_misses;
    uint8_t *rgba;
    bool started;
    double next_frame_s, next_png_s, next_latest_s, next_frame_wall;
    uint32_t snapshots; // frames still to write on request
    uint64_t frames, skipped, pngs, render_errors;
    double latency_sum_s, latency_max_s, entity_wall; // entity batch in → its frame out
    char detail[256];
    /* The video: H.264 and KLV in MPEG-TS, to the file, UDP and the bus. */
    im_video_t *video;
    im_vout_t *vout;
    char video_path[4096 + 64];
    double unix_at_zero; // UTC (Unix seconds) of simulation time 0: the KLV time stamps
    bool have_unix;
    uint64_t video_errors;
    im_klv_frame_t klv;
    /* SAR mode: the imager, made when first needed, and its latest chip. */
    im_sar_t *sar;
    bool sar_have;               // a chip was made
    bool sar_fresh;              // the frame being made shows a new chip
    double sar_t;                // simulation time of the latest chip
    double sar_wall, sar_cost_s; // wall clock when it was started, and what it took
    double next_tif_s;           // latest-sar.tif written again from this time
    uint64_t sar_errors, sar_chips;
    char sar_error[200];
    char sar_short[96]; // the reason on a frame without a chip
    bool sar_blank;     // this frame has no chip
} s_app_t;

static void s_bad (s_app_t *app, const char *what)
{
    cgs_service_bad_input (app->svc, what);
}

static void s_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    cgs_service_take_entities (app->svc, app->ents, msg, hdr);
    if (app->entity_wall == 0)
        app->entity_wall = cgs_loop_now ();
}

static void s_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    (void)topic, (void)hdr;
    s_app_t *app = arg;
    const Cgs__Intercept *m = (const Cgs__Intercept *)msg;
    if (!app->sensor.uav_id || m->uav_id != app->sensor.uav_id)
        return;
    bool active = m->track_id != 0 && m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE &&
                  m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED;
    uint32_t id = active ? m->track_id : 0;
    if (id != app->track_id) {
        if (id)
            cgs_log (LOG_INFO, "designated track %u: looking for its vehicle", id);
        app->track_id = id;
        app->have_track = false;
        app->sar_gmti.have = false;
    }
}

static void s_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__TrackBatch *b = (const Cgs__TrackBatch *)msg;
    for (size_t i = 0; app->track_id && i < b->n_tracks; i++) {
        const Cgs__Track *t = b->tracks[i];
        if (!t || t->track_id != app->track_id)
            continue;
        if (!t->position || !t->velocity || !isfinite (t->position->east_m) ||
            !isfinite (t->position->north_m) || !isfinite (t->velocity->east_mps) ||
            !isfinite (t->velocity->north_mps)) {
            s_bad (app, "a track without a valid position or velocity");
            return;
        }
        app->have_track = t->status != CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
        app->track_pos = (cgs_enu_t){t->position->east_m, t->position->north_m, 0};
        app->track_vel = (cgs_enu_t){t->velocity->east_mps, t->velocity->north_mps, 0};
        app->track_t = hdr->sim_time_s;
        app->have_cov = t->n_covariance == 16;
        for (size_t k = 0; app->have_cov && k < 16; k++)
            app->have_cov = isfinite (t->covariance[k]);
        if (app->have_cov)
            memcpy (app->track_cov, t->covariance, sizeof app->track_cov);
    }
}

/* The entities to draw at time t: moved on along their velocity, ground
 * ones on the ground; not the sensor's own UAV. */
static size_t s_entities_at (s_app_t *app, double t)
{
    size_t count = cgs_entities_count (app->ents);
    if (app->draw_cap < count) {
        im_entity_t *d = realloc (app->draw, count * sizeof *d);
        if (!d) {
            cgs_health_set_error (cgs_service_health (app->svc),
                                  "out of memory for entities: a frame drew none");
            return 0;
        }
        app->draw = d;
        app->draw_cap = count;
    }
    size_t n = 0, cursor = 0;
    const cgs_entity_state_t *s;
    while ((s = cgs_entities_next (app->ents, &cursor))) {
        cgs_enu_t p;
        if (s->id == app->sensor.uav_id ||
            !cgs_entity_at (s, t, S_STALE_S, app->sensor.terrain, &p))
            continue;
        app->draw[n++] = (im_entity_t){
            .id = s->id,
            .kind = s->kind,
            .position = p,
            .heading_deg = s->heading_deg,
            .running = hypot (s->velocity.e_m, s->velocity.n_m) > S_MOVING_MPS,
            .marking = s->marking,
            .force = s->force,
            .speed_mps = hypot (s->velocity.e_m, s->velocity.n_m),
        };
    }
    return n;
}

static void s_enu (Cgs__Enu *m, cgs_enu_t p)
{
    cgs__enu__init (m);
    m->east_m = p.e_m;
    m->north_m = p.n_m;
    m->up_m = p.u_m;
}

static void s_queue_png (s_app_t *app, const char *name)
{
    int rc = im_png_writer_submit (app->png, app->rgba, app->params.width_px, app->params.height_px,
                                   name);
    if (rc == -EAGAIN)
        cgs_health_set_error (cgs_service_health (app->svc),
                              "PNG writer behind: a frame's file was dropped");
    else if (rc < 0)
        cgs_health_set_error (cgs_service_health (app->svc), "out of memory for a PNG file");
}

/* The frame as video: its KLV from the same camera and footprint as the
 * `image` message, H.264 and KLV muxed to the outputs, and its bytes on
 * `video` for the map. */
static void s_encode (s_app_t *app, double t, const cgs_camera_t *cam, const cgs_footprint_t *fp,
                      cgs_enu_t track_at)
{
    const char *mission = app->params.video_mission_id[0]
                              ? app->params.video_mission_id
                              : cgs_exercise_name (cgs_service_exercise (app->svc));
    uint8_t klv[IM_KLV_MAX_PACKET];
    size_t klv_len = 0;
    if (im_frame_klv (cam, fp, &app->uav, app->sensor.frame, app->unix_at_zero + t, mission,
                      app->have_track, track_at, app->track_id, &app->klv) == 0)
        klv_len = im_klv_encode (&app->klv, klv, sizeof klv);
    char err[256];
    bool key = false;
    im_vout_frame_reset (app->vout);
    if (im_video_frame (app->video, app->rgba, t, klv, klv_len, &key, err, sizeof err) < 0) {
        if (app->video_errors++ == 0)
            cgs_log (LOG_ERR, "video: %s", err);
        cgs_health_set_error (cgs_service_health (app->svc), err);
        return;
    }
    size_t len;
    const uint8_t *ts = im_vout_frame (app->vout, &len);
    if (!app->params.video_map || !ts || !len)
        return;
    Cgs__VideoFrame m = CGS__VIDEO_FRAME__INIT;
    m.uav_id = app->sensor.uav_id;
    m.frame_number = app->frames;
    m.keyframe = key;
    m.ts.data = (uint8_t *)ts;
    m.ts.len = len;
    cgs_service_set_sim_time (app->svc, t);
    cgs_service_publish (app->svc, "video", &m.base);
}

/* SAR mode: a new spotlight chip once the last one's aperture has been
 * flown (a SAR image takes that long to collect; at least every 0.2 s of
 * simulation time), else the last chip again; into app->rgba, letterboxed,
 * with its ground area as the frame's footprint. The chip is centred on the
 * designated target's estimate, else where the camera's boresight meets the
 * ground. A moving target's return falls R·v_r/V along cross range from it
 * (SAR's moving-target shift): the chip is centred where the last chip put
 * the target's return, so the target is in it, at its apparent place.
 * -1 when there is no chip to show. */
static int s_sar_frame (s_app_t *app, double t, const cgs_camera_t *cam, size_t n,
                        const cgs_enu_t *target, cgs_footprint_t *ret_fp)
{
    const im_params_t *p = &app->params;
    char err[256] = "";
    if (!app->sar && !(app->sar = im_sar_new (&p->sar, app->sensor.seed, err, sizeof err))) {
        cgs_health_set_error (cgs_service_health (app->svc), err);
        if (app->sar_errors++ == 0)
            cgs_log (LOG_ERR, "SAR: %s", err);
        return -1;
    }
    const im_sar_chip_t *last = im_sar_chip (app->sar);
    double every = fmax (0.2, app->sar_have && last ? last->aperture_s : 0.0);
    double now = cgs_loop_now ();
    app->sar_fresh = false;
    // At most half the wall clock goes to chips, so commands and the bus are
    // served between them at any time scale.
    if (!app->sar_have || t < app->sar_t ||
        (t - app->sar_t >= every && now - app->sar_wall >= 2 * app->sar_cost_s)) {
        cgs_footprint_t cfp;
        cgs_camera_footprint (cam, app->sensor.terrain, p->max_range_m, &cfp);
        cgs_enu_t center = cgs_footprint_center_enu (&cfp);
        im_sar_aim_t aim = {.widen = 1};
        int aimed = 0;
        if (target) {
            // Aimed where the designated target's return is expected, and
            // widened to hold it (im_sar_aim.h).
            im_sar_track_t trk = {.pos = app->track_pos,
                                  .vel = app->track_vel,
                                  .t_s = app->track_t,
                                  .has_cov = app->have_cov};
            memcpy (trk.cov, app->track_cov, sizeof trk.cov);
            aimed = im_sar_aim (app->sar, cam->eye, app->uav.velocity, app->sensor.terrain, &trk,
                                &app->sar_gmti, t, p->sar.max_widen, &aim);
            center = aim.center;
        }
        double widen = aim.widen;
        // Said when the chips become widened or not, or the aim changes
        // between the track and the SAR's own measurement (not every chip).
        int how = !target ? 0 : widen <= 1 ? 1 : aim.by_gmti ? 2 : 3;
        if (aimed == 0 && how != app->sar_how) {
            if (how >= 2)
                cgs_log (LOG_INFO,
                         "SAR: chips widened (now %g times: %.0f m, resolution %g times coarser) "
                         "to hold the designated target's return (%.0f m standard deviation, by "
                         "%s)",
                         widen, widen * p->sar.scene_m, widen, aim.sigma_m,
                         how == 2 ? "its radial velocity measured by the SAR"
                                  : "the track's radial velocity");
            else if (app->sar_how >= 2)
                cgs_log (LOG_INFO, "SAR: chips as configured again (%.0f m)", p->sar.scene_m);
            app->sar_how = how;
        }
        im_sar_geom_t g = {
            .radar = cam->eye, .radar_vel = app->uav.velocity, .center = center, .widen = widen};
        im_sar_scene_t sc = {.terrain = app->sensor.terrain, .ents = app->draw, .nents = n};
        int rc = im_sar_image (app->sar, &g, &sc, NULL);
        app->sar_wall = now;
        app->sar_cost_s = cgs_loop_now () - now;
        if (rc < 0) {
            snprintf (err, sizeof err,
                      rc == -EDOM ? "SAR: no image of (%.0f, %.0f): the grazing angle is outside "
                                    "1..85 degrees, the range under 100 m, or the look too near "
                                    "the flight path"
                                  : "SAR: no image of (%.0f, %.0f): %s",
                      g.center.e_m, g.center.n_m, strerror (-rc));
            cgs_health_set_error (cgs_service_health (app->svc), err);
            // Said once until the reason changes (or a chip is made).
            char why[32];
            snprintf (why, sizeof why, "%d", rc);
            if (strcmp (why, app->sar_error) != 0)
                cgs_log (LOG_WARNING, "%s", err);
            snprintf (app->sar_error, sizeof app->sar_error, "%s", why);
            app->sar_errors++;
            snprintf (app->sar_short, sizeof app->sar_short, "%s",
                      rc == -EDOM ? "SAR: NO IMAGE - GRAZING, RANGE OR LOOK TOO NEAR THE TRACK"
                                  : "SAR: NO IMAGE");
        } else {
            app->sar_have = app->sar_fresh = true;
            app->sar_t = t;
            app->sar_chips++;
            app->sar_error[0] = '\0';
        }
    }
    const im_sar_chip_t *c = im_sar_chip (app->sar);
    app->sar_blank = !app->sar_have;
    if (app->sar_blank) {
        // No chip yet (the geometry refuses one): a dark frame that says why,
        // so the sensor's mode shows and the reason is on the picture; the
        // camera's footprint stands for it.
        for (size_t i = 0; i < (size_t)p->width_px * (size_t)p->height_px; i++) {
            uint8_t *o = app->rgba + 4 * i;
            o[0] = o[1] = o[2] = 16, o[3] = 255;
        }
        const char *line = app->sar_short;
        im_post_overlay (app->rgba, p->width_px, p->height_px, &line, 1);
        cgs_camera_footprint (cam, app->sensor.terrain, p->max_range_m, ret_fp);
        return 0;
    }
    im_sar_to_rgba (app->sar, app->rgba, p->width_px, p->height_px);
    cgs_footprint_t fp = {0};
    for (int i = 0; i < 4; i++) {
        fp.corner[i] = (cgs_v2_t){c->corners[i].e_m, c->corners[i].n_m};
        fp.corner_up_m[i] = c->corners[i].u_m;
    }
    fp.center = (cgs_v2_t){c->center.e_m, c->center.n_m};
    fp.center_up_m = c->center.u_m;
    *ret_fp = fp;
    return 0;
}

/* The SAR chip as a GeoTIFF in the output folder, named as the PNG file
 * png_name with .tif for .png. */
static void s_geotiff (s_app_t *app, double t, const char *png_name)
{
    char path[sizeof app->out_dir + 80], err[256];
    snprintf (path, sizeof path, "%s/%.*s.tif", app->out_dir, (int)(strlen (png_name) - 4),
              png_name);
    if (im_geotiff_write (path, app->sar, app->sensor.frame, app->sensor.terrain,
                          app->have_unix ? app->unix_at_zero + t : t, err, sizeof err) < 0) {
        cgs_health_set_error (cgs_service_health (app->svc), err);
        if (app->sar_errors++ == 0)
            cgs_log (LOG_WARNING, "SAR GeoTIFF: %s", err);
    }
}

/* In SAR mode, where the target's vehicle falls in the frame: its range and
 * Doppler put it in the chip (a moving vehicle shifted along cross range). */
static void s_sar_target (s_app_t *app, double t, size_t n, im_target_t *tg)
{
    const im_sar_chip_t *c = app->sar_blank ? NULL : im_sar_chip (app->sar);
    const im_params_t *p = &app->params;
    tg->in_view = tg->projected = tg->occluded = false;
    // A new chip measures the designated target when its return is in it
    // (the moving-target channel), else the next is aimed by the track.
    bool measured = false;
    for (size_t i = 0; c && tg->known && i < n; i++) {
        const im_entity_t *e = &app->draw[i];
        if (e->id != tg->entity_id)
            continue;
        double h = e->heading_deg * M_PI / 180.0, len, wid, hgt;
        cgs_enu_t v = {e->speed_mps * sin (h), e->speed_mps * cos (h), 0};
        // Where it was when the chip shown was made.
        double back = app->sar_t - t;
        cgs_enu_t at = {e->position.e_m + v.e_m * back, e->position.n_m + v.n_m * back, 0};
        at.u_m = cgs_terrain_height_clamped (app->sensor.terrain, at.e_m, at.n_m);
        double x, y;
        if (app->sar_fresh && p->sar.gmti)
            measured = im_sar_gmti_measure (c, app->sensor.terrain, at, v, app->sar_t,
                                            p->sar.gmti_sigma_mps, &app->sar_rng, &app->sar_gmti);
        if (im_sar_ground_to_px (c, p->width_px, p->height_px, at, v, &x, &y)) {
            im_model_extent (e->kind, &len, &wid, &hgt);
            double side = fmin (p->width_px, p->height_px);
            tg->projected = tg->in_view = true;
            tg->px_x = x, tg->px_y = y;
            tg->size_px = len / (c->pixel_m * c->size_px / side);
        }
    }
    if (c && app->sar_fresh && p->sar.gmti && tg->known) {
        if (measured)
            app->sar_gmti_hits++;
        else
            app->sar_gmti_misses++, app->sar_gmti.have = false;
    }
}

static void s_render (s_app_t *app, double t)
{
    im_params_t pm = app->params; // with the mode as commanded
    pm.mode = app->mode;
    const im_params_t *p = &pm;
    cgs_enu_t track_at = {0};
    if (app->have_track) {
        double dt = t - app->track_t;
        track_at.e_m = app->track_pos.e_m + app->track_vel.e_m * dt;
        track_at.n_m = app->track_pos.n_m + app->track_vel.n_m * dt;
        track_at.u_m = cgs_terrain_height_clamped (app->sensor.terrain, track_at.e_m, track_at.n_m);
    }
    cgs_camera_t cam;
    if (im_frame_camera (p, &app->uav, t, &cam) < 0) {
        cgs_health_set_error (cgs_service_health (app->svc), "a frame's camera could not be made");
        return;
    }
    size_t n = s_entities_at (app, t);
    char err[256] = "";
    cgs_footprint_t fp;
    bool sar = p->mode == IM_MODE_SAR;
    if (sar) {
        if (s_sar_frame (app, t, &cam, n, app->have_track ? &track_at : NULL, &fp) < 0)
            return;
    } else {
        if (im_renderer_draw (app->ren, &cam, p, app->draw, n, app->rgba, err, sizeof err) < 0) {
            if (app->render_errors++ == 0)
                cgs_log (LOG_ERR, "%s", err);
            cgs_health_set_error (cgs_service_health (app->svc), err);
            return;
        }
        if (p->mode == IM_MODE_INFRARED)
            im_post_infrared (&app->post, app->rgba, p);
        cgs_camera_footprint (&cam, app->sensor.terrain, p->max_range_m, &fp);
    }
    if (p->status_blocks && !sar) {
        static im_label_t labels[IM_LABELS_MAX];
        size_t nl =
            im_frame_labels (&cam, app->sensor.terrain, app->draw, n, labels, IM_LABELS_MAX);
        int lead = p->width_px >= 960 ? 16 : 8;
        for (size_t i = nl; i-- > 0;) { // the nearest drawn last, on top
            char sl[3][24];
            im_frame_status_lines (labels[i].entity, sl);
            const char *lp[3] = {sl[0], sl[1], sl[2]};
            im_post_status_block (app->rgba, p->width_px, p->height_px,
                                  (int)lround (labels[i].px_x) + lead,
                                  (int)lround (labels[i].px_y) - lead, lead, lp, 3);
        }
    }
    if (p->overlay) {
        char lines[4][96];
        im_frame_overlay (t, &app->uav, &cam, &fp, app->sensor.frame, lines);
        const im_sar_chip_t *sc = sar && !app->sar_blank ? im_sar_chip (app->sar) : NULL;
        if (sc) // the chip's range, resolution and widening
            snprintf (lines[2], sizeof lines[2], "SLANT %.0f M  SAR RES %.1f M%s",
                      sc->slant_range_m, fmax (sc->range_res_m, sc->cross_res_m),
                      sc->widen > 1 ? "  WIDE" : "");
        const char *ptrs[4] = {lines[0], lines[1], lines[2], lines[3]};
        im_post_overlay (app->rgba, p->width_px, p->height_px, ptrs, 4);
    }
    im_target_t tg;
    im_frame_target (&cam, app->sensor.terrain, app->draw, n, app->have_track, track_at, S_GATE_M,
                     &tg);
    if (sar)
        s_sar_target (app, t, n, &tg);
    app->frames++;
    if (p->frame_code)
        im_post_frame_code (app->rgba, p->width_px, p->height_px, app->frames);
    if (app->video)
        s_encode (app, t, &cam, &fp, track_at);
    // Files: numbered at the PNG rate, on request, and latest.png for the map.
    char name[64] = "";
    if (app->snapshots > 0) {
        snprintf (name, sizeof name, "snapshot-%08llu.png", (unsigned long long)app->frames);
        app->snapshots--;
    } else if (p->png_rate_hz > 0 && t >= app->next_png_s) {
        snprintf (name, sizeof name, "frame-%08llu.png", (unsigned long long)app->frames);
        app->next_png_s = fmax (app->next_png_s + 1.0 / p->png_rate_hz, t);
    }
    if (*name) {
        s_queue_png (app, name);
        app->pngs++;
        if (sar && !app->sar_blank) // the chip, ground-projected, beside it
            s_geotiff (app, t, name);
    }
    bool latest = p->latest_rate_hz > 0 && t >= app->next_latest_s;
    if (sar && app->sar_fresh && p->latest_rate_hz > 0 &&
        (t >= app->next_tif_s || t < app->next_tif_s - 1.0 / p->latest_rate_hz)) {
        s_geotiff (app, t, "latest-sar.png"); // each new chip, at most at the latest.png rate
        app->next_tif_s = t + 1.0 / p->latest_rate_hz;
    }
    if (latest) {
        s_queue_png (app, "latest.png");

        app->next_latest_s = fmax (app->next_latest_s + 1.0 / p->latest_rate_hz, t);
    }
    // The message.
    Cgs__Image m = CGS__IMAGE__INIT;
    Cgs__CameraPose pose = CGS__CAMERA_POSE__INIT;
    Cgs__Footprint f = CGS__FOOTPRINT__INIT;
    Cgs__Enu eye, corners[4], center, *cptrs[4];
    s_enu (&eye, cam.eye);
    pose.position = &eye;
    pose.heading_deg = cam.heading_deg;
    pose.pitch_deg = cam.pitch_deg;
    pose.roll_deg = cam.roll_deg;
    pose.hfov_deg = app->uav.hfov_deg;
    pose.vfov_deg = app->uav.vfov_deg;
    for (int i = 0; i < 4; i++) {
        s_enu (&corners[i], cgs_footprint_corner_enu (&fp, i));
        cptrs[i] = &corners[i];
    }
    s_enu (&center, cgs_footprint_center_enu (&fp));
    f.n_corners = 4;
    f.corners = cptrs;
    f.center = &center;
    f.display_scale = 1;
    m.uav_id = app->sensor.uav_id;
    m.frame_number = app->frames;
    m.camera = &pose;
    m.footprint = &f;
    m.target_in_view = tg.in_view;
    m.target_px_x = tg.projected ? tg.px_x : 0;
    m.target_px_y = tg.projected ? tg.px_y : 0;
    m.target_size_px = tg.projected ? tg.size_px : 0;
    m.target_entity_id = tg.known ? tg.entity_id : 0;
    m.width_px = (uint32_t)p->width_px;
    m.height_px = (uint32_t)p->height_px;
    m.mode = (Cgs__ImageMode)p->mode; // the same values
    m.path = name;
    m.latest_path = latest ? app->latest_path : "";
    cgs_service_set_sim_time (app->svc, t);
    cgs_service_publish (app->svc, "image", &m.base);
    if (app->entity_wall > 0) { // from the first entity update since the last frame to this one
        double lat = cgs_loop_now () - app->entity_wall;
        app->latency_sum_s += lat;
        app->latency_max_s = fmax (app->latency_max_s, lat);
        app->entity_wall = 0;
    }
}

static void s_on_uav (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__Uav *u = (const Cgs__Uav *)msg;
    double t = hdr->sim_time_s;
    bool new_id = false;
    int rc = cgs_sensor_take_uav (&app->sensor, u, t, &new_id);
    if (rc > 0)
        return; // another UAV's
    if (rc < 0 || !isfinite (u->pitch_deg) || !isfinite (u->roll_deg)) {
        s_bad (app, "a uav message without a valid time, position, velocity or attitude");
        return;
    }
    if (new_id)
        cgs_log (LOG_INFO, "imaging sensor on %s (entity %u) at t=%.2f s", app->sensor.uav_name,
                 app->sensor.uav_id, t);
    const cgs_scenario_uav_t *su = app->sensor.uav;
    const Cgs__ImagingSensor *s = u->sensor;
    im_uav_t nu = {
        .valid = true,
        .id = u->entity_id,
        .position = app->sensor.position,
        .velocity = app->sensor.velocity,
        .heading_deg = u->heading_deg,
        .pitch_deg = u->pitch_deg,
        .roll_deg = u->roll_deg,
        .altitude_agl_m = u->altitude_agl_m,
        .depression_deg = s ? s->depression_deg : su->sensor_depression_deg,
        .hfov_deg = s && s->hfov_deg > 0 ? s->hfov_deg : su->sensor_hfov_deg,
        .vfov_deg = s && s->vfov_deg > 0 ? s->vfov_deg : su->sensor_vfov_deg,
        .time_s = t,
    };
    cgs_camera_in_t ci = {0};
    if (cgs_msg_uav_camera (u, &ci) == 0) {
        nu.point = ci.point;
    }
    cgs_camera_t cam; // refused here, at intake, when no camera can be made of it
    if (im_frame_camera (&app->params, &nu, t, &cam) < 0) {
        s_bad (app, "a uav message whose attitude or sensor (depression in (-90, 90), fields "
                    "of view in (0, 180)) cannot make a camera");
        return;
    }
    app->uav = nu;
    if (!app->have_unix && hdr->wall_time_s > 0) {
        // Simulation time mapped to UTC: the wall clock when this UAV was first heard,
        // less its simulation time, kept for the whole run.
        app->unix_at_zero = hdr->wall_time_s - t;
        app->have_unix = true;
    }
    double period = 1.0 / app->params.frame_rate_hz;
    if (!app->started || t < app->next_frame_s - 2 * period) { // first, or time went back
        if (app->started && app->video)
            im_video_continue (app->video); // the video's time runs on
        app->started = true;
        app->next_frame_s = app->next_png_s = app->next_latest_s = t;
    }
    if (t < app->next_frame_s - 0.01 * period) // a step's rounding does not skip a frame
        return;
    app->next_frame_s = fmax (app->next_frame_s + period, t);
    double now = cgs_loop_now ();
    // At most S_MAX_FPS frames a wall-clock second on average: a frame may come
    // half a period early (updates jitter about their rate), and no credit
    // builds up while none come.
    double wall_period = 1.0 / S_MAX_FPS;
    if (app->next_frame_wall > 0 && now < app->next_frame_wall - 0.5 * wall_period) {
        app->skipped++;
        return;
    }
    app->next_frame_wall = fmax (app->next_frame_wall, now - wall_period) + wall_period;
    s_render (app, t);
    cgs_entities_evict (app->ents, t, S_STALE_S);
}

static const char *s_mode_name (im_mode_t m)
{
    return m == IM_MODE_INFRARED ? "infrared" : m == IM_MODE_SAR ? "SAR" : "visible";
}

/* The sensor's mode: visible, infrared (FLIR) or SAR. */
static void s_on_mode (s_app_t *app, const Cgs__SetSensorMode *m, Cgs__Reply *reply)
{
    if (m->uav_id && m->uav_id != app->sensor.uav_id) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        snprintf (app->detail, sizeof app->detail, "this imagerd serves %s (entity %u), not %u",
                  app->sensor.uav_name, app->sensor.uav_id, m->uav_id);
        reply->error = app->detail;
        return;
    }
    if ((unsigned)m->mode > IM_MODE_SAR) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        snprintf (app->detail, sizeof app->detail,
                  "unknown sensor mode %d (visible 0, infrared 1, SAR 2)", (int)m->mode);
        reply->error = app->detail;
        return;
    }
    im_mode_t was = app->mode;
    app->mode = (im_mode_t)m->mode;
    snprintf (app->detail, sizeof app->detail, "%s: imaging sensor %s (was %s)",
              app->sensor.uav_name, s_mode_name (app->mode), s_mode_name (was));
    cgs_log (LOG_NOTICE, "%s", app->detail);
    reply->detail = app->detail;
}

/* Saved state: a cgs_ckpt frame "IMGR", version 1: the mode (u32) and the
 * parameters' mode then (u32). A parameter file whose mode has changed
 * since wins over the saved mode: it is the newer word. */
#define S_STATE_MAGIC   "IMGR"
#define S_STATE_VERSION 1u
#define S_STATE_WHAT    "imagerd state"

static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    s_app_t *app = arg;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_STATE_MAGIC, S_STATE_VERSION);
    cgs_ckpt_put_u32 (&w, (uint32_t)app->mode);
    cgs_ckpt_put_u32 (&w, (uint32_t)app->params.mode);
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

static int s_restore (s_app_t *app, const uint8_t *buf, size_t len, char *err, size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc =
        cgs_ckpt_open (&r, buf, len, S_STATE_MAGIC, S_STATE_VERSION, S_STATE_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    uint32_t mode = cgs_ckpt_get_u32 (&r), then = cgs_ckpt_get_u32 (&r);
    if ((rc = cgs_ckpt_end (&r, S_STATE_WHAT, err, errlen)) < 0)
        return rc;
    if (then != (uint32_t)app->params.mode) {
        snprintf (err, errlen, "the parameters' mode changed since (%s), so it is the mode",
                  s_mode_name (app->params.mode));
        return 1;
    }
    if (mode > IM_MODE_SAR) {
        snprintf (err, errlen, "an %s with an unknown mode %u", S_STATE_WHAT, mode);
        return -EPROTO;
    }
    app->mode = (im_mode_t)mode;
    return 0;
}

static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_app_t *app = arg;
    if (cmd->body_case == CGS__COMMAND__BODY_PING)
        return;
    if (cmd->body_case == CGS__COMMAND__BODY_SET_SENSOR_MODE) {
        s_on_mode (app, cmd->set_sensor_mode, reply);
        return;
    }
    if (cmd->body_case != CGS__COMMAND__BODY_SNAPSHOT) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        snprintf (app->detail, sizeof app->detail, "imagerd does not handle %s",
                  cgs_cmd_name (cmd));
        reply->error = app->detail;
        return;
    }
    const Cgs__Snapshot *s = cmd->snapshot;
    if (s->uav_id && s->uav_id != app->sensor.uav_id) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        snprintf (app->detail, sizeof app->detail, "this imagerd serves %s (entity %u), not %u",
                  app->sensor.uav_name, app->sensor.uav_id, s->uav_id);
        reply->error = app->detail;
        return;
    }
    uint32_t n = s->frames ? s->frames : 1;
    if (n > 1000) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        snprintf (app->detail, sizeof app->detail, "at most 1000 frames a request, asked %u", n);
        reply->error = app->detail;
        return;
    }
    app->snapshots += n;
    snprintf (app->detail, sizeof app->detail, "%s: the next %u frame%s to %s",
              app->sensor.uav_name, n, n == 1 ? "" : "s", app->out_dir);
    reply->detail = app->detail;
}

static int s_setup_video (s_app_t *app, char *err, size_t errlen)
{
    const im_params_t *p = &app->params;
    char host[64] = "";
    int port = 0;
    if (p->video_udp[0])
        im_params_parse_udp (p->video_udp, host, sizeof host, &port); // checked at load
    if (p->video_file)
        snprintf (app->video_path, sizeof app->video_path, "%s/%s.ts", app->out_dir,
                  cgs_service_instance_name (app->svc));
    im_vout_config_t oc = {.file = app->video_path,
                           .udp_host = host,
                           .udp_port = port,
                           .ttl = p->video_ttl,
                           .local_addr = p->video_local,
                           .keep_frame = p->video_map};
    if (!(app->vout = im_vout_new (&oc, err, errlen)))
        return -EIO;
    im_vout_stats_t vs;
    im_vout_stats (app->vout, &vs);
    if (vs.cut_bytes)
        cgs_log (LOG_WARNING, "video file %s: cut a partial packet (%llu bytes) off its end",
                 app->video_path, (unsigned long long)vs.cut_bytes);
    im_video_config_t vc = {.width_px = p->width_px,
                            .height_px = p->height_px,
                            .frame_rate_hz = fmin (p->frame_rate_hz, S_MAX_FPS),
                            .bitrate_kbps = p->video_bitrate_kbps,
                            .keyframe_s = p->video_keyframe_s,
                            .preset = p->video_preset,
                            .threads = 1};
    if (!(app->video = im_video_new (&vc, im_vout_write, app->vout, err, errlen)))
        return -EINVAL;
    char udp[160] = "no UDP";
    if (host[0])
        snprintf (udp, sizeof udp, "UDP to %s:%d%s", host, port,
                  IN_MULTICAST (ntohl (inet_addr (host))) ? " (multicast)" : "");
    cgs_log (LOG_INFO,
             "video: H.264 %d kbit/s (x264 %s, a keyframe every %g s) with MISB ST 0601 KLV in "
             "MPEG-TS; %s%s; %s; %s",
             p->video_bitrate_kbps, p->video_preset, p->video_keyframe_s,
             app->video_path[0] ? "file " : "no file", app->video_path, udp,
             p->video_map ? "on the bus (`video`) for the map" : "not on the bus");
    return 0;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    int rc =
        cgs_sensor_setup (&app->sensor, app->svc, "imagerd", 0x9E3779B97F4A7C15ull, err, errlen);
    if (rc < 0)
        return rc;
    im_params_defaults (&app->params);
    const char *params = cgs_service_params_path (app->svc);
    if (*params) {
        if ((rc = im_params_load (params, &app->params, err, errlen)) < 0)
            return rc;
        cgs_log (LOG_INFO, "imager parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "imager parameters: the built-in defaults (no parameter file named)");
    }
    if (!*app->out_dir)
        snprintf (app->out_dir, sizeof app->out_dir, "%s/images", cgs_service_state_dir (app->svc));
    const im_params_t *p = &app->params;
    if (cgs_service_check_only (app->svc))
        return im_ctx_check_driver (getenv ("GALLIUM_DRIVER"), err, errlen);
    app->ents = cgs_entities_new ();
    app->rgba = malloc ((size_t)p->width_px * (size_t)p->height_px * 4);
    if (!app->ents || !app->rgba ||
        im_post_init (&app->post, p->width_px, p->height_px, app->sensor.seed) < 0) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    if (!(app->ctx = im_ctx_new (p->width_px, p->height_px, err, errlen)))
        return -EINVAL;
    im_terrain_mesh_t mesh;
    if ((rc = im_terrain_mesh_build (app->sensor.terrain, p->chunk_cells, p->lods, &mesh)) < 0) {
        snprintf (err, errlen, "cannot build the terrain mesh: %s", strerror (-rc));
        return rc;
    }
    app->ren = im_renderer_new (p->width_px, p->height_px, &mesh, err, errlen);
    cgs_log (LOG_INFO,
             "%s: %d x %d px, %s at %g Hz of simulation time; terrain %d x %d nodes in %zu "
             "chunks, %d levels; rendering with %s (%s)",
             app->sensor.uav_name, p->width_px, p->height_px,
             p->mode == IM_MODE_INFRARED ? "infrared" : "visible", p->frame_rate_hz, mesh.cols,
             mesh.rows, mesh.nchunks, p->lods, im_ctx_backend (),
             app->ren ? im_renderer_gl (app->ren) : "no renderer");
    im_terrain_mesh_fini (&mesh);
    if (!app->ren)
        return -EINVAL;
    if (!(app->png = im_png_writer_new (app->out_dir, S_PNG_QUEUE, err, errlen)))
        return -EIO;
    char abs_dir[PATH_MAX];
    snprintf (app->latest_path, sizeof app->latest_path, "%s/latest.png",
              realpath (app->out_dir, abs_dir) ? abs_dir : app->out_dir);
    cgs_log (LOG_INFO, "images to %s (latest.png every %g s of simulation time%s)", app->out_dir,
             p->latest_rate_hz > 0 ? 1.0 / p->latest_rate_hz : 0.0,
             p->png_rate_hz > 0 ? ", numbered frames too" : "");
    return p->video ? s_setup_video (app, err, errlen) : 0;
}

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    s_app_t *app = arg;
    if (strcmp (name, "out") == 0) {
        if (!*value || strlen (value) >= sizeof app->out_dir - 64) {
            snprintf (why, whylen, "--out needs a folder name under %zu bytes",
                      sizeof app->out_dir - 64);
            return -EINVAL;
        }
        snprintf (app->out_dir, sizeof app->out_dir, "%s", value);
    }
    return 0;
}

int main (int argc, char **argv)
{
    static s_app_t app;
    static const cgs_service_option_t options[] = {
        {"out", true, "DIR", "folder for PNG files and the video file (default: STATE_DIR/images)"},
        {NULL, false, NULL, NULL},
    };
    cgs_service_info_t info = {
        .program = "imagerd",
        .summary = "Imaging sensor of one UAV: renders its view headless (visible, infrared or "
                   "SAR).",
        .options = options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_new (&info, argc, argv, &app.svc);
    if (rc != 0)
        return rc > 0 ? 0 : 1;
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    if (cgs_service_check_only (app.svc)) {
        printf ("%s: parameters and scenario are good\n", cgs_service_instance_name (app.svc));
        exit_code = 0;
        goto done;
    }
    app.mode = app.params.mode;
    app.sar_rng = app.sensor.seed ^ 0x67d71u;
    if (cgs_service_instance (app.svc)->command[0]) {
        if (cgs_service_serve_commands (app.svc, s_on_command, s_save, &app) < 0)
            goto done;
        const uint8_t *saved = NULL;
        size_t saved_len = 0;
        cgs_service_saved_state (app.svc, &saved, &saved_len);
        int rr = saved_len > 0 ? s_restore (&app, saved, saved_len, err, sizeof err) : 0;
        if (rr < 0) {
            cgs_log (LOG_WARNING, "saved state ignored (%s); the mode is the parameters'", err);
            cgs_health_set_error (cgs_service_health (app.svc), err);
        } else if (rr > 0) {
            cgs_log (LOG_NOTICE, "saved mode not taken: %s", err);
        } else if (saved_len > 0) {
            cgs_log (LOG_NOTICE, "resumed in the saved mode: %s", s_mode_name (app.mode));
        }
    }
    if (cgs_service_subscribe (app.svc, "entity", s_on_entity, &app) < 0 ||
        cgs_service_subscribe (app.svc, "intercept", s_on_intercept, &app) < 0 ||
        cgs_service_subscribe (app.svc, "track", s_on_track, &app) < 0 ||
        cgs_service_subscribe (app.svc, "uav", s_on_uav, &app) < 0)
        goto done;
    exit_code = cgs_service_run (app.svc);
    cgs_log (LOG_INFO,
             "%llu frames (%llu skipped to keep under %g per second), %llu PNG files asked for; "
             "entity update to frame %.1f ms on average, %.1f ms at most",
             (unsigned long long)app.frames, (unsigned long long)app.skipped, S_MAX_FPS,
             (unsigned long long)app.pngs,
             app.frames ? 1e3 * app.latency_sum_s / (double)app.frames : 0.0,
             1e3 * app.latency_max_s);
    if (app.video) {
        char verr[256];
        if (im_video_finish (app.video, verr, sizeof verr) < 0)
            cgs_log (LOG_WARNING, "video: %s", verr);
        im_video_stats_t vs;
        im_vout_stats_t os;
        im_video_stats (app.video, &vs);
        im_vout_stats (app.vout, &os);
        cgs_log (os.file_errors || os.udp_errors || os.frames_lost ? LOG_WARNING : LOG_INFO,
                 "video: %llu frames (%llu keyframes, %llu KLV packets, %llu errors), %.1f MB of "
                 "transport stream; file %llu bytes (%llu errors), %llu datagrams (%llu errors), "
                 "%llu frames not on the bus (out of memory)%s%s",
                 (unsigned long long)vs.frames, (unsigned long long)vs.keyframes,
                 (unsigned long long)vs.klv_packets, (unsigned long long)app.video_errors,
                 (double)vs.bytes / 1e6, (unsigned long long)os.file_bytes,
                 (unsigned long long)os.file_errors, (unsigned long long)os.datagrams,
                 (unsigned long long)os.udp_errors, (unsigned long long)os.frames_lost,
                 os.last_error[0] ? "; last: " : "", os.last_error);
    }
done:
    im_video_destroy (&app.video);
    im_vout_destroy (&app.vout);
    if (app.png) {
        im_png_stats_t st;
        im_png_writer_destroy (&app.png, &st); // writes what is queued first
        cgs_log (st.failed ? LOG_WARNING : LOG_INFO,
                 "PNG files: %llu written, %llu dropped (writer behind), %llu failed%s%s",
                 (unsigned long long)st.written, (unsigned long long)st.dropped,
                 (unsigned long long)st.failed, st.failed ? "; last: " : "", st.last_error);
    }
    if (app.sar_chips || app.sar_errors)
        cgs_log (app.sar_errors ? LOG_WARNING : LOG_INFO,
                 "SAR: %llu chips, %llu without an image; the designated target measured in %llu "
                 "of %llu",
                 (unsigned long long)app.sar_chips, (unsigned long long)app.sar_errors,
                 (unsigned long long)app.sar_gmti_hits,
                 (unsigned long long)(app.sar_gmti_hits + app.sar_gmti_misses));
    im_sar_destroy (&app.sar);
    im_renderer_destroy (&app.ren);
    im_ctx_destroy (&app.ctx);
    im_post_fini (&app.post);
    cgs_entities_destroy (&app.ents);
    cgs_sensor_fini (&app.sensor);
    free (app.draw);
    free (app.rgba);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
