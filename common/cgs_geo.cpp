/* cgs_geo — geodesy for mscgs: a C shim over GeographicLib for the exercise's
 * local east-north-up frame, WGS84 geodetic and geocentric coordinates, MGRS
 * and DIS Euler angles. The only C++ in the tree; no GeographicLib exception
 * leaves this file (each becomes -EINVAL). */
#include "cgs_geo.h"

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/MGRS.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include <cassert>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>
#include <string>

using GeographicLib::Geocentric;
using GeographicLib::LocalCartesian;
using GeographicLib::Math;
using GeographicLib::MGRS;
using GeographicLib::UTMUPS;

namespace
{

// A 3-vector; ECEF or local components depending on use.
struct vec3 {
    double v[3];
};

// An attitude as three body axes (x forward, y right, z down), each given
// in the components of some reference frame.
struct axes3 {
    vec3 x, y, z;
};

// A local tangent frame: its north, east and down unit vectors in ECEF.
struct ned_frame {
    vec3 n, e, d;
};

// Below this horizontal length of the body x axis (unit vector), the attitude
// is taken to be at gimbal lock (pitch or theta of +-90 degrees).
const double s_gimbal_eps = 1e-12;

bool s_finite3 (double a, double b, double c)
{
    return std::isfinite (a) && std::isfinite (b) && std::isfinite (c);
}

bool s_geodetic_ok (const cgs_geodetic_t &g)
{
    return s_finite3 (g.lat_deg, g.lon_deg, g.height_m) && g.lat_deg >= -90.0 && g.lat_deg <= 90.0;
}

double s_dot (const vec3 &a, const vec3 &b)
{
    return a.v[0] * b.v[0] + a.v[1] * b.v[1] + a.v[2] * b.v[2];
}

// North, east and down unit vectors in ECEF at geodetic latitude/longitude.
ned_frame s_ned_at (double lat_deg, double lon_deg)
{
    double sphi, cphi, slam, clam;
    Math::sincosd (lat_deg, sphi, cphi);
    Math::sincosd (lon_deg, slam, clam);
    ned_frame f;
    f.n = {{-sphi * clam, -sphi * slam, cphi}};
    f.e = {{-slam, clam, 0.0}};
    f.d = {{-cphi * clam, -cphi * slam, -sphi}};
    return f;
}

// Body axes from a ZYX Euler sequence (yaw about z, then pitch about y, then
// roll about x) given as sine/cosine pairs, in the components of the frame the
// angles refer to: the rows of Rx(roll) * Ry(pitch) * Rz(yaw).
axes3 s_axes_from_sincos (double sps, double cps, double sth, double cth, double sph, double cph)
{
    axes3 b;
    b.x = {{cth * cps, cth * sps, -sth}};
    b.y = {{sph * sth * cps - cph * sps, sph * sth * sps + cph * cps, sph * cth}};
    b.z = {{cph * sth * cps + sph * sps, cph * sth * sps - sph * cps, cph * cth}};
    return b;
}

// The inverse of s_axes_from_sincos, in radians: yaw and roll in [-pi, pi], pitch in
// [-pi/2, pi/2]. At gimbal lock roll is set to 0 and yaw carries the rest.
void s_euler_from_axes (const axes3 &b, double *yaw_rad, double *pitch_rad, double *roll_rad)
{
    double horiz = std::hypot (b.x.v[0], b.x.v[1]);
    *pitch_rad = std::atan2 (-b.x.v[2], horiz);
    if (horiz < s_gimbal_eps) {
        // With roll 0 the y axis is (-sin yaw, cos yaw, 0).
        *roll_rad = 0.0;
        *yaw_rad = std::atan2 (-b.y.v[0], b.y.v[1]);
    } else {
        *yaw_rad = std::atan2 (b.x.v[1], b.x.v[0]);
        *roll_rad = std::atan2 (b.y.v[2], b.z.v[2]);
    }
}

// A vector given in a NED frame's components, expressed in ECEF.
vec3 s_ned_to_ecef (const ned_frame &f, const vec3 &a)
{
    vec3 r;
    for (int i = 0; i < 3; i++)
        r.v[i] = a.v[0] * f.n.v[i] + a.v[1] * f.e.v[i] + a.v[2] * f.d.v[i];
    return r;
}

// An ECEF vector expressed in a NED frame's components.
vec3 s_ecef_to_ned (const ned_frame &f, const vec3 &a)
{
    return {{s_dot (a, f.n), s_dot (a, f.e), s_dot (a, f.d)}};
}

// Heading, pitch, roll (degrees) in frame f to DIS Euler angles.
cgs_dis_euler_t s_euler_from_hpr (const ned_frame &f, double heading_deg, double pitch_deg,
                                  double roll_deg)
{
    double sps, cps, sth, cth, sph, cph; // exact for multiples of 90 degrees
    Math::sincosd (heading_deg, sps, cps);
    Math::sincosd (pitch_deg, sth, cth);
    Math::sincosd (roll_deg, sph, cph);
    axes3 ned = s_axes_from_sincos (sps, cps, sth, cth, sph, cph);
    axes3 ecef = {s_ned_to_ecef (f, ned.x), s_ned_to_ecef (f, ned.y), s_ned_to_ecef (f, ned.z)};
    cgs_dis_euler_t e;
    s_euler_from_axes (ecef, &e.psi_rad, &e.theta_rad, &e.phi_rad);
    return e;
}

// DIS Euler angles to heading in [0, 360), pitch, roll (degrees) in frame f.
void s_hpr_from_euler (const ned_frame &f, const cgs_dis_euler_t &e, double *heading_deg,
                       double *pitch_deg, double *roll_deg)
{
    axes3 ecef =
        s_axes_from_sincos (std::sin (e.psi_rad), std::cos (e.psi_rad), std::sin (e.theta_rad),
                            std::cos (e.theta_rad), std::sin (e.phi_rad), std::cos (e.phi_rad));
    axes3 ned = {s_ecef_to_ned (f, ecef.x), s_ecef_to_ned (f, ecef.y), s_ecef_to_ned (f, ecef.z)};
    double yaw, pitch, roll;
    s_euler_from_axes (ned, &yaw, &pitch, &roll);
    double h = std::fmod (yaw / Math::degree (), 360.0);
    if (h < 0.0)
        h += 360.0;
    if (h >= 360.0) // -tiny + 360 rounds to 360
        h = 0.0;
    *heading_deg = h;
    *pitch_deg = pitch / Math::degree ();
    *roll_deg = roll / Math::degree ();
}

} // namespace

