/* libFuzzer target: any bytes as every checkpoint the services restore
 * (uavsim's UAV, vehicle and world, trackerd's tracks and their next id,
 * guidanced's intercept and state) and as a cgs_ckpt frame read field by
 * field: first as they are (the frame's checks), then sealed as the
 * payload of a good frame of each kind (the decoders behind the checks).
 * Must never crash, leak or hit undefined behaviour. A refused restore
 * leaves its object as it was (guidanced's state aside: it resets), and
 * the checkpoint of a restored object restores to itself; a breach aborts. */
#include "cgs_ckpt.h"
#include "cgs_scenario.h"
#include "cgs_util.h"
#include "gd_adapter.h"
#include "gd_checkpoint.h"
#include "trk_checkpoint.h"
#include "trk_tracker.h"
#include "uavsim_uav.h"
#include "uavsim_vehicle.h"
#include "uavsim_world.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size);

static const char *const s_scenario = "[terrain]\n"
                                      "seed = 3\n"
                                      "size_m = 2000\n"
                                      "resolution_m = 100\n"
                                      "relief_m = 50\n"
                                      "[uav uav1]\n"
                                      "position = -500 -500\n"
                                      "loiter_radius_m = 800\n"
                                      "[vehicle a]\n"
                                      "force = unknown\n"
                                      "point = 0 0\n"
                                      "point = 500 0\n"
                                      "point = 500 500\n"
                                      "end = reverse\n"
                                      "deviation_m = 20\n";

static const uavsim_vehicle_point_t s_points[] = {{0, 0, 0}, {400, 0, 8}, {400, 300, 0}};
static const double s_halts[] = {0, 20, 0};

/* What the restores go into, made once. */
typedef struct {
    uavsim_uav_model_t *uav;
    uavsim_vehicle_t *vehicle;
    uavsim_world_t *world;
    trk_tracker_t *tracker;
    gd_intercept_t *intercept;
    cgs_scenario_t *scenario; // guidanced's
    gd_adapter_t *adapter;
} s_targets_t;

static s_targets_t *s_targets (void)
{
    static s_targets_t t;
    static bool made;
    if (made)
        return &t;
    made = true;
    uavsim_uav_params_t up;
    uavsim_uav_params_defaults (&up);
    uavsim_uav_init_t init = {.position = {0, 0, 500},
                              .heading_deg = 30,
                              .airspeed_mps = 35,
                              .agl_m = 400,
                              .loiter_clockwise = true};
    t.uav = uavsim_uav_new (&up, &init);
    uavsim_vehicle_params_t vp;
    uavsim_vehicle_params_defaults (&vp);
    vp.points = s_points;
    vp.n_points = 3;
    vp.halt_s = s_halts;
    vp.deviation_m = 10;
    vp.end = UAVSIM_VEHICLE_END_REVERSE;
    (void)uavsim_vehicle_new (&vp, &t.vehicle);
    char err[512];
    cgs_scenario_t *sc = NULL;
    if (cgs_scenario_load_string ("fuzz.ini", s_scenario, NULL, 1, &sc, err, sizeof err) == 0)
        (void)uavsim_world_new (sc, NULL, &t.world, err, sizeof err);
    trk_params_t tp;
    trk_params_defaults (&tp);
    t.tracker = trk_tracker_new (&tp);
    gd_params_t gp;
    gd_params_defaults (&gp);
    t.intercept = gd_intercept_new (&gp, NULL);
    if (cgs_scenario_load_string ("fuzz.ini", s_scenario, NULL, 1, &t.scenario, err, sizeof err) ==
        0) {
        cgs_port_t port = {0};
        t.adapter = gd_adapter_new (&gp, t.scenario, NULL, &port, NULL);
    }
    if (!t.uav || !t.vehicle || !t.world || !t.tracker || !t.intercept || !t.adapter)
        abort ();
    return &t;
}

typedef int (*s_save_fn) (const void *obj, uint8_t **ret_buf, size_t *ret_len);
typedef int (*s_restore_fn) (void *obj, const uint8_t *buf, size_t len, char *err, size_t errlen);

static int s_uav_save (const void *o, uint8_t **b, size_t *n)
{
    return uavsim_uav_save (o, b, n);
}
static int s_uav_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return uavsim_uav_restore (o, b, n, e, el);
}
static int s_vehicle_save (const void *o, uint8_t **b, size_t *n)
{
    return uavsim_vehicle_save (o, b, n);
}
static int s_vehicle_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return uavsim_vehicle_restore (o, b, n, e, el);
}
static int s_world_save (const void *o, uint8_t **b, size_t *n)
{
    return uavsim_world_save (o, b, n);
}
static int s_world_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return uavsim_world_restore (o, b, n, e, el);
}
static int s_trk_save (const void *o, uint8_t **b, size_t *n)
{
    return trk_checkpoint_save (o, b, n);
}
static int s_trk_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return trk_checkpoint_restore (o, b, n, e, el);
}
static int s_gd_save (const void *o, uint8_t **b, size_t *n)
{
    return gd_checkpoint_save (o, b, n);
}
static int s_gd_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return gd_checkpoint_restore (o, b, n, e, el);
}
static int s_adapter_save (const void *o, uint8_t **b, size_t *n)
{
    return gd_adapter_save (o, b, n);
}
static int s_adapter_restore (void *o, const uint8_t *b, size_t n, char *e, size_t el)
{
    return gd_adapter_restore (o, b, n, e, el);
}

