/* cgs_scenario — the scenario file: terrain, UAVs, ground vehicles, the
 * operator's scripted actions and uavsim's own settings, read from an INI
 * file into a plain struct for every service that needs it (uavsim simulates
 * it; mtid, bcisd and imagerd take its terrain and UAVs). Every value is checked; every
 * error names the file, the line, the section and key, what was expected and
 * what was found ("s.ini:12: [vehicle t1] speed_mps: expected a number in
 * [0.5, 40], got '90'"). Pure: no logging, no globals.
 *
 * File format (deploy/scenarios/default.ini documents every key):
 *
 *   [terrain]        optional; `dem = PATH` (relative to the scenario file)
 *                    with resolution_m, half_extent_m; or procedural fBm:
 *                    seed, size_m, resolution_m, relief_m (0 = flat),
 *                    base_height_m, feature_m, octaves, persistence; with
 *                    either, woods: vegetation_cover (0..1), canopy_height_m,
 *                    vegetation_feature_m, vegetation_seed
 *   [uav NAME]       one or more
 *   [vehicle NAME]   any number; route as repeated
 *                    `point = POSITION [@ SPEED_MPS] [halt SECONDS]`
 *   [operator]       optional; repeated `designate = FILTER nearest POSITION at TIME_S`
 *   [uavsim]         optional service settings
 *
 * Positions take any form cgs_config_parse_position reads (local metres,
 * `geo LAT LON`, `LAT{N|S} LON{E|W}`, MGRS). In a route point, an '@' (which
 * no position form contains) separates the position from the optional speed
 * of the leg that starts at that point: `point = 1200 -350 @ 8` (blanks
 * around '@' optional). Then, after the whole word `halt` (any case; no
 * position form has a word "halt", nor has a speed), a halt of SECONDS in
 * (0, 3600]: the vehicle stops on that point for so long each time it
 * reaches it, then drives on: `point = 1200 -350 @ 8 halt 60`, or
 * `point = mgrs 10SFE 59641 79460 halt 30`. Not on the first or last point
 * of a route with end = stop (it never comes back to the one, and stops for
 * good on the other). Route rules: at least 2 points, consecutive points at
 * least 1 m apart; the last point takes a speed only with end = loop (the
 * leg back to the first point), and with loop it must not repeat the first
 * point (the route closes by itself); with end = reverse each leg keeps its
 * speed in both directions. With procedural terrain every point must lie on
 * it; every position must be within 200 km of the origin.
 *
 * Entity ids: `id = N` (1..65534, each once) where given; the others get 1,
 * 2, ... skipping given ones, UAVs first, then vehicles, each in file order. */
#ifndef CGS_SCENARIO_H
#define CGS_SCENARIO_H

#include "cgs_geo.h"
#include "cgs_terrain.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Force, with the numbers of proto/header.proto's enum Force. */
typedef enum {
    CGS_FORCE_UNKNOWN = 0,
    CGS_FORCE_FRIENDLY = 1,
    CGS_FORCE_HOSTILE = 2,
    CGS_FORCE_NEUTRAL = 3,
} cgs_force_t;

/* Entity kind, with the numbers of proto/world.proto's enum EntityKind. */
typedef enum {
    CGS_KIND_OTHER = 0,
    CGS_KIND_TRACKED = 1,
    CGS_KIND_WHEELED = 2,
    CGS_KIND_AIR = 3,
    CGS_KIND_PERSON = 4,
} cgs_kind_t;

/* What a vehicle does after its last route point. */
typedef enum {
    CGS_END_STOP = 0,    // stops there for good
    CGS_END_LOOP = 1,    // drives on to the first point and round again
    CGS_END_REVERSE = 2, // drives the route backwards, and so on, back and forth
} cgs_end_t;

/* Which tracks a scripted designation may pick. */
typedef enum {
    CGS_PICK_UNKNOWN = 0,  // tracks not identified as friendly by BCIS
    CGS_PICK_FRIENDLY = 1, // tracks identified as friendly
    CGS_PICK_ANY = 2,      // any track
} cgs_pick_t;

/* DIS entity type (IEEE 1278.1, SISO-REF-010), written in the file as seven
 * numbers "kind domain country category subcategory specific extra". */
typedef struct {
    uint8_t kind;
    uint8_t domain;
    uint16_t country;
    uint8_t category;
    uint8_t subcategory;
    uint8_t specific;
    uint8_t extra;
} cgs_dis_type_t;

#define CGS_MARKING_MAX       11 // DIS marking: at most 11 ASCII characters
#define CGS_SCENARIO_NAME_MAX 63 // UAV and vehicle names: [A-Za-z0-9_.-], at most 63