struct cgs_geo {
    cgs_geodetic_t origin; // the frame's origin
    LocalCartesian proj;   // GeographicLib's ENU projection about the origin
    double origin_ecef[3]; // the origin in ECEF, metres
    double rot[9];         // ENU to ECEF, row major: columns are east, north, up in ECEF
    ned_frame ned;         // the frame's north, east, down axes in ECEF

    cgs_geo (double lat_deg, double lon_deg, double height_m)
        : origin{lat_deg, lon_deg, height_m}, proj (lat_deg, lon_deg, height_m)
    {
        Geocentric::WGS84 ().Forward (lat_deg, lon_deg, height_m, origin_ecef[0], origin_ecef[1],
                                      origin_ecef[2]);
        ned = s_ned_at (lat_deg, lon_deg);
        for (int i = 0; i < 3; i++) {
            rot[3 * i + 0] = ned.e.v[i];
            rot[3 * i + 1] = ned.n.v[i];
            rot[3 * i + 2] = -ned.d.v[i];
        }
    }
};

extern "C" {

cgs_geo_t *cgs_geo_new (double lat_deg, double lon_deg, double height_m)
{
    cgs_geodetic_t g = {lat_deg, lon_deg, height_m};
    if (!s_geodetic_ok (g))
        return NULL;
    try {
        return new (std::nothrow) cgs_geo (lat_deg, lon_deg, height_m);
    } catch (...) {
        return NULL;
    }
}

void cgs_geo_destroy (cgs_geo_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    delete *self_p;
    *self_p = NULL;
}

cgs_geodetic_t cgs_geo_origin (const cgs_geo_t *self)
{
    assert (self);
    return self->origin;
}

int cgs_geo_enu_to_geodetic (const cgs_geo_t *self, cgs_enu_t p, cgs_geodetic_t *ret_g)
{
    assert (self && ret_g);
    if (!s_finite3 (p.e_m, p.n_m, p.u_m))
        return -EINVAL;
    try {
        cgs_geodetic_t g;
        self->proj.Reverse (p.e_m, p.n_m, p.u_m, g.lat_deg, g.lon_deg, g.height_m);
        if (!s_geodetic_ok (g))
            return -EINVAL;
        *ret_g = g;
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_geodetic_to_enu (const cgs_geo_t *self, cgs_geodetic_t g, cgs_enu_t *ret_p)
{
    assert (self && ret_p);
    if (!s_geodetic_ok (g))
        return -EINVAL;
    try {
        cgs_enu_t p;
        self->proj.Forward (g.lat_deg, g.lon_deg, g.height_m, p.e_m, p.n_m, p.u_m);
        if (!s_finite3 (p.e_m, p.n_m, p.u_m))
            return -EINVAL;
        *ret_p = p;
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_enu_to_ecef (const cgs_geo_t *self, cgs_enu_t p, cgs_ecef_t *ret_x)
{
    assert (self && ret_x);
    if (!s_finite3 (p.e_m, p.n_m, p.u_m))
        return -EINVAL;
    cgs_ecef_t v;
    cgs_geo_enu_vector_to_ecef (self, p, &v);
    cgs_ecef_t x = {self->origin_ecef[0] + v.x_m, self->origin_ecef[1] + v.y_m,
                    self->origin_ecef[2] + v.z_m};
    if (!s_finite3 (x.x_m, x.y_m, x.z_m))
        return -EINVAL;
    *ret_x = x;
    return 0;
}

int cgs_geo_ecef_to_enu (const cgs_geo_t *self, cgs_ecef_t x, cgs_enu_t *ret_p)
{
    assert (self && ret_p);
    if (!s_finite3 (x.x_m, x.y_m, x.z_m))
        return -EINVAL;
    cgs_ecef_t d = {x.x_m - self->origin_ecef[0], x.y_m - self->origin_ecef[1],
                    x.z_m - self->origin_ecef[2]};
    cgs_enu_t p;
    cgs_geo_ecef_vector_to_enu (self, d, &p);
    if (!s_finite3 (p.e_m, p.n_m, p.u_m))
        return -EINVAL;
    *ret_p = p;
    return 0;
}

void cgs_geo_enu_vector_to_ecef (const cgs_geo_t *self, cgs_enu_t v, cgs_ecef_t *ret_v)
{
    assert (self && ret_v);
    const double *r = self->rot;
    ret_v->x_m = r[0] * v.e_m + r[1] * v.n_m + r[2] * v.u_m;
    ret_v->y_m = r[3] * v.e_m + r[4] * v.n_m + r[5] * v.u_m;
    ret_v->z_m = r[6] * v.e_m + r[7] * v.n_m + r[8] * v.u_m;
}

void cgs_geo_ecef_vector_to_enu (const cgs_geo_t *self, cgs_ecef_t v, cgs_enu_t *ret_v)
{
    assert (self && ret_v);
    const double *r = self->rot;
    ret_v->e_m = r[0] * v.x_m + r[3] * v.y_m + r[6] * v.z_m;
    ret_v->n_m = r[1] * v.x_m + r[4] * v.y_m + r[7] * v.z_m;
    ret_v->u_m = r[2] * v.x_m + r[5] * v.y_m + r[8] * v.z_m;
}

int cgs_geo_geodetic_to_ecef (cgs_geodetic_t g, cgs_ecef_t *ret_x)
{
    assert (ret_x);
    if (!s_geodetic_ok (g))
        return -EINVAL;
    try {
        cgs_ecef_t x;
        Geocentric::WGS84 ().Forward (g.lat_deg, g.lon_deg, g.height_m, x.x_m, x.y_m, x.z_m);
        if (!s_finite3 (x.x_m, x.y_m, x.z_m))
            return -EINVAL;
        *ret_x = x;
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_ecef_to_geodetic (cgs_ecef_t x, cgs_geodetic_t *ret_g)
{
    assert (ret_g);
    if (!s_finite3 (x.x_m, x.y_m, x.z_m))
        return -EINVAL;
    try {
        cgs_geodetic_t g;
        Geocentric::WGS84 ().Reverse (x.x_m, x.y_m, x.z_m, g.lat_deg, g.lon_deg, g.height_m);
        if (!s_geodetic_ok (g))
            return -EINVAL;
        *ret_g = g;
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_to_mgrs (cgs_geodetic_t g, int digits, char *buf, size_t size)
{
    if (!buf || digits < 0 || digits > 5 || !s_geodetic_ok (g))
        return -EINVAL;
    try {
        int zone;
        bool northp;
        double x, y;
        UTMUPS::Forward (g.lat_deg, g.lon_deg, zone, northp, x, y);
        std::string mgrs;
        MGRS::Forward (zone, northp, x, y, g.lat_deg, digits, mgrs);
        if (mgrs.empty () || mgrs.compare (0, 3, "INV") == 0)
            return -EINVAL;
        if (mgrs.size () + 1 > size)
            return -ENOBUFS;
        std::memcpy (buf, mgrs.c_str (), mgrs.size () + 1);
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_from_mgrs (const char *mgrs, cgs_geodetic_t *ret_g, double *ret_precision_m)
{
    if (!mgrs || !ret_g)
        return -EINVAL;
    try {
        std::string s;
        for (const char *c = mgrs; *c; c++) {
            unsigned char u = (unsigned char)*c;
            if (!std::isspace (u))
                s.push_back ((char)std::toupper (u));
        }
        if (s.empty ())
            return -EINVAL;
        int zone, prec;
        bool northp;
        double x, y;
        MGRS::Reverse (s, zone, northp, x, y, prec, true);
        // prec -1: a grid zone designation alone (no square); -2: "INVALID".
        if (prec < 0 || zone == UTMUPS::INVALID)
            return -EINVAL;
        cgs_geodetic_t g = {0.0, 0.0, 0.0};
        UTMUPS::Reverse (zone, northp, x, y, g.lat_deg, g.lon_deg);
        if (!s_geodetic_ok (g))
            return -EINVAL;
        *ret_g = g;
        if (ret_precision_m)
            *ret_precision_m = std::pow (10.0, 5 - prec);
        return 0;
    } catch (...) {
        return -EINVAL;
    }
}

int cgs_geo_dis_euler_from_hpr (cgs_geodetic_t at, double heading_deg, double pitch_deg,
                                double roll_deg, cgs_dis_euler_t *ret_e)
{
    assert (ret_e);
    if (!s_geodetic_ok (at) || !s_finite3 (heading_deg, pitch_deg, roll_deg))
        return -EINVAL;
    *ret_e = s_euler_from_hpr (s_ned_at (at.lat_deg, at.lon_deg), heading_deg, pitch_deg, roll_deg);
    return 0;
}

int cgs_geo_hpr_from_dis_euler (cgs_geodetic_t at, cgs_dis_euler_t e, double *ret_heading_deg,
                                double *ret_pitch_deg, double *ret_roll_deg)
{
    assert (ret_heading_deg && ret_pitch_deg && ret_roll_deg);
    if (!s_geodetic_ok (at) || !s_finite3 (e.psi_rad, e.theta_rad, e.phi_rad))
        return -EINVAL;
    s_hpr_from_euler (s_ned_at (at.lat_deg, at.lon_deg), e, ret_heading_deg, ret_pitch_deg,
                      ret_roll_deg);
    return 0;
}

void cgs_geo_dis_euler_from_local (const cgs_geo_t *self, double heading_deg, double pitch_deg,
                                   double roll_deg, cgs_dis_euler_t *ret_e)
{
    assert (self && ret_e);
    *ret_e = s_euler_from_hpr (self->ned, heading_deg, pitch_deg, roll_deg);
}

void cgs_geo_local_from_dis_euler (const cgs_geo_t *self, cgs_dis_euler_t e,
                                   double *ret_heading_deg, double *ret_pitch_deg,
                                   double *ret_roll_deg)
{
    assert (self && ret_heading_deg && ret_pitch_deg && ret_roll_deg);
    s_hpr_from_euler (self->ned, e, ret_heading_deg, ret_pitch_deg, ret_roll_deg);
}

} // extern "C"
