/* cgs_state — small files in the state directory, written atomically (a
 * temporary file, fsync, rename, fsync of the folder) so a crash leaves the
 * old contents or the new, never a torn file. Pure of logging. */
#ifndef CGS_STATE_H
#define CGS_STATE_H

#include <stddef.h>

/* Write data to path atomically; creates missing folders; 0 or -errno. */
int cgs_state_write (const char *path, const void *data, size_t len);
/* Read a whole file into a new malloc'd buffer (NUL-terminated past len);
 * 0, -ENOENT when absent, -EFBIG over max bytes, or -errno. */
int cgs_state_read (const char *path, size_t max, void **ret_data, size_t *ret_len);
/* mkdir -p; 0 or -errno. */
int cgs_state_mkdir (const char *dir);
/* Join dir and name into buf ("dir/name"); 0 or -ENAMETOOLONG. */
int cgs_state_path (char *buf, size_t size, const char *dir, const char *name);

#endif
