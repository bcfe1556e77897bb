/* im_ctx — what both backends share (see im_ctx.h). */
#include "im_ctx.h"
#include "cgs_util.h"

#include <errno.h>
#include <string.h>

int im_ctx_check_driver (const char *value, char *err, size_t errlen)
{
    if (!value || !*value || strcmp (value, "llvmpipe") == 0 || strcmp (value, "softpipe") == 0)
        return 0;
    cgs_errf (err, errlen,
              "GALLIUM_DRIVER=%s is refused: imagerd renders in software and only llvmpipe or "
              "softpipe work without a GPU (others, zink among them, crash Mesa); unset it to "
              "use llvmpipe",
              value);
    return -EINVAL;
}
