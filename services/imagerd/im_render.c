/* im_render — the imaging sensor's view in OpenGL 3.3 core (see im_render.h). */
#define GL_GLEXT_PROTOTYPES 1
#include "im_render.h"
#include "cgs_util.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_DEG         (M_PI / 180.0)
#define S_KOSCHMIEDER 3.912 // −ln 0.02: extinction × visibility

static const char s_vs[] = "#version 330 core\n"
                           "layout(location = 0) in vec3 a_pos;\n"
                           "layout(location = 1) in vec3 a_nrm;\n"
                           "layout(location = 2) in float a_mat;\n"
                           "uniform mat4 u_view, u_proj;\n"
                           "uniform mat3 u_rot;\n"
                           "uniform vec3 u_offset;\n"
                           "out vec3 v_world;\n"
                           "out vec3 v_nrm;\n"
                           "flat out int v_mat;\n"
                           "void main () {\n"
                           "  vec3 w = u_rot * a_pos + u_offset;\n"
                           "  v_world = w;\n"
                           "  v_nrm = u_rot * a_nrm;\n"
                           "  v_mat = int (a_mat + 0.5);\n"
                           "  gl_Position = u_proj * (u_view * vec4 (w, 1.0));\n"
                           "}\n";

static const char s_fs[] =
    "#version 330 core\n"
    "in vec3 v_world;\n"
    "in vec3 v_nrm;\n"
    "flat in int v_mat;\n"
    "uniform vec3 u_eye, u_sun, u_haze, u_color;\n"
    "uniform int u_mode;\n"
    "uniform vec2 u_hrange;\n"
    "uniform float u_beta, u_running;\n"
    "uniform float u_ambient, u_sun_gain, u_hull_rise, u_engine, u_gear_rise, u_glass, "
    "u_person, u_sky, u_alpha, u_tmin, u_tmax;\n"
    "out vec4 o_color;\n"
    "void main () {\n"
    "  vec3 n = normalize (v_nrm);\n"
    "  float sun = max (dot (n, u_sun), 0.0);\n"
    "  float r = distance (v_world, u_eye);\n"
    "  if (u_mode == 0) {\n"
    "    vec3 c;\n"
    "    if (v_mat == 0) {\n"
    "      float h = clamp ((v_world.z - u_hrange.x) / max (u_hrange.y - u_hrange.x, 1.0), 0.0, "
    "1.0);\n"
    "      vec3 low = vec3 (0.30, 0.42, 0.20), mid = vec3 (0.46, 0.42, 0.27), high = vec3 (0.56, "
    "0.53, 0.49);\n"
    "      c = h < 0.5 ? mix (low, mid, 2.0 * h) : mix (mid, high, 2.0 * h - 1.0);\n"
    "      c = mix (c, vec3 (0.42, 0.38, 0.34), clamp (4.0 * (1.0 - n.z), 0.0, 1.0));\n"
    "    } else if (v_mat == 1) c = u_color;\n"
    "    else if (v_mat == 2) c = 0.7 * u_color;\n"
    "    else if (v_mat == 3) c = vec3 (0.12);\n"
    "    else if (v_mat == 4) c = vec3 (0.05, 0.07, 0.10);\n"
    "    else c = vec3 (0.55, 0.45, 0.35);\n"
    "    c *= 0.35 + 0.65 * sun;\n"
    "    o_color = vec4 (mix (u_haze, c, exp (-u_beta * r)), 1.0);\n"
    "  } else {\n"
    "    float t;\n"
    "    if (v_mat == 0) t = u_ambient + u_sun_gain * sun;\n"
    "    else if (v_mat == 1) t = u_ambient + u_running * u_hull_rise + 0.3 * u_sun_gain * sun;\n"
    "    else if (v_mat == 2) t = mix (u_ambient + 2.0, u_engine, u_running);\n"
    "    else if (v_mat == 3) t = u_ambient + u_running * u_gear_rise;\n"
    "    else if (v_mat == 4) t = u_glass;\n"
    "    else t = u_person;\n"
    "    float tau = exp (-u_alpha * r);\n"
    "    float g = clamp ((tau * t + (1.0 - tau) * u_sky - u_tmin) / (u_tmax - u_tmin), 0.0, "
    "1.0);\n"
    "    o_color = vec4 (g, g, g, 1.0);\n"
    "  }\n"
    "}\n";

