/* ls_run — one whole exercise in lockstep (see ls_run.h). */
#include "ls_run.h"

#include "bcis_adapter.h"
#include "cgs_exercise.h"
#include "cgs_util.h"
#include "gd_adapter.h"
#include "ls_bus.h"
#include "mti_adapter.h"
#include "trk_adapter.h"
#include "uavsim_adapter.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_SENSORS_MAX   16  // mtid and bcisd instances
#define S_TICK_S        0.2 // guidanced's delivery tick, as its daemon's (simulation time here)
#define S_LIMIT_AFTER_S 1500.0
#define S_LIMIT_NONE_S  1800.0
#define S_PI            3.14159265358979323846

/* The salts the sensor daemons seed their models with (their main.c). */
#define S_SALT_MTID  0xD1B54A32D192ED03ull
#define S_SALT_BCISD 0xC2B2AE3D27D4EB4Full

typedef struct {
    cgs_sensor_t sensor;
    mti_adapter_t *mti;
    bcis_adapter_t *bcis;
} s_sensor_t;

typedef struct {
    const ls_run_config_t *c;
    cgs_exercise_t *ex;
    cgs_geo_t *frame;
    uavsim_world_t *world;
    ls_bus_t *bus;
    uavsim_adapter_t *uavsim;
    s_sensor_t sensors[S_SENSORS_MAX];
    size_t nsensors;
    trk_adapter_t *trk;
    gd_adapter_t *gd;
    ls_source_t *gd_source;
    ls_run_result_t *res;
} s_run_t;

/* ---- the subscribers ----------------------------------------------------------------- */

static void s_to_mti (void *arg, const char *topic, const ProtobufCMessage *m, const Cgs__Header *h)
{
    mti_adapter_on_message (arg, topic, m, h);
}

static void s_to_bcis (void *arg, const char *topic, const ProtobufCMessage *m,
                       const Cgs__Header *h)
{
    bcis_adapter_on_message (arg, topic, m, h);
}

static void s_to_trk (void *arg, const char *topic, const ProtobufCMessage *m, const Cgs__Header *h)
{
    trk_adapter_on_message (arg, topic, m, h);
}

static void s_to_uavsim (void *arg, const char *topic, const ProtobufCMessage *m,
                         const Cgs__Header *h)
{
    (void)topic;
    uavsim_adapter_on_intercept (arg, (const Cgs__Intercept *)m, h->sim_time_s);
}

static void s_to_gd (void *arg, const char *topic, const ProtobufCMessage *m, const Cgs__Header *h)
{
    gd_adapter_on_message (arg, topic, m, h);
}

static int s_subscribe (s_run_t *r, const char *const *topics, cgs_sub_fn *fn, void *arg)
{
    for (size_t i = 0; topics[i]; i++) {
        int rc = ls_bus_subscribe (r->bus, topics[i], fn, arg);
        if (rc < 0)
            return rc;
    }
    return 0;
}

/* ---- building the exercise ----------------------------------------------------------- */

/* The scenario with this run's variation. */
static int s_scenario (s_run_t *r, uint64_t seed, cgs_scenario_t **ret, char *err, size_t errlen)
{
    const ls_run_config_t *c = r->c;
    const char *path = c->scenario_path ? c->scenario_path : cgs_exercise_scenario (r->ex);
    if (!path || !*path) {
        cgs_errf (err, errlen, "%s names no scenario: give one", cgs_exercise_path (r->ex));
        return -EINVAL;
    }
    cgs_scenario_t *sc = NULL;
    int rc = cgs_scenario_load (path, r->frame, seed, &sc, err, errlen);
    if (rc < 0)
        return rc;
    for (size_t i = 0; i < sc->designation_count; i++)
        sc->designations[i].time_s = fmax (0, sc->designations[i].time_s + c->designation_shift_s);
    if (c->uav_phase_given) {
        for (size_t i = 0; i < sc->uav_count; i++) {
            cgs_scenario_uav_t *u = &sc->uavs[i];
            double b = c->uav_phase_deg * S_PI / 180;
            u->position.e_m = u->loiter_center.e_m + u->loiter_radius_m * sin (b);
            u->position.n_m = u->loiter_center.n_m + u->loiter_radius_m * cos (b);
            // Along the orbit: clockwise turns right of the outward bearing.
            double h = c->uav_phase_deg + (u->loiter_clockwise ? 90 : -90);
            u->heading_deg = fmod (h + 720, 360);
        }
    }
    *ret = sc;
    return 0;
}

/* A sensor instance: mtid or bcisd on its UAV, parameters from the
 * instance's file, else the UAV's, else the defaults (as the daemons). */
