/* im_sar — the imaging sensor's SAR mode: a spotlight SAR chip made by
 * image-domain synthesis. The scene (terrain facets with σ0 by incidence
 * and material, woods as volume at canopy height, vehicles as groups of
 * bright points) becomes point scatterers, each placed where its range
 * history puts it (its slant range and Doppler at the aperture's centre:
 * layover, foreshortening, and a moving target's cross-range shift
 * Δx = R·v_r/V all follow), shadowed where terrain, canopy or a vehicle
 * hides it from the radar, with a random phase per look (speckle). They are
 * spread onto an oversampled grid (a non-uniform FFT's gridding), and the
 * point-spread function is applied by FFT: the window over the spectral
 * support that the bandwidth and the integration angle give, zero outside.
 * So a point gives exactly a windowed sinc with the configured
 * resolutions. Then |.|², looks averaged, dB, 8-bit grey. im_sar_ref.h is
 * the slow reference (phase history and backprojection) the tests hold it
 * to.
 *
 * Chip orientation: up is far (away from the radar), as SAR analysts show
 * it; right is to the right of the line of sight. A moving target's
 * cross-range shift is therefore left/right. Geometry `ground` (default):
 * the pixels lie on the horizontal plane through the chip's centre, rows
 * along ground range; `slant`: on the slant plane (the line of sight and
 * the platform's velocity), rows along slant range.
 *
 * Pure: no logging, no globals. FFTW's planner is not thread-safe:
 * create and destroy objects from one thread (imagerd has one). */

/* The parameters come first, on their own: im_params.h includes this header
 * with IM_SAR_PARAMS_ONLY defined, since the rest needs im_render.h, which
 * needs im_params.h. */
#ifndef IM_SAR_PARAMS_DEFINED
#define IM_SAR_PARAMS_DEFINED

#include "cgs_config.h"

#include <stdbool.h>
#include <stddef.h>

typedef enum {
    IM_SAR_WINDOW_RECT = 0, // no weighting: 3 dB width 0.886 (× c/2B, λ/2Δθ), PSLR −13.26 dB
    IM_SAR_WINDOW_HAMMING = 1, // 0.54 + 0.46 cos: 3 dB width 1.30, PSLR −42.7 dB
    IM_SAR_WINDOW_TAYLOR = 2,  // Taylor, n̄ = 4, −35 dB: 3 dB width 1.18, PSLR −35.2 dB
} im_sar_window_t;

typedef enum {
    IM_SAR_GROUND = 0, // pixels on the horizontal plane through the centre
    IM_SAR_SLANT = 1,  // pixels on the slant plane
} im_sar_geometry_t;

/* [sar] in imager.ini. Defaults: X band, about 1 m before weighting.
 *  - bandwidth 133 MHz: the rectangular window's 3 dB slant-range width
 *    0.886·c/(2B) is 0.999 m;
 *  - integration angle 0.79°: 0.886·λ/(2Δθ) at 9.6 GHz is 1.003 m;
 *  - Taylor (n̄ 4, −35 dB) rather than Hamming: 3 dB widths 1.18·c/(2B)
 *    (1.33 m here) rather than 1.30·c/(2B) (1.47 m), at sidelobes (−35 dB)
 *    below all but the brightest targets on a 40 dB display; the usual
 *    choice of SAR processors;
 *  - 1 look: the looks here are independent speckle draws at full
 *    resolution, which a real radar pays for with resolution or bandwidth
 *    that these parameters do not charge; one look keeps the resolution
 *    honest;
 *  - 256 m in 256 pixels: 1 m pixels, about one a resolution cell, the
 *    complex image sampled at its Nyquist rate (1.13 m). */
#define IM_SAR_WIDEN_MAX 64.0 // the most a chip is widened (im_sar_geom_t.widen)