/* Restore buf into obj. Refused: obj saves what it saved before (unless
 * the kind resets on refusal, guidanced's state). Taken: obj's checkpoint
 * restores to itself (a restore may normalise what it derives, such as a
 * vehicle's heading, but only once). A breach aborts. */
static void s_restore (void *obj, s_save_fn save, s_restore_fn restore, bool keeps,
                       const uint8_t *buf, size_t len)
{
    uint8_t *before = NULL, *after = NULL, *again = NULL;
    size_t nb = 0, na = 0, ng = 0;
    char err[512];
    if (save (obj, &before, &nb) < 0)
        return;
    int rc = restore (obj, buf, len, err, sizeof err);
    if (rc != -ENOMEM && save (obj, &after, &na) == 0) {
        if (rc < 0 && keeps && (na != nb || memcmp (after, before, na) != 0))
            abort (); // a refused restore changed its object
        if (rc == 0) {
            if (restore (obj, after, na, err, sizeof err) != 0)
                abort (); // its own checkpoint is refused
            if (save (obj, &again, &ng) == 0 && (ng != na || memcmp (again, after, na) != 0))
                abort (); // and does not restore to itself
        }
    }
    free (before);
    free (after);
    free (again);
}

/* Every field type read from the frame, until the reader fails. */
static void s_read_fields (const uint8_t *buf, size_t len)
{
    cgs_ckpt_reader_t r;
    char err[256];
    if (cgs_ckpt_open (&r, buf, len, "FUZZ", 1, "fuzz checkpoint", err, sizeof err) < 0)
        return;
    for (unsigned k = 0; cgs_ckpt_ok (&r); k++) {
        size_t n;
        char s[16];
        switch (k % 8) {
        case 0:
            (void)cgs_ckpt_get_u8 (&r);
            break;
        case 1:
            (void)cgs_ckpt_get_bool (&r);
            break;
        case 2:
            (void)cgs_ckpt_get_u32 (&r);
            break;
        case 3:
            (void)cgs_ckpt_get_u64 (&r);
            break;
        case 4:
            (void)cgs_ckpt_get_f64 (&r);
            break;
        case 5:
            (void)cgs_ckpt_get_finite (&r);
            break;
        case 6:
            (void)cgs_ckpt_get_bytes (&r, &n);
            break;
        default:
            cgs_ckpt_get_str (&r, s, sizeof s);
            break;
        }
    }
    (void)cgs_ckpt_end (&r, "fuzz checkpoint", err, sizeof err);
}

/* data as the payload of a good frame of kind magic, version 1. */
static uint8_t *s_seal (const char *magic, const uint8_t *data, size_t size, size_t *ret_len)
{
    size_t len = CGS_CKPT_HEAD + size + CGS_CKPT_TAIL;
    uint8_t *b = malloc (len);
    if (!b)
        return NULL;
    memcpy (b, magic, 4);
    const uint64_t head[2] = {1, size};
    for (int i = 0; i < 4; i++)
        b[4 + i] = (uint8_t)(head[0] >> (8 * i));
    for (int i = 0; i < 8; i++)
        b[8 + i] = (uint8_t)(head[1] >> (8 * i));
    if (size)
        memcpy (b + CGS_CKPT_HEAD, data, size);
    uint32_t crc = cgs_crc32 (data, size);
    for (int i = 0; i < 4; i++)
        b[CGS_CKPT_HEAD + size + i] = (uint8_t)(crc >> (8 * i));
    *ret_len = len;
    return b;
}

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size)
{
    s_targets_t *t = s_targets ();
    struct {
        const char *magic;
        void *obj;
        s_save_fn save;
        s_restore_fn restore;
        bool keeps; // a refused restore leaves the object as it was
    } kinds[] = {
        {"UUAV", t->uav, s_uav_save, s_uav_restore, true},
        {"UVHC", t->vehicle, s_vehicle_save, s_vehicle_restore, true},
        {"UWLD", t->world, s_world_save, s_world_restore, true},
        {"TRKS", t->tracker, s_trk_save, s_trk_restore, true},
        {"GDIC", t->intercept, s_gd_save, s_gd_restore, true},
        {"GDST", t->adapter, s_adapter_save, s_adapter_restore, false},
    };
    uint32_t id;
    s_read_fields (data, size);
    (void)trk_checkpoint_next_id (data, size, &id);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++)
        s_restore (kinds[k].obj, kinds[k].save, kinds[k].restore, kinds[k].keeps, data, size);
    size_t len = 0;
    uint8_t *sealed = s_seal ("FUZZ", data, size, &len);
    if (sealed)
        s_read_fields (sealed, len);
    free (sealed);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        sealed = s_seal (kinds[k].magic, data, size, &len);
        if (!sealed)
            continue;
        if (k == 3)
            (void)trk_checkpoint_next_id (sealed, len, &id);
        s_restore (kinds[k].obj, kinds[k].save, kinds[k].restore, kinds[k].keeps, sealed, len);
        free (sealed);
    }
    return 0;
}
