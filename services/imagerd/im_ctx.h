/* im_ctx — the one place that knows how an OpenGL 3.3 core context is made
 * without a window. Two backends, one chosen at build time (make RENDER=...):
 *   osmesa  Mesa's off-screen library (libOSMesa), as the design names it;
 *   egl     EGL on Mesa's surfaceless platform (libEGL + libOpenGL), for
 *           Mesa 25.1 and later, which removed OSMesa.
 * Both render in software (llvmpipe, or softpipe). The renderer draws into
 * its own framebuffer object, so neither backend's window buffer is read. */
#ifndef IM_CTX_H
#define IM_CTX_H

#include <stddef.h>

typedef struct im_ctx im_ctx_t;

/* "osmesa" or "egl": the backend this program was built with. */
const char *im_ctx_backend (void);
/* Make a context for images up to width × height and make it current on
 * the calling thread. NULL with the reason in err: a refused GALLIUM_DRIVER
 * (im_ctx_check_driver), no display, no OpenGL 3.3 core. */
im_ctx_t *im_ctx_new (int width, int height, char *err, size_t errlen);
void im_ctx_destroy (im_ctx_t **self_p);

/* Mesa picks its Gallium driver from GALLIUM_DRIVER; one that is not a
 * software rasterizer crashes the library (zink, for one, dereferences a
 * Vulkan device that is not there). 0 when value (may be NULL or empty) is
 * unset, llvmpipe or softpipe; else -EINVAL with the reason in err. */
int im_ctx_check_driver (const char *value, char *err, size_t errlen);

#endif
