/* im_ctx on EGL's surfaceless platform (see im_ctx.h). */
#include "im_ctx.h"
#include "cgs_util.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <errno.h>
#include <stdlib.h>

struct im_ctx {
    EGLDisplay display;
    EGLContext ctx;
};

const char *im_ctx_backend (void)
{
    return "egl";
}

im_ctx_t *im_ctx_new (int width, int height, char *err, size_t errlen)
{
    if (im_ctx_check_driver (getenv ("GALLIUM_DRIVER"), err, errlen) < 0)
        return NULL;
    if (width < 1 || height < 1) {
        cgs_errf (err, errlen, "egl: a %d x %d image is not possible", width, height);
        return NULL;
    }
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress ("eglGetPlatformDisplayEXT");
    if (!get_display) {
        cgs_errf (err, errlen, "egl: no eglGetPlatformDisplayEXT (EGL_EXT_platform_base)");
        return NULL;
    }
    im_ctx_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_errf (err, errlen, "egl: out of memory");
        return NULL;
    }
    self->display = get_display (EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major, minor;
    if (self->display == EGL_NO_DISPLAY || !eglInitialize (self->display, &major, &minor)) {
        cgs_errf (err, errlen, "egl: no surfaceless display (EGL error 0x%x)", eglGetError ());
        self->display = EGL_NO_DISPLAY;
        im_ctx_destroy (&self);
        return NULL;
    }
    if (!eglBindAPI (EGL_OPENGL_API)) {
        cgs_errf (err, errlen, "egl: no desktop OpenGL (EGL error 0x%x)", eglGetError ());
        im_ctx_destroy (&self);
        return NULL;
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              3,
                              EGL_CONTEXT_MINOR_VERSION,
                              3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    self->ctx = eglCreateContext (self->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (self->ctx == EGL_NO_CONTEXT) {
        cgs_errf (err, errlen, "egl: no OpenGL 3.3 core context (EGL error 0x%x)", eglGetError ());
        im_ctx_destroy (&self);
        return NULL;
    }
    if (!eglMakeCurrent (self->display, EGL_NO_SURFACE, EGL_NO_SURFACE, self->ctx)) {
        cgs_errf (err, errlen, "egl: cannot make the context current (EGL error 0x%x)",
                  eglGetError ());
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
    if (self->display != EGL_NO_DISPLAY) {
        eglMakeCurrent (self->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (self->ctx != EGL_NO_CONTEXT)
            eglDestroyContext (self->display, self->ctx);
        // Not eglTerminate: the surfaceless display is one per process (a new
        // context gets it again) and libEGL terminates it at exit; terminating
        // it here unloads the driver with a few of its allocations still held.
    }
    free (self);
    *self_p = NULL;
}
