/* im_render — draws the imaging sensor's view with OpenGL 3.3 core into a
 * framebuffer object and reads it back: the terrain mesh (chunks outside the
 * view culled, each at its level of detail) shaded by height and slope with
 * sun lighting and range haze, and the entities as models by kind at their
 * positions and headings on the ground. In infrared mode each surface's
 * temperature (by material; running engines hot, ground by sun exposure)
 * is attenuated with range toward the sky's and written as a grey level
 * between the display's black and white temperatures (im_post adds blur,
 * noise and the polarity). Needs a current context (im_ctx). */
#ifndef IM_RENDER_H
#define IM_RENDER_H

#include "cgs_camera.h"
#include "im_params.h"
#include "im_scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct im_renderer im_renderer_t;

/* An entity to draw. */
typedef struct {
    uint32_t id;
    cgs_kind_t kind;
    cgs_enu_t position; // on the ground (the model's base)
    double heading_deg;
    bool running;        // engine on: hot in the infrared
    const char *marking; // for its status block (NULL: none)
    cgs_force_t force;
    double speed_mps; // over the ground
} im_entity_t;

/* A renderer for width × height images of the mesh (NULL: no terrain). It
 * keeps its own copy of what it needs on the GPU side; the mesh may be
 * freed after. NULL with the reason in err. */
im_renderer_t *im_renderer_new (int width, int height, const im_terrain_mesh_t *mesh, char *err,
                                size_t errlen);
void im_renderer_destroy (im_renderer_t **self_p);
/* The GL_RENDERER and GL_VERSION strings of the context. */
const char *im_renderer_gl (const im_renderer_t *self);

/* Draw one frame and read it into rgba (width × height × 4 bytes, top row
 * first). 0, or -EIO with the reason in err (a GL error). */
int im_renderer_draw (im_renderer_t *self, const cgs_camera_t *cam, const im_params_t *p,
                      const im_entity_t *ents, size_t n, uint8_t *rgba, char *err, size_t errlen);

/* What the last draw did. */
typedef struct {
    size_t chunks_drawn, chunks_culled;
    size_t triangles;
    size_t entities_drawn;
} im_render_stats_t;
void im_renderer_stats (const im_renderer_t *self, im_render_stats_t *ret);

#endif