static int s_sensor (s_run_t *r, const cgs_instance_t *in, bool radar, uint64_t seed, char *err,
                     size_t errlen)
{
    if (r->nsensors == S_SENSORS_MAX) {
        cgs_errf (err, errlen, "more than %d sensor instances", S_SENSORS_MAX);
        return -EINVAL;
    }
    if (!*in->uav) {
        cgs_errf (err, errlen, "%s: [service %s] names no `uav =`", cgs_exercise_path (r->ex),
                  in->name);
        return -EINVAL;
    }
    s_sensor_t *s = &r->sensors[r->nsensors];
    // The world's scenario and terrain, shared (the sensor only reads them).
    int rc = cgs_sensor_attach (&s->sensor, in->uav, r->frame,
                                (cgs_scenario_t *)uavsim_world_scenario (r->world),
                                (cgs_terrain_t *)uavsim_world_terrain (r->world), seed,
                                radar ? S_SALT_MTID : S_SALT_BCISD, err, errlen);
    if (rc < 0)
        return rc;
    r->nsensors++;
    cgs_port_t port = ls_bus_port (ls_bus_source (r->bus, in->name));
    const cgs_scenario_uav_t *u = s->sensor.uav;
    if (radar) {
        mti_params_t p;
        mti_params_defaults (&p);
        const char *file = *in->params ? in->params : u->radar_params;
        if (file && *file && (rc = mti_params_load (file, &p, err, errlen)) < 0)
            return rc;
        if (!(s->mti = mti_adapter_new (&p, &s->sensor, &port)))
            return -ENOMEM;
        return s_subscribe (r, mti_adapter_topics, s_to_mti, s->mti);
    }
    bcis_params_t p;
    bcis_params_defaults (&p);
    const char *file = *in->params ? in->params : u->bcis_params;
    if (file && *file && (rc = bcis_params_load (file, &p, err, errlen)) < 0)
        return rc;
    if (!(s->bcis = bcis_adapter_new (&p, &s->sensor, &port)))
        return -ENOMEM;
    return s_subscribe (r, bcis_adapter_topics, s_to_bcis, s->bcis);
}

static int s_build (s_run_t *r, char *err, size_t errlen)
{
    const ls_run_config_t *c = r->c;
    int rc = cgs_exercise_load (c->exercise_path, &r->ex, err, errlen);
    if (rc < 0)
        return rc;
    cgs_geodetic_t o = cgs_exercise_origin (r->ex);
    if (!(r->frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m))) {
        cgs_errf (err, errlen, "%s: the exercise origin is not usable", c->exercise_path);
        return -EINVAL;
    }
    uint64_t seed = c->seed_given ? c->seed : cgs_exercise_seed (r->ex);
    cgs_scenario_t *sc = NULL;
    if ((rc = s_scenario (r, seed, &sc, err, errlen)) < 0)
        return rc;
    if ((rc = uavsim_world_new (sc, r->frame, &r->world, err, errlen)) < 0)
        return rc; // it took the scenario over, and freed it
    if (!(r->bus = ls_bus_new (cgs_exercise_id (r->ex))))
        return -ENOMEM;
    ls_bus_set_log (r->bus, c->log);
    // The observer first: it sees every message before the services react.
    ms_icpt_t *ic = &r->res->icpt;
    ms_icpt_init (ic);
    if (ls_bus_subscribe (r->bus, "intercept", ms_icpt_on_intercept, ic) < 0 ||
        ls_bus_subscribe (r->bus, "track", ms_icpt_on_track, ic) < 0 ||
        ls_bus_subscribe (r->bus, "mti.truth", ms_icpt_on_mti_truth, ic) < 0 ||
        ls_bus_subscribe (r->bus, "entity", ms_icpt_on_entity, ic) < 0)
        return -ENOMEM;
    const cgs_instance_t *uavsim = NULL;
    for (size_t i = 0; i < cgs_exercise_instance_count (r->ex); i++) {
        const cgs_instance_t *in = cgs_exercise_instance (r->ex, i);
        if (!in->enabled)
            continue;
        if (strcmp (in->program, "uavsim") == 0 && !uavsim) {
            uavsim = in;
            cgs_port_t port = ls_bus_port (ls_bus_source (r->bus, in->name));
            if (!(r->uavsim = uavsim_adapter_new (r->world, o, &port)))
                return -ENOMEM;
            if ((rc = ls_bus_subscribe (r->bus, "intercept", s_to_uavsim, r->uavsim)) < 0)
                return rc;
        } else if (strcmp (in->program, "mtid") == 0 || strcmp (in->program, "bcisd") == 0) {
            if ((rc = s_sensor (r, in, in->program[0] == 'm', seed, err, errlen)) < 0)
                return rc;
        } else if (strcmp (in->program, "trackerd") == 0 && !r->trk) {
            trk_params_t p;
            trk_params_defaults (&p);
            if (*in->params && (rc = trk_params_load (in->params, &p, err, errlen)) < 0)
                return rc;
            cgs_port_t port = ls_bus_port (ls_bus_source (r->bus, in->name));
            if (!(r->trk = trk_adapter_new (&p, &port)))
                return -ENOMEM;
            trk_tracker_set_terrain (trk_adapter_tracker (r->trk), uavsim_world_terrain (r->world));
            if ((rc = s_subscribe (r, trk_adapter_topics, s_to_trk, r->trk)) < 0)
                return rc;
        } else if (strcmp (in->program, "guidanced") == 0 && !r->gd) {
            gd_params_t p;
            gd_params_defaults (&p);
            if (*in->params && (rc = gd_params_load (in->params, &p, err, errlen)) < 0)
                return rc;
            r->gd_source = ls_bus_source (r->bus, in->name);
            cgs_port_t port = ls_bus_port (r->gd_source);
            if (!(r->gd = gd_adapter_new (&p, uavsim_world_scenario (r->world),
                                          uavsim_world_terrain (r->world), &port, NULL)))
                return -ENOMEM;
            gd_adapter_set_client_id (r->gd, "guidanced@lockstep");
            if ((rc = s_subscribe (r, gd_adapter_topics, s_to_gd, r->gd)) < 0)
                return rc;
        }
    }
    if (!r->uavsim) {
        cgs_errf (err, errlen, "%s has no enabled uavsim instance", c->exercise_path);
        return -EINVAL;
    }
    if (c->watch) {
        static const char *const all[] = {"clock",      "entity",    "uav",  "mti",
                                          "mti.truth",  "mti.scan",  "bcis", "track",
                                          "track.turn", "intercept", NULL};
        if ((rc = s_subscribe (r, all, c->watch, c->watch_arg)) < 0)
            return rc;
    }
    return 0;
}