typedef enum {
    CGS_TERRAIN_FBM = 0, // procedural (the default; relief_m = 0 gives flat ground)
    CGS_TERRAIN_DEM = 1, // a DEM file read through GDAL
} cgs_terrain_source_t;

typedef struct {
    cgs_terrain_source_t source;
    cgs_terrain_fbm_t fbm; // when source is FBM; seed defaults to the exercise seed
    char *dem_path;        // when source is DEM: the file, joined to the scenario's folder
    double resolution_m;   // DEM: grid spacing, 0 = about the raster's own (default 0)
    double half_extent_m;  // DEM: half-width of the square read, 0 = whole raster (default 10000)
    cgs_vegetation_t vegetation; // woods over either kind: vegetation_cover (default 0),
                                 // canopy_height_m, vegetation_feature_m, vegetation_seed
} cgs_terrain_spec_t;

typedef struct {
    char name[CGS_SCENARIO_NAME_MAX + 1]; // section name, e.g. "uav1"
    int line;                             // line of its [uav NAME] header
    uint32_t id;                          // entity id, unique in the scenario
    char marking[CGS_MARKING_MAX + 1];    // default: the name, cut to 11 characters
    cgs_dis_type_t dis_type;              // default 1 2 225 50 0 0 0 (platform, air, USA, unmanned)
    cgs_enu_t position;                   // start, local frame (up ignored: see altitude_agl_m)
    double altitude_agl_m;                // above the terrain (default 1200)
    double airspeed_mps;                  // (default 35)
    double heading_deg;                   // start heading, clockwise from north (default 0)
    cgs_enu_t loiter_center;              // default: the start position
    double loiter_radius_m;               // (default 1500)
    bool loiter_clockwise;   // loiter_direction = clockwise|anticlockwise (default clockwise)
    double standoff_m;       // least distance of the loiter orbit to any route (default 1000;
                             // 0: not checked): cgs_scenario_standoff warns below it
    double bank_limit_deg;   // (default 30)
    double climb_rate_mps;   // largest climb or descent rate (default 5)
    double airspeed_min_mps; // slowest commanded airspeed (default 20, or the start's if slower)
    double airspeed_max_mps; // fastest commanded airspeed (default 60, or the start's if faster)
    double sensor_depression_deg; // imaging sensor, below the horizon (default 45)
    double sensor_hfov_deg;       // horizontal field of view (default 10)
    double sensor_vfov_deg;       // vertical field of view (default 7.5)
    bool sensor_stabilized;       // levelled against the bank (default false)
    bool sensor_stare_target;     // sensor_stare = off|target: staring at the designated target
                                  // (default off)
    double sensor_depression_min_deg, sensor_depression_max_deg; // the camera command's limits
                                                                 // (default 5, 89)
    double sensor_hfov_min_deg, sensor_hfov_max_deg;             // zoom limits (default 1, 40)
    double gimbal_azimuth_limit_deg; // staring: either side of the nose (default 150)
    double gimbal_elevation_min_deg, gimbal_elevation_max_deg; // staring: below (negative) or above
                                                               // the body's plane (default −90, 0)
    char *radar_params; // radar parameter file, "" when not given
    char *bcis_params;  // BCIS parameter file, "" when not given
} cgs_scenario_uav_t;

typedef struct {
    cgs_enu_t position; // local frame; up is ignored (vehicles keep to the ground)
    double speed_mps;   // speed on the leg that starts here (the vehicle's speed unless given)
    bool speed_given;   // an `@ SPEED` was written
    double halt_s;      // seconds it halts on reaching this point (0: drives on; `halt S`)
    int line;           // line of its `point =`
} cgs_point_t;

typedef struct {
    char name[CGS_SCENARIO_NAME_MAX + 1]; // section name, e.g. "t1"
    int line;                             // line of its [vehicle NAME] header
    uint32_t id;                          // entity id, unique in the scenario
    char marking[CGS_MARKING_MAX + 1];    // default: the name, cut to 11 characters
    cgs_force_t force;                    // required
    cgs_kind_t kind;                      // tracked|wheeled|person (default tracked)
    cgs_dis_type_t dis_type; // default by kind; country 225 (USA) when friendly, else 0
    bool bcis_transponder;   // default: yes when friendly
    char *rcs_class;         // radar cross-section class (default "vehicle")
    double start_time_s;     // stands still at its first point until then (default 0)
    double speed_mps;        // default leg speed (default 10)
    cgs_point_t *points;     // the route, at least 2 points
    size_t point_count;
    cgs_end_t end;           // (default stop)
    double deviation_m;      // how far it wanders off the straight legs (default 0)
    uint64_t deviation_seed; // default: cgs_scenario_vehicle_seed (exercise seed, id)
} cgs_scenario_vehicle_t;