typedef struct {
    double fc_hz;           // centre frequency
    double bandwidth_hz;    // chirp bandwidth: slant range resolution 0.886·c/(2B) (rect)
    double integration_deg; // angle the line of sight turns through: 0.886·λ/(2Δθ) (rect)
    im_sar_window_t window; // weighting in frequency and angle
    int looks;              // independent speckle draws averaged (1..16)
    double scene_m;         // chip side on its plane, metres
    int size_px;            // chip side, pixels (64..2048)
    double max_widen;       // imagerd widens a chip up to this many times to hold the
                            // designated target's return (im_sar_geom_t.widen; 1: never)
    bool gmti;              // a moving-target channel measures the designated target's
    double gmti_sigma_mps;  // radial velocity in each chip that holds it, with this σ
    im_sar_geometry_t geometry;
    bool speckle;            // random phase per scatterer (false: a smooth, speckle-free image)
    double ground_gamma_db;  // bare ground γ: σ0 = γ·cos(incidence)
    double woods_gamma_db;   // woods (volume at canopy height) γ
    double vehicle_rcs_m2;   // a tracked vehicle's total RCS (its points' sum); wheeled 0.6×
    double nesz_db;          // noise-equivalent σ0 (thermal noise floor; shadows sit on it)
    double display_max_db;   // σ0 shown white
    double dynamic_range_db; // display range: black at display_max_db − this
} im_sar_params_t;

/* The documented defaults (deploy/params/imager.ini). */
void im_sar_params_defaults (im_sar_params_t *p);
/* Check a set built in code: 0, or -EINVAL with "[sar] key: expected ..., got ..." in err. */
int im_sar_params_check (const im_sar_params_t *p, char *err, size_t errlen);
/* Read the [sar] section of a loaded file over *p (keys absent keep their
 * value): 0, or -EINVAL with "file:line: [sar] key: ..." in err (fields read
 * before the bad key may be written: callers read into a copy). */
int im_sar_params_read (cgs_config_t *cfg, im_sar_params_t *p, char *err, size_t errlen);

#endif

#ifndef IM_SAR_PARAMS_ONLY
#ifndef IM_SAR_H
#define IM_SAR_H

#include "cgs_geo.h"
#include "cgs_terrain.h"
#include "im_render.h"

#include <stdint.h>

typedef struct im_sar im_sar_t;

/* The collection: where the radar is, and where it looks. */
typedef struct {
    cgs_enu_t radar;     // antenna at the aperture's centre, local frame, metres
    cgs_enu_t radar_vel; // platform velocity, m/s: the synthetic aperture lies along it
    cgs_enu_t center;    // chip centre, on the ground
    // Widen the chip this many times (1..IM_SAR_WIDEN_MAX; 0 or 1: as
    // configured): scene and resolutions w times the configured, on the same
    // pixel count, the integration angle w times smaller; the same cost.
    double widen;
} im_sar_geom_t;

/* A point scatterer: a corner reflector, a calibration or test target. */
typedef struct {
    cgs_enu_t position; // at the aperture's centre
    cgs_enu_t velocity; // m/s (zero: static)
    double rcs_m2;
} im_sar_point_t;

/* What is imaged. */
typedef struct {
    const cgs_terrain_t *terrain; // NULL: flat open ground at height 0
    const im_entity_t *ents;      // ground entities (kind AIR is not imaged)
    size_t nents;
    const im_sar_point_t *points; // extra point scatterers (may be NULL)
    size_t npoints;
    bool no_clutter; // entities and points only: no ground returns and no noise
} im_sar_scene_t;

/* A chip's geometry: enough to map ground points to its pixels and back.
 * Pixel (x, y): x to the right, y down from the far edge, pixel i's centre
 * at i + 0.5. */
typedef struct {
    im_sar_geometry_t geometry;
    int size_px;
    double pixel_m;                     // pixel spacing on the chip's plane
    cgs_enu_t radar, radar_vel, center; // as collected
    cgs_enu_t los;                      // unit, radar to centre
    cgs_enu_t range_dir;  // unit, up the chip (far): ground range, or the line of sight (slant)
    cgs_enu_t cross_dir;  // unit, chip right: horizontal (ground), in the slant plane (slant)
    double slant_range_m; // radar to centre
    double grazing_deg;   // at the centre, above the horizontal
    double squint_deg;    // line of sight from broadside, positive ahead
    double aperture_s;    // time to turn through the integration angle
    double widen;         // scene and resolutions this many times the configured
    double range_res_m;   // 3 dB width along range_dir on the chip's plane, window included
    double cross_res_m;   // 3 dB width along cross_dir
    // The corners on the ground (at the centre's height): near-left, far-left,
    // far-right, near-right, as seen from the radar.
    cgs_enu_t corners[4];
    size_t scatterers; // per look
} im_sar_chip_t;

/* A SAR imager for the parameters; its FFTW plans are made here (sizes
 * follow from the parameters). NULL with the reason in err (bad parameters,
 * out of memory). */