static void s_free (s_run_t *r)
{
    gd_adapter_destroy (&r->gd);
    trk_adapter_destroy (&r->trk);
    for (size_t i = 0; i < r->nsensors; i++) {
        mti_adapter_destroy (&r->sensors[i].mti);
        bcis_adapter_destroy (&r->sensors[i].bcis);
        cgs_sensor_fini (&r->sensors[i].sensor);
    }
    uavsim_adapter_destroy (&r->uavsim);
    ls_bus_destroy (&r->bus);
    uavsim_world_destroy (&r->world);
    cgs_geo_destroy (&r->frame);
    cgs_exercise_destroy (&r->ex);
}

/* ---- running ----------------------------------------------------------------------- */

/* guidanced's tasks to uavsim, each answered at once (as the command
 * channel would after its round trip). */
static void s_deliver (s_run_t *r)
{
    if (!r->gd)
        return;
    size_t cursor = 0;
    gd_adapter_task_t task;
    while (gd_adapter_next_task (r->gd, &cursor, &task)) {
        Cgs__Command cmd = *task.command;
        cmd.client_id = (char *)gd_adapter_client_id (r->gd);
        cmd.command_number = task.command_number;
        Cgs__Reply reply = CGS__REPLY__INIT;
        reply.status = CGS__REPLY_STATUS__REPLY_STATUS_OK;
        uavsim_adapter_command (r->uavsim, &cmd, &reply);
        gd_adapter_task_answered (r->gd, &task, &reply);
        r->res->tasks++;
    }
}

static double s_limit (const s_run_t *r)
{
    if (r->c->limit_s > 0)
        return r->c->limit_s;
    const cgs_scenario_t *sc = uavsim_world_scenario (r->world);
    if (sc->designation_count == 0)
        return S_LIMIT_NONE_S;
    double last = 0;
    for (size_t i = 0; i < sc->designation_count; i++)
        last = fmax (last, sc->designations[i].time_s);
    return last + S_LIMIT_AFTER_S;
}

int ls_run (const ls_run_config_t *c, ls_run_result_t *ret, char *err, size_t errlen)
{
    s_run_t r = {.c = c, .res = ret};
    memset (ret, 0, sizeof *ret);
    int rc = s_build (&r, err, errlen);
    if (rc < 0) {
        s_free (&r);
        return rc;
    }
    double limit = s_limit (&r), next_tick = 0;
    uavsim_adapter_publish_due (r.uavsim, true);
    ret->messages += ls_bus_drain (r.bus);
    for (;;) {
        double t = uavsim_world_time (r.world);
        if (t >= limit)
            break;
        if (ret->icpt.final && t >= ret->icpt.final_s + c->after_s)
            break;
        uavsim_adapter_step (r.uavsim);
        ret->steps++;
        ret->messages += ls_bus_drain (r.bus);
        if (r.gd && t + 1e-9 >= next_tick) {
            gd_adapter_tick (r.gd);
            next_tick = t + S_TICK_S;
        }
        s_deliver (&r);
        ret->messages += ls_bus_drain (r.bus);
    }
    ret->end_s = uavsim_world_time (r.world);
    ret->failures = ls_bus_failures (r.bus);
    ls_bus_report (r.bus, &ret->bad_inputs, &ret->errors, ret->first_error,
                   sizeof ret->first_error);
    s_free (&r);
    return 0;
}