typedef struct {
    GLint view, proj, rot, offset, eye, sun, haze, color, mode, hrange, beta, running, ambient,
        sun_gain, hull_rise, engine, gear_rise, glass, person, sky, alpha, tmin, tmax;
} s_uniforms_t;

#define S_KINDS 5 // cgs_kind_t: other, tracked, wheeled, air, person

struct im_renderer {
    int w, h;
    GLuint prog, fbo, color_rb, depth_rb;
    GLuint terrain_vao, terrain_vbo, terrain_ebo;
    GLuint model_vao, model_vbo;
    GLint model_first[S_KINDS];
    GLsizei model_count[S_KINDS];
    double model_radius[S_KINDS];
    im_chunk_t *chunks;
    size_t nchunks;
    int lods;
    double lod_distance_m; // from the last draw's parameters
    double hmin, hmax;
    im_terrain_mesh_t mesh_info; // geometry only (no arrays)
    s_uniforms_t u;
    uint8_t *row; // one row, for flipping the readback
    im_render_stats_t stats;
    char gl[256];
};

static GLuint s_shader (GLenum type, const char *src, char *err, size_t errlen)
{
    GLuint s = glCreateShader (type);
    glShaderSource (s, 1, &src, NULL);
    glCompileShader (s);
    GLint ok = 0;
    glGetShaderiv (s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog (s, sizeof log, NULL, log);
        cgs_errf (err, errlen, "GL: %s shader does not compile: %s",
                  type == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
        glDeleteShader (s);
        return 0;
    }
    return s;
}

static void s_attribs (void)
{
    glVertexAttribPointer (0, 3, GL_FLOAT, GL_FALSE, sizeof (im_vertex_t),
                           (void *)offsetof (im_vertex_t, pos));
    glVertexAttribPointer (1, 3, GL_FLOAT, GL_FALSE, sizeof (im_vertex_t),
                           (void *)offsetof (im_vertex_t, nrm));
    glVertexAttribPointer (2, 1, GL_FLOAT, GL_FALSE, sizeof (im_vertex_t),
                           (void *)offsetof (im_vertex_t, mat));
    for (GLuint i = 0; i < 3; i++)
        glEnableVertexAttribArray (i);
}

static int s_models (im_renderer_t *self, char *err, size_t errlen)
{
    im_model_t models[S_KINDS] = {{0}};
    size_t total = 0;
    int rc = 0;
    for (int k = 0; k < S_KINDS && rc == 0; k++) {
        rc = im_model_build ((cgs_kind_t)k, &models[k]);
        total += models[k].nverts;
    }
    im_vertex_t *all = rc == 0 ? malloc (total * sizeof *all) : NULL;
    if (!all) {
        cgs_errf (err, errlen, "out of memory for the entity models");
        rc = -ENOMEM;
    } else {
        size_t at = 0;
        for (int k = 0; k < S_KINDS; k++) {
            memcpy (all + at, models[k].verts, models[k].nverts * sizeof *all);
            self->model_first[k] = (GLint)at;
            self->model_count[k] = (GLsizei)models[k].nverts;
            self->model_radius[k] = 0.5 * sqrt (models[k].length_m * models[k].length_m +
                                                models[k].width_m * models[k].width_m +
                                                models[k].height_m * models[k].height_m);
            at += models[k].nverts;
        }
        glGenVertexArrays (1, &self->model_vao);
        glBindVertexArray (self->model_vao);
        glGenBuffers (1, &self->model_vbo);
        glBindBuffer (GL_ARRAY_BUFFER, self->model_vbo);
        glBufferData (GL_ARRAY_BUFFER, (GLsizeiptr)(total * sizeof *all), all, GL_STATIC_DRAW);
        s_attribs ();
        glBindVertexArray (0);
    }
    free (all);
    for (int k = 0; k < S_KINDS; k++)
        im_model_fini (&models[k]);
    return rc;
}

im_renderer_t *im_renderer_new (int width, int height, const im_terrain_mesh_t *mesh, char *err,
                                size_t errlen)
{
    im_renderer_t *self = calloc (1, sizeof *self);
    if (!self || !(self->row = malloc ((size_t)width * 4))) {
        cgs_errf (err, errlen, "out of memory for the renderer");
        free (self);
        return NULL;
    }
    self->w = width;
    self->h = height;
    snprintf (self->gl, sizeof self->gl, "%s, OpenGL %s", (const char *)glGetString (GL_RENDERER),
              (const char *)glGetString (GL_VERSION));
    GLuint vs = s_shader (GL_VERTEX_SHADER, s_vs, err, errlen);
    GLuint fs = vs ? s_shader (GL_FRAGMENT_SHADER, s_fs, err, errlen) : 0;
    if (!vs || !fs) {
        glDeleteShader (vs);
        im_renderer_destroy (&self);
        return NULL;
    }
    self->prog = glCreateProgram ();
    glAttachShader (self->prog, vs);
    glAttachShader (self->prog, fs);
    glLinkProgram (self->prog);
    glDeleteShader (vs);
    glDeleteShader (fs);
    GLint ok = 0;
    glGetProgramiv (self->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetProgramInfoLog (self->prog, sizeof log, NULL, log);
        cgs_errf (err, errlen, "GL: the shaders do not link: %s", log);
        im_renderer_destroy (&self);
        return NULL;
    }
#define S_U(f) self->u.f = glGetUniformLocation (self->prog, "u_" #f)
    S_U (view), S_U (proj), S_U (rot), S_U (offset), S_U (eye), S_U (sun), S_U (haze);
    S_U (color), S_U (mode), S_U (hrange), S_U (beta), S_U (running), S_U (ambient);
    S_U (sun_gain), S_U (hull_rise), S_U (engine), S_U (gear_rise), S_U (glass), S_U (person);
    S_U (sky), S_U (alpha), S_U (tmin), S_U (tmax);
#undef S_U
    // The framebuffer: colour and depth renderbuffers of the image's size.
    glGenFramebuffers (1, &self->fbo);
    glBindFramebuffer (GL_FRAMEBUFFER, self->fbo);
    glGenRenderbuffers (1, &self->color_rb);
    glBindRenderbuffer (GL_RENDERBUFFER, self->color_rb);
    glRenderbufferStorage (GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer (GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                               self->color_rb);
    glGenRenderbuffers (1, &self->depth_rb);
    glBindRenderbuffer (GL_RENDERBUFFER, self->depth_rb);
    glRenderbufferStorage (GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer (GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                               self->depth_rb);
    if (glCheckFramebufferStatus (GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        cgs_errf (err, errlen, "GL: a %d x %d framebuffer is not complete", width, height);
        im_renderer_destroy (&self);
        return NULL;
    }
    if (mesh && mesh->nverts) {
        self->chunks = malloc (mesh->nchunks * sizeof *self->chunks);
        if (!self->chunks) {
            cgs_errf (err, errlen, "out of memory for the terrain chunks");
            im_renderer_destroy (&self);
            return NULL;
        }
        memcpy (self->chunks, mesh->chunks, mesh->nchunks * sizeof *self->chunks);
        self->nchunks = mesh->nchunks;
        self->mesh_info = *mesh;
        self->mesh_info.verts = NULL, self->mesh_info.indices = NULL, self->mesh_info.chunks = NULL;
        self->hmin = INFINITY, self->hmax = -INFINITY;
        for (size_t i = 0; i < mesh->nchunks; i++) {
            self->hmin = fmin (self->hmin, mesh->chunks[i].lo.u_m + mesh->skirt_m);
            self->hmax = fmax (self->hmax, mesh->chunks[i].hi.u_m);
        }
        glGenVertexArrays (1, &self->terrain_vao);
        glBindVertexArray (self->terrain_vao);
        glGenBuffers (1, &self->terrain_vbo);
        glBindBuffer (GL_ARRAY_BUFFER, self->terrain_vbo);
        glBufferData (GL_ARRAY_BUFFER, (GLsizeiptr)(mesh->nverts * sizeof *mesh->verts),
                      mesh->verts, GL_STATIC_DRAW);
        glGenBuffers (1, &self->terrain_ebo);
        glBindBuffer (GL_ELEMENT_ARRAY_BUFFER, self->terrain_ebo);
        glBufferData (GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(mesh->nindices * sizeof (uint32_t)),
                      mesh->indices, GL_STATIC_DRAW);
        s_attribs ();
        glBindVertexArray (0);
    }
    if (s_models (self, err, errlen) < 0) {
        im_renderer_destroy (&self);
        return NULL;
    }
    GLenum e = glGetError ();
    if (e != GL_NO_ERROR) {
        cgs_errf (err, errlen, "GL error 0x%x while setting up the renderer", e);
        im_renderer_destroy (&self);
        return NULL;
    }
    return self;
}

void im_renderer_destroy (im_renderer_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    im_renderer_t *self = *self_p;
    glDeleteBuffers (1, &self->terrain_vbo);
    glDeleteBuffers (1, &self->terrain_ebo);
    glDeleteBuffers (1, &self->model_vbo);
    glDeleteVertexArrays (1, &self->terrain_vao);
    glDeleteVertexArrays (1, &self->model_vao);
    glDeleteRenderbuffers (1, &self->color_rb);
    glDeleteRenderbuffers (1, &self->depth_rb);
    glDeleteFramebuffers (1, &self->fbo);
    if (self->prog)
        glDeleteProgram (self->prog);
    free (self->chunks);
    free (self->row);
    free (self);
    *self_p = NULL;
}

const char *im_renderer_gl (const im_renderer_t *self)
{
    return self->gl;
}

void im_renderer_stats (const im_renderer_t *self, im_render_stats_t *ret)
{
    *ret = self->stats;
}

/* The hull colour of a kind, visible light. */
static void s_kind_color (cgs_kind_t k, float c[3])
{
    static const float colors[S_KINDS][3] = {
        {0.40f, 0.38f, 0.30f}, // other
        {0.29f, 0.33f, 0.20f}, // tracked: olive drab
        {0.52f, 0.46f, 0.32f}, // wheeled: sand
        {0.60f, 0.62f, 0.64f}, // air: light grey
        {0.45f, 0.40f, 0.28f}, // person
    };
    memcpy (c, colors[(unsigned)k < S_KINDS ? k : 0], 3 * sizeof *c);
}

int im_renderer_draw (im_renderer_t *self, const cgs_camera_t *cam, const im_params_t *p,
                      const im_entity_t *ents, size_t n, uint8_t *rgba, char *err, size_t errlen)
{
    memset (&self->stats, 0, sizeof self->stats);
    glBindFramebuffer (GL_FRAMEBUFFER, self->fbo);
    glViewport (0, 0, self->w, self->h);
    glEnable (GL_DEPTH_TEST);
    glDisable (GL_CULL_FACE);
    // The sky: haze colour in the visible, the sky's temperature in the infrared.
    const float haze[3] = {0.70f, 0.74f, 0.78f};
    bool ir = p->mode == IM_MODE_INFRARED;
    float sky = (float)((p->sky_k - p->display_min_k) / (p->display_max_k - p->display_min_k));
    sky = sky < 0 ? 0 : sky > 1 ? 1 : sky;
    if (ir)
        glClearColor (sky, sky, sky, 1.0f);
    else
        glClearColor (haze[0], haze[1], haze[2], 1.0f);
    glClear (GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram (self->prog);
    glUniformMatrix4fv (self->u.view, 1, GL_FALSE, cam->view);
    glUniformMatrix4fv (self->u.proj, 1, GL_FALSE, cam->proj);
    glUniform3f (self->u.eye, (float)cam->eye.e_m, (float)cam->eye.n_m, (float)cam->eye.u_m);
    double az = p->sun_azimuth_deg * S_DEG, el = p->sun_elevation_deg * S_DEG;
    glUniform3f (self->u.sun, (float)(sin (az) * cos (el)), (float)(cos (az) * cos (el)),
                 (float)sin (el));
    glUniform3f (self->u.haze, haze[0], haze[1], haze[2]);
    glUniform1i (self->u.mode, ir ? 1 : 0);
    glUniform2f (self->u.hrange, (float)self->hmin, (float)self->hmax);
    glUniform1f (self->u.beta, (float)(S_KOSCHMIEDER / p->visibility_m));
    glUniform1f (self->u.ambient, (float)p->ambient_k);
    glUniform1f (self->u.sun_gain, (float)(p->sun_gain_k * (el > 0 ? sin (el) : 0.0)));
    glUniform1f (self->u.hull_rise, (float)p->hull_rise_k);
    glUniform1f (self->u.engine, (float)p->engine_k);
    glUniform1f (self->u.gear_rise, (float)p->running_gear_rise_k);
    glUniform1f (self->u.glass, (float)p->glass_k);
    glUniform1f (self->u.person, (float)p->person_k);
    glUniform1f (self->u.sky, (float)p->sky_k);
    glUniform1f (self->u.alpha, (float)(p->attenuation_per_km / 1000.0));
    glUniform1f (self->u.tmin, (float)p->display_min_k);
    glUniform1f (self->u.tmax, (float)p->display_max_k);
    double planes[6][4];
    cgs_camera_frustum (cam, planes);
    // Terrain: each chunk in view at its level of detail.
    static const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    glUniformMatrix3fv (self->u.rot, 1, GL_FALSE, identity);
    glUniform3f (self->u.offset, 0, 0, 0);
    glUniform1f (self->u.running, 0);
    if (self->terrain_vao) {
        glBindVertexArray (self->terrain_vao);
        for (size_t i = 0; i < self->nchunks; i++) {
            const im_chunk_t *c = &self->chunks[i];
            if (cgs_frustum_culls ((const double (*)[4])planes, c->lo, c->hi)) {
                self->stats.chunks_culled++;
                continue;
            }
            int l = im_chunk_lod (&self->mesh_info, c, cam->eye, p->lod_distance_m);
            glDrawElements (GL_TRIANGLES, (GLsizei)c->count[l], GL_UNSIGNED_INT,
                            (void *)((size_t)c->first[l] * sizeof (uint32_t)));
            self->stats.chunks_drawn++;
            self->stats.triangles += c->count[l] / 3;
        }
    }
    // Entities: the model of each kind, turned to its heading.
    glBindVertexArray (self->model_vao);
    for (size_t i = 0; i < n; i++) {
        const im_entity_t *e = &ents[i];
        unsigned k = (unsigned)e->kind < S_KINDS ? (unsigned)e->kind : 0;
        double r = self->model_radius[k];
        cgs_enu_t lo = {e->position.e_m - r, e->position.n_m - r, e->position.u_m - r};
        cgs_enu_t hi = {e->position.e_m + r, e->position.n_m + r, e->position.u_m + 2 * r};
        if (cgs_frustum_culls ((const double (*)[4])planes, lo, hi))
            continue;
        double h = e->heading_deg * S_DEG;
        // Columns: model x (right), y (forward), z (up) in the local frame.
        const float rot[9] = {
            (float)cos (h), (float)-sin (h), 0, (float)sin (h), (float)cos (h), 0, 0, 0, 1};
        float color[3];
        s_kind_color ((cgs_kind_t)k, color);
        glUniformMatrix3fv (self->u.rot, 1, GL_FALSE, rot);
        glUniform3f (self->u.offset, (float)e->position.e_m, (float)e->position.n_m,
                     (float)e->position.u_m);
        glUniform3f (self->u.color, color[0], color[1], color[2]);
        glUniform1f (self->u.running, e->running ? 1.0f : 0.0f);
        glDrawArrays (GL_TRIANGLES, self->model_first[k], self->model_count[k]);
        self->stats.entities_drawn++;
        self->stats.triangles += (size_t)self->model_count[k] / 3;
    }
    glBindVertexArray (0);
    // Read back, top row first.
    glPixelStorei (GL_PACK_ALIGNMENT, 1);
    glReadPixels (0, 0, self->w, self->h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    GLenum ge = glGetError ();
    if (ge != GL_NO_ERROR) {
        cgs_errf (err, errlen, "GL error 0x%x while drawing a frame", ge);
        return -EIO;
    }
    size_t stride = (size_t)self->w * 4;
    for (int y = 0; y < self->h / 2; y++) {
        uint8_t *a = rgba + (size_t)y * stride, *b = rgba + (size_t)(self->h - 1 - y) * stride;
        memcpy (self->row, a, stride);
        memcpy (a, b, stride);
        memcpy (b, self->row, stride);
    }
    return 0;
}
