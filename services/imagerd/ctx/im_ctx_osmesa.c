/* im_ctx on OSMesa (see im_ctx.h). */
#include "im_ctx.h"
#include "cgs_util.h"

#include <GL/osmesa.h>
#include <errno.h>
#include <stdlib.h>

struct im_ctx {
    OSMesaContext ctx;
    unsigned char *buffer; // OSMesa's own colour buffer (the renderer draws elsewhere)
};

const char *im_ctx_backend (void)
{
    return "osmesa";
}

im_ctx_t *im_ctx_new (int width, int height, char *err, size_t errlen)
{
    if (im_ctx_check_driver (getenv ("GALLIUM_DRIVER"), err, errlen) < 0)
        return NULL;
    if (width < 1 || height < 1) {
        cgs_errf (err, errlen, "osmesa: a %d x %d image is not possible", width, height);
        return NULL;
    }
    im_ctx_t *self = calloc (1, sizeof *self);
    if (self)
        self->buffer = malloc ((size_t)width * (size_t)height * 4);
    if (!self || !self->buffer) {
        cgs_errf (err, errlen, "osmesa: out of memory");
        im_ctx_destroy (&self);
        return NULL;
    }
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    self->ctx = OSMesaCreateContextAttribs (attribs, NULL);
    if (!self->ctx) {
        cgs_errf (err, errlen, "osmesa: no OpenGL 3.3 core context (OSMesaCreateContextAttribs)");
        im_ctx_destroy (&self);
        return NULL;
    }
    if (!OSMesaMakeCurrent (self->ctx, self->buffer, GL_UNSIGNED_BYTE, width, height)) {
        cgs_errf (err, errlen, "osmesa: cannot make the context current");
        im_ctx_destroy (&self);
        return NULL;
    }
    return self;
}

void im_ctx_destroy (im_ctx_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    im_ctx_t *self = *self_p;
    if (self->ctx) {
        OSMesaMakeCurrent (NULL, NULL, 0, 0, 0); // releases the framebuffer it made
        OSMesaDestroyContext (self->ctx);
    }
    free (self->buffer);
    free (self);
    *self_p = NULL;
}
