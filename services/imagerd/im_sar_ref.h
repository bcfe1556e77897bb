/* im_sar_ref — the reference SAR the fast path (im_sar) is held to: the
 * phase history of point targets for a spotlight collection, then the image
 * formed from it by backprojection. Pulses from a straight, steady aperture
 * centred on the collection's radar position, spanning the integration
 * angle; frequencies across the bandwidth; each sample
 * s(f, t) = Σ √σ_k · exp(−j4πf·R_k(t)/c), R_k(t) the range from the
 * antenna to target k, each moving at its velocity through the aperture.
 * The image at a point p is Σ W(f)·W(t)·s(f, t)·exp(+j4πf·R_p(t)/c), the
 * same window as the fast path in frequency and along the aperture, scaled
 * so that ∫|h|² dA = 1 on the chip's plane (the fast path's calibration).
 * Slow: pulses × frequencies per pixel. For tests. Pure. */
#ifndef IM_SAR_REF_H
#define IM_SAR_REF_H

#include "im_sar.h"

typedef struct im_sar_ref im_sar_ref_t;

/* Simulate the collection of the targets. extent_m: how far from the centre
 * anything (target or pixel) lies; it sets the sampling (no ambiguity
 * within twice that). NULL with the reason in err (bad parameters or
 * geometry, more than 4096 samples a side, out of memory). */
im_sar_ref_t *im_sar_ref_new (const im_sar_params_t *p, const im_sar_geom_t *g,
                              const im_sar_point_t *pts, size_t n, double extent_m, char *err,
                              size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void im_sar_ref_destroy (im_sar_ref_t **self_p);

/* Pulses and frequencies sampled. */
int im_sar_ref_pulses (const im_sar_ref_t *self);
int im_sar_ref_freqs (const im_sar_ref_t *self);
/* The phase history's sample (pulse i, frequency j), unweighted: re, im. */
void im_sar_ref_sample (const im_sar_ref_t *self, int i, int j, double *ret_re, double *ret_im);
/* The time of pulse i from the aperture's centre, and frequency j, Hz. */
double im_sar_ref_time (const im_sar_ref_t *self, int i);
double im_sar_ref_freq (const im_sar_ref_t *self, int j);

/* Backproject onto the points pts (on the plane of chip `plane`, whose
 * geometry sets the area scale): re, im per point into ret_re_im. */
void im_sar_ref_backproject (const im_sar_ref_t *self, const im_sar_chip_t *plane,
                             const cgs_enu_t *pts, size_t n, double *ret_re_im);

#endif