im_sar_t *im_sar_new (const im_sar_params_t *p, uint64_t seed, char *err, size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void im_sar_destroy (im_sar_t **self_p);

/* Image the scene: the chip's pixels (im_sar_intensity, im_sar_grey) and,
 * in *ret_chip (may be NULL), its geometry. Each call draws new speckle.
 * 0; -EINVAL (a value not finite, the platform not moving, entities or
 * points counted but not given); -EDOM (the grazing angle outside 1°..85°,
 * the range under 100 m, the line of sight within 11.5° of the track, or
 * so squinted (past about 80° at 30° grazing) that the slant plane's
 * cross-range has almost no part across the look on the ground); -ENOMEM.
 * On error the previous chip stays. */
int im_sar_image (im_sar_t *self, const im_sar_geom_t *g, const im_sar_scene_t *scene,
                  im_sar_chip_t *ret_chip);

/* The geometry a chip of g would have (no image is made: cheap), with no
 * scatterers: for aiming the next chip. 0, or im_sar_image's -EINVAL or
 * -EDOM for a collection it refuses by its geometry. */
int im_sar_plan (const im_sar_t *self, const im_sar_geom_t *g, im_sar_chip_t *ret_chip);

/* The parameters it was made with. */
const im_sar_params_t *im_sar_params (const im_sar_t *self);
/* The last chip's geometry; NULL before the first. */
const im_sar_chip_t *im_sar_chip (const im_sar_t *self);
/* The chip's side, pixels. */
int im_sar_size (const im_sar_t *self);
/* The last chip: size × size intensities in σ0 units (a flat field of σ0
 * averages σ0 in ground geometry, σ0/cos ψ in slant; a point of σ m²
 * peaks near σ/(range width · cross width)), row 0 the far edge. */
const double *im_sar_intensity (const im_sar_t *self);
/* The same as display grey levels (dB between the display's black and white). */
const uint8_t *im_sar_grey (const im_sar_t *self);
/* The last look's complex image (re, im per pixel, √σ0 units), when the
 * pixels sample it (pixel no coarser than the Nyquist spacing); else NULL. */
const double *im_sar_slc (const im_sar_t *self);

/* The chip in an RGBA frame (width × height × 4, top row first): grey,
 * scaled to fit and centred, black bars about it (letterbox). */
void im_sar_to_rgba (const im_sar_t *self, uint8_t *rgba, int width, int height);

/* Where a scatterer at p moving at vel (zero: static) appears in the chip
 * (its slant range and Doppler: layover and the moving-target shift
 * included): true with chip pixel coordinates when it falls in the chip. */
bool im_sar_chip_to_px (const im_sar_chip_t *c, cgs_enu_t p, cgs_enu_t vel, double *ret_x,
                        double *ret_y);
/* The ground point (on terrain; NULL: flat at height 0) where the return of
 * a scatterer at p moving at vel appears, in the chip or beyond it: p
 * itself for a static point on the ground; a mover's place shifted along
 * cross range by R·v_r/V. False when no ground point has its range and
 * Doppler. */
bool im_sar_apparent (const im_sar_chip_t *c, cgs_enu_t p, cgs_enu_t vel,
                      const cgs_terrain_t *terrain, cgs_enu_t *ret);
/* The same in a width × height frame made by im_sar_to_rgba. */
bool im_sar_ground_to_px (const im_sar_chip_t *c, int width, int height, cgs_enu_t p, cgs_enu_t vel,
                          double *ret_x, double *ret_y);
/* The point of the chip's plane (ground or slant) at chip pixel (x, y). */
void im_sar_chip_px_to_plane (const im_sar_chip_t *c, double x, double y, cgs_enu_t *ret);
/* The ground point (on the terrain; NULL: flat ground at height 0) whose
 * return falls at chip pixel (x, y): true, or false when no ground point
 * has that range and Doppler. */
bool im_sar_chip_px_to_ground (const im_sar_chip_t *c, double x, double y,
                               const cgs_terrain_t *terrain, cgs_enu_t *ret);

/* The window's weight at x in [−0.5, 0.5] across its support (0 outside). */
double im_sar_window (im_sar_window_t w, double x);
/* The window's 3 dB width of the response, in units of 1/support (rect 0.886). */
double im_sar_window_width (im_sar_window_t w);

#endif
#endif
