/* cgs_geo — geodesy for mscgs: the exercise's local east-north-up frame,
 * geodetic (WGS84), geocentric (ECEF, as DIS uses), MGRS (as operators read),
 * and DIS Euler angles. A thin C API over GeographicLib (cgs_geo.cpp is the
 * only C++ in the tree). Pure: no globals, no logging. */
#ifndef CGS_GEO_H
#define CGS_GEO_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double lat_deg;  // latitude, degrees north
    double lon_deg;  // longitude, degrees east
    double height_m; // height above the WGS84 ellipsoid, metres
} cgs_geodetic_t;

typedef struct {
    double e_m; // east of the exercise origin, metres
    double n_m; // north of the exercise origin, metres
    double u_m; // up from the exercise origin, metres
} cgs_enu_t;

typedef struct {
    double x_m, y_m, z_m; // WGS84 geocentric (ECEF), metres
} cgs_ecef_t;

/* DIS Euler angles (IEEE 1278.1): the entity's body axes (x forward, y right,
 * z down) from the ECEF axes by rotations psi about z, theta about y, phi
 * about x, in that order. */
typedef struct {
    double psi_rad;
    double theta_rad;
    double phi_rad;
} cgs_dis_euler_t;

/* A local east-north-up frame tangent to the ellipsoid at its origin. */
typedef struct cgs_geo cgs_geo_t;

/* Frame about an origin; NULL if the latitude is outside [-90, 90] or a value is not finite. */
cgs_geo_t *cgs_geo_new (double lat_deg, double lon_deg, double height_m);
/* Free the frame and set *self_p to NULL; accepts NULL and *self_p == NULL. */
void cgs_geo_destroy (cgs_geo_t **self_p);
/* The frame's origin. */
cgs_geodetic_t cgs_geo_origin (const cgs_geo_t *self);

/* Local ENU to geodetic; 0 or -EINVAL. */
int cgs_geo_enu_to_geodetic (const cgs_geo_t *self, cgs_enu_t p, cgs_geodetic_t *ret_g);
/* Geodetic to local ENU; 0 or -EINVAL. */
int cgs_geo_geodetic_to_enu (const cgs_geo_t *self, cgs_geodetic_t g, cgs_enu_t *ret_p);
/* Local ENU to ECEF; 0 or -EINVAL. */
int cgs_geo_enu_to_ecef (const cgs_geo_t *self, cgs_enu_t p, cgs_ecef_t *ret_x);
/* ECEF to local ENU; 0 or -EINVAL. */
int cgs_geo_ecef_to_enu (const cgs_geo_t *self, cgs_ecef_t x, cgs_enu_t *ret_p);
/* Rotate a vector (velocity, direction) from the local frame's axes to ECEF axes. */
void cgs_geo_enu_vector_to_ecef (const cgs_geo_t *self, cgs_enu_t v, cgs_ecef_t *ret_v);
/* Rotate a vector from ECEF axes to the local frame's axes. */
void cgs_geo_ecef_vector_to_enu (const cgs_geo_t *self, cgs_ecef_t v, cgs_enu_t *ret_v);

/* Geodetic to ECEF (WGS84); 0 or -EINVAL. */
int cgs_geo_geodetic_to_ecef (cgs_geodetic_t g, cgs_ecef_t *ret_x);
/* ECEF to geodetic (WGS84); 0 or -EINVAL. */
int cgs_geo_ecef_to_geodetic (cgs_ecef_t x, cgs_geodetic_t *ret_g);

/* MGRS string of a point, precision digits per axis 0..5 (5 = 1 m); 0, -EINVAL
 * (bad input) or -ENOBUFS (buffer too small). */
int cgs_geo_to_mgrs (cgs_geodetic_t g, int digits, char *buf, size_t size);
/* Centre of an MGRS square (spaces allowed, any case) as geodetic with height
 * 0; *ret_precision_m (may be NULL) is the square's side. 0 or -EINVAL. */
int cgs_geo_from_mgrs (const char *mgrs, cgs_geodetic_t *ret_g, double *ret_precision_m);

/* DIS Euler angles of an entity at geodetic position `at` whose attitude is
 * heading (degrees clockwise from true north), pitch (nose up positive) and
 * roll (right wing down positive) in the local tangent plane there. 0 or -EINVAL. */
int cgs_geo_dis_euler_from_hpr (cgs_geodetic_t at, double heading_deg, double pitch_deg,
                                double roll_deg, cgs_dis_euler_t *ret_e);
/* The inverse of cgs_geo_dis_euler_from_hpr; heading in [0, 360). 0 or -EINVAL. */
int cgs_geo_hpr_from_dis_euler (cgs_geodetic_t at, cgs_dis_euler_t e, double *ret_heading_deg,
                                double *ret_pitch_deg, double *ret_roll_deg);
/* DIS Euler angles of an attitude given in the exercise's local frame (heading
 * from the frame's north axis). Exact anywhere, since the frame's axes are a
 * fixed rotation of ECEF. */
void cgs_geo_dis_euler_from_local (const cgs_geo_t *self, double heading_deg, double pitch_deg,
                                   double roll_deg, cgs_dis_euler_t *ret_e);
/* The inverse of cgs_geo_dis_euler_from_local; heading in [0, 360). */
void cgs_geo_local_from_dis_euler (const cgs_geo_t *self, cgs_dis_euler_t e,
                                   double *ret_heading_deg, double *ret_pitch_deg,
                                   double *ret_roll_deg);

#ifdef __cplusplus
}
#endif
#endif