/* `designate = FILTER nearest POSITION at TIME_S` in [operator]. */
typedef struct {
    cgs_pick_t pick; // which tracks qualify
    cgs_enu_t near;  // the track nearest this point is designated
    double time_s;   // simulation time of the designation
    int line;
} cgs_designation_t;

/* [uavsim]: the service's own settings. */
typedef struct {
    double step_s;                // simulation step, simulated seconds (default 0.05)
    double entity_rate_hz;        // entity publication, per simulated second (default 10)
    double uav_rate_hz;           // uav publication, per simulated second (default 10)
    double clock_rate_hz;         // clock publication, per simulated second (default 10)
    double checkpoint_interval_s; // checkpoint period, wall-clock seconds (default 5)
} cgs_uavsim_settings_t;

typedef struct {
    char *path; // the file it was read from
    cgs_terrain_spec_t terrain;
    cgs_scenario_uav_t *uavs; // in file order, at least one
    size_t uav_count;
    cgs_scenario_vehicle_t *vehicles; // in file order
    size_t vehicle_count;
    cgs_designation_t *designations; // in file order
    size_t designation_count;
    cgs_uavsim_settings_t settings;
} cgs_scenario_t;

/* Read a scenario file. Geodetic and MGRS positions are placed in frame (may
 * be NULL when every position is in local metres). default_seed (the
 * exercise seed) seeds the procedural terrain and the vehicles' deviation
 * unless the file gives seeds. 0, or -ENOENT/-EINVAL/-ENOMEM with
 * "file:line: [section] key: reason" in err; *ret is written only on success. */
int cgs_scenario_load (const char *path, const cgs_geo_t *frame, uint64_t default_seed,
                       cgs_scenario_t **ret, char *err, size_t errlen);
/* The same from text, as if read from a file called name (relative paths in
 * it are taken from name's folder). */
int cgs_scenario_load_string (const char *name, const char *text, const cgs_geo_t *frame,
                              uint64_t default_seed, cgs_scenario_t **ret, char *err,
                              size_t errlen);
/* Free; accepts NULL and a half-built scenario; sets *self_p to NULL. */
void cgs_scenario_destroy (cgs_scenario_t **self_p);

/* Build the scenario's terrain: the DEM (frame required) or the procedural
 * fBm square. 0, or -errno with the reason in err; *ret_t only on success. */
int cgs_scenario_terrain (const cgs_scenario_t *self, const cgs_geo_t *frame, cgs_terrain_t **ret_t,
                          char *err, size_t errlen);
/* The deviation seed a vehicle gets when its section gives none: output
 * number id of splitmix64 seeded with the exercise seed. */
uint64_t cgs_scenario_vehicle_seed (uint64_t exercise_seed, uint32_t id);
/* The vehicle or UAV of that name, or NULL. */
const cgs_scenario_vehicle_t *cgs_scenario_vehicle (const cgs_scenario_t *self, const char *name);

/* A UAV's loiter orbit closer to a vehicle's route than its standoff_m. */
typedef struct {
    size_t uav, vehicle; // indices in the scenario
    size_t leg;          // the route's leg (points leg and leg + 1) that comes closest
    double distance_m;   // the least distance between the orbit (the circle) and that leg
} cgs_standoff_t;

/* The stand-off check: for each UAV with standoff_m > 0 and each vehicle,
 * the least horizontal distance between the loiter orbit and the route's
 * legs (zero where a leg crosses the orbit); the pairs nearer than the
 * UAV's standoff_m are written to ret (at most max) in file order. Returns
 * how many pairs there are in all. A scenario may be flown so (a warning,
 * not an error): the orbit is where the UAV waits and watches, and a route
 * under it puts a target beneath the radar, in its near-range blind zone
 * and inside the UAV's turns. */
size_t cgs_scenario_standoff (const cgs_scenario_t *self, cgs_standoff_t *ret, size_t max);
/* One of them as text: "FILE:LINE: [uav U] loiter orbit comes within D m of
 * vehicle V's route (leg from line A to line B); stand-off is S m". */
void cgs_scenario_standoff_text (const cgs_scenario_t *self, const cgs_standoff_t *s, char *buf,
                                 size_t len);
const cgs_scenario_uav_t *cgs_scenario_uav (const cgs_scenario_t *self, const char *name);

#endif
