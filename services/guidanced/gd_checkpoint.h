/* gd_checkpoint — the checkpoint of one UAV's intercept: everything but its
 * parameters and terrain, as a cgs_ckpt frame ("GDIC"). Pure: no files, no
 * logging. */
#ifndef GD_CHECKPOINT_H
#define GD_CHECKPOINT_H

#include "gd_intercept.h"

#include <stddef.h>
#include <stdint.h>

/* The intercept's checkpoint, in a new malloc'd buffer; 0 or -ENOMEM. */
int gd_checkpoint_save (const gd_intercept_t *ic, uint8_t **ret_buf, size_t *ret_len);
/* Restore a checkpoint into an intercept (its parameters and terrain kept;
 * the footprint follows from the UAV's state). 0, or one of cgs_ckpt's
 * errors with the reason in err (-EINVAL also for values out of range);
 * the intercept is then unchanged. */
int gd_checkpoint_restore (gd_intercept_t *ic, const uint8_t *buf, size_t len, char *err,
                           size_t errlen);

#endif
