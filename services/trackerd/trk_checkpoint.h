/* trk_checkpoint — trackerd's checkpoint of its tracker: every track and the
 * id counter, as a cgs_ckpt frame ("TRKS"), so track ids outlive a restart.
 * Pure: no files, no logging. */
#ifndef TRK_CHECKPOINT_H
#define TRK_CHECKPOINT_H

#include "trk_tracker.h"

#include <stddef.h>
#include <stdint.h>

/* A checkpoint of every track and the id counter, in a new malloc'd
 * buffer; 0 or -ENOMEM. */
int trk_checkpoint_save (const trk_tracker_t *trk, uint8_t **ret_buf, size_t *ret_len);
/* Replace the tracker's tracks with a checkpoint's (history beyond
 * history_scans is trimmed to the newest). 0, or one of cgs_ckpt's errors
 * with the reason in err (-EINVAL also for tracks or ids that are not
 * consistent); the tracker is then unchanged. */
int trk_checkpoint_restore (trk_tracker_t *trk, const uint8_t *buf, size_t len, char *err,
                            size_t errlen);
/* The next track id a checkpoint of this format names, even when its
 * tracks are damaged or it is cut short (its checksum is not checked: the
 * id only keeps ids from being given twice); 0, or -EINVAL, -EPROTO,
 * -ENOTSUP when its header is not one of this format. */
int trk_checkpoint_next_id (const uint8_t *buf, size_t len, uint32_t *ret_id);

#endif
