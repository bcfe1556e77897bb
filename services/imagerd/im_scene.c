/* im_scene — terrain mesh and entity models (see im_scene.h). */
#include "im_scene.h"

#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static float s_node (const cgs_terrain_t *t, int c, int r)
{
    int cols = cgs_terrain_cols (t), rows = cgs_terrain_rows (t);
    c = c < 0 ? 0 : c >= cols ? cols - 1 : c;
    r = r < 0 ? 0 : r >= rows ? rows - 1 : r;
    return cgs_terrain_node (t, c, r);
}

/* The nodes a level takes along [a, b]: a, a + s, ..., and b. */
static int s_steps (int a, int b, int s, int *out)
{
    int n = 0;
    for (int i = a; i < b; i += s)
        out[n++] = i;
    out[n++] = b;
    return n;
}

/* How far node i (along a row r, or a column when !along_row) lies from the
 * line a level of step st draws between its nodes a chunk's edge: 0 at the
 * level's own nodes. n is the number of nodes along that line. */
static double s_crack (const cgs_terrain_t *t, int i, int fixed, int st, int chunk, int n,
                       bool along_row)
{
    if (i % chunk == 0 || i == n - 1)
        return 0;
    int c0 = i - i % chunk; // the chunk's first node; its nodes are c0, c0 + st, ..., its last
    int a = c0 + (i - c0) / st * st, b = a + st;
    b = b > c0 + chunk ? c0 + chunk : b;
    b = b > n - 1 ? n - 1 : b;
    if (i == a)
        return 0;
    double f = (double)(i - a) / (b - a);
    double ha = along_row ? cgs_terrain_node (t, a, fixed) : cgs_terrain_node (t, fixed, a);
    double hb = along_row ? cgs_terrain_node (t, b, fixed) : cgs_terrain_node (t, fixed, b);
    double hi = along_row ? cgs_terrain_node (t, i, fixed) : cgs_terrain_node (t, fixed, i);
    return fabs (hi - ((1 - f) * ha + f * hb));
}

int im_terrain_mesh_build (const cgs_terrain_t *t, int chunk_cells, int lods,
                           im_terrain_mesh_t *ret)
{
    if (!t || !ret || chunk_cells < 2 || chunk_cells > 1024 || (chunk_cells & (chunk_cells - 1)) ||
        lods < 1 || lods > IM_MAX_LODS)
        return -EINVAL;
    im_terrain_mesh_t m = {
        .cols = cgs_terrain_cols (t),
        .rows = cgs_terrain_rows (t),
        .res_m = cgs_terrain_resolution (t),
        .lods = lods,
    };
    if (m.cols < 2 || m.rows < 2)
        return -EINVAL;
    double max_e, max_n, hmin, hmax;
    cgs_terrain_bounds (t, &m.e0_m, &m.n0_m, &max_e, &max_n);
    cgs_terrain_height_range (t, &hmin, &hmax);
    (void)hmin, (void)hmax;
    size_t nodes = (size_t)m.cols * (size_t)m.rows;
    m.nverts = 2 * nodes;
    m.verts = malloc (m.nverts * sizeof *m.verts);
    int ccols = (m.cols - 2) / chunk_cells + 1, crows = (m.rows - 2) / chunk_cells + 1;
    m.nchunks = (size_t)ccols * (size_t)crows;
    m.chunks = calloc (m.nchunks, sizeof *m.chunks);
    // Indices: every level of a chunk takes at most its full-detail count.
    size_t per_chunk = 0;
    for (int l = 0; l < lods; l++) {
        size_t k = (size_t)chunk_cells / (1u << l) + 1;
        per_chunk += 6 * k * k + 4 * 6 * k;
    }
    size_t icap = per_chunk * m.nchunks;
    m.indices = malloc (icap * sizeof *m.indices);
    int *cs = malloc ((size_t)(chunk_cells + 2) * sizeof *cs);
    int *rs = malloc ((size_t)(chunk_cells + 2) * sizeof *rs);
    if (!m.verts || !m.chunks || !m.indices || !cs || !rs) {
        free (cs);
        free (rs);
        im_terrain_mesh_fini (&m);
        return -ENOMEM;
    }
    /* Skirt depth: the deepest crack a level can leave between neighbours,
     * the largest distance along any chunk edge between a node and the
     * straight line a coarser level draws between its own nodes. */
    double crack = 0;
    for (int l = 1; l < lods; l++)
        for (int r = 0; r < m.rows; r++)
            for (int c = 0; c < m.cols; c++) {
                if (r % chunk_cells == 0 || r == m.rows - 1) // along a chunk's row edge
                    crack = fmax (crack, s_crack (t, c, r, 1 << l, chunk_cells, m.cols, true));
                if (c % chunk_cells == 0 || c == m.cols - 1) // along a column edge
                    crack = fmax (crack, s_crack (t, r, c, 1 << l, chunk_cells, m.rows, false));
            }
    m.skirt_m = fmax (2.0 * m.res_m, 1.1 * crack + 1.0);
    for (int r = 0; r < m.rows; r++)
        for (int c = 0; c < m.cols; c++) {
            float h = cgs_terrain_node (t, c, r);
            // Normal from central differences of the node heights.
            double dhe = (s_node (t, c + 1, r) - s_node (t, c - 1, r)) /
                         (((c + 1 < m.cols) + (c > 0)) * m.res_m);
            double dhn = (s_node (t, c, r + 1) - s_node (t, c, r - 1)) /
                         (((r + 1 < m.rows) + (r > 0)) * m.res_m);
            double len = sqrt (dhe * dhe + dhn * dhn + 1.0);
            im_vertex_t v = {
                .pos = {(float)(m.e0_m + c * m.res_m), (float)(m.n0_m + r * m.res_m), h},
                .nrm = {(float)(-dhe / len), (float)(-dhn / len), (float)(1.0 / len)},
                .mat = IM_MAT_GROUND,
            };
            size_t i = (size_t)r * (size_t)m.cols + (size_t)c;
            m.verts[i] = v;
            v.pos[2] = (float)(h - m.skirt_m);
            m.verts[nodes + i] = v;
        }
    size_t ni = 0;
    const uint32_t twin = (uint32_t)nodes;
    for (int cj = 0; cj < crows; cj++)
        for (int ci = 0; ci < ccols; ci++) {
            im_chunk_t *ch = &m.chunks[(size_t)cj * (size_t)ccols + (size_t)ci];
            ch->col0 = ci * chunk_cells;
            ch->row0 = cj * chunk_cells;
            ch->col1 = ch->col0 + chunk_cells < m.cols - 1 ? ch->col0 + chunk_cells : m.cols - 1;
            ch->row1 = ch->row0 + chunk_cells < m.rows - 1 ? ch->row0 + chunk_cells : m.rows - 1;
            double lo = INFINITY, hi = -INFINITY;
            for (int r = ch->row0; r <= ch->row1; r++)
                for (int c = ch->col0; c <= ch->col1; c++) {
                    double h = cgs_terrain_node (t, c, r);
                    lo = fmin (lo, h);
                    hi = fmax (hi, h);
                }
            ch->lo = (cgs_enu_t){m.e0_m + ch->col0 * m.res_m, m.n0_m + ch->row0 * m.res_m,
                                 lo - m.skirt_m};
            ch->hi = (cgs_enu_t){m.e0_m + ch->col1 * m.res_m, m.n0_m + ch->row1 * m.res_m, hi};
            for (int l = 0; l < lods; l++) {
                int nc = s_steps (ch->col0, ch->col1, 1 << l, cs);
                int nr = s_steps (ch->row0, ch->row1, 1 << l, rs);
                ch->first[l] = (uint32_t)ni;
#define S_ID(c, r) ((uint32_t)((size_t)(r) * (size_t)m.cols + (size_t)(c)))
                for (int j = 0; j + 1 < nr; j++)
                    for (int i = 0; i + 1 < nc; i++) {
                        uint32_t a = S_ID (cs[i], rs[j]), b = S_ID (cs[i + 1], rs[j]);
                        uint32_t c = S_ID (cs[i + 1], rs[j + 1]), d = S_ID (cs[i], rs[j + 1]);
                        const uint32_t q[6] = {a, b, c, a, c, d}; // counter-clockwise from above
                        memcpy (&m.indices[ni], q, sizeof q);
                        ni += 6;
                    }
                // Skirts: a wall hanging from each edge of the chunk down to the twins.
                for (int side = 0; side < 4; side++) {
                    int n = side < 2 ? nc : nr;
                    for (int i = 0; i + 1 < n; i++) {
                        uint32_t a, b;
                        if (side == 0)
                            a = S_ID (cs[i], rs[0]), b = S_ID (cs[i + 1], rs[0]);
                        else if (side == 1)
                            a = S_ID (cs[i + 1], rs[nr - 1]), b = S_ID (cs[i], rs[nr - 1]);
                        else if (side == 2)
                            a = S_ID (cs[0], rs[i + 1]), b = S_ID (cs[0], rs[i]);
                        else
                            a = S_ID (cs[nc - 1], rs[i]), b = S_ID (cs[nc - 1], rs[i + 1]);
                        const uint32_t q[6] = {a, a + twin, b + twin, a, b + twin, b};
                        memcpy (&m.indices[ni], q, sizeof q);
                        ni += 6;
                    }
                }
#undef S_ID
                ch->count[l] = (uint32_t)(ni - ch->first[l]);
            }
        }
    free (cs);
    free (rs);
    m.nindices = ni;
    *ret = m;
    return 0;
}

void im_terrain_mesh_fini (im_terrain_mesh_t *m)
{
    if (!m)
        return;
    free (m->verts);
    free (m->indices);
    free (m->chunks);
    memset (m, 0, sizeof *m);
}

int im_chunk_lod (const im_terrain_mesh_t *m, const im_chunk_t *c, cgs_enu_t eye,
                  double lod_distance_m)
{
    // Distance from the eye to the nearest point of the box.
    double de = fmax (0.0, fmax (c->lo.e_m - eye.e_m, eye.e_m - c->hi.e_m));
    double dn = fmax (0.0, fmax (c->lo.n_m - eye.n_m, eye.n_m - c->hi.n_m));
    double du = fmax (0.0, fmax (c->lo.u_m - eye.u_m, eye.u_m - c->hi.u_m));
    double d = sqrt (de * de + dn * dn + du * du);
    if (!(lod_distance_m > 0) || !(d > lod_distance_m))
        return 0;
    int l = (int)floor (log2 (d / lod_distance_m)) + 1;
    return l < m->lods ? l : m->lods - 1;
}

/* ---- models -------------------------------------------------------------------- */

typedef struct {
    im_vertex_t *v;
    size_t n, cap;
} s_build_t;

/* An axis-aligned box: centre (x, y, z), size (sx, sy, sz), 12 triangles. */
static int s_box (s_build_t *b, double x, double y, double z, double sx, double sy, double sz,
                  im_material_t mat)
{
    if (b->n + 36 > b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 256;
        im_vertex_t *v = realloc (b->v, cap * sizeof *v);
        if (!v)
            return -ENOMEM;
        b->v = v;
        b->cap = cap;
    }
    // Each face: normal axis, sign; its corners counter-clockwise seen from outside.
    static const int faces[6][4][3] = {
        {{1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}},     // +x
        {{-1, 1, -1}, {-1, -1, -1}, {-1, -1, 1}, {-1, 1, 1}}, // -x
        {{1, 1, -1}, {-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}},     // +y
        {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}}, // -y
        {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}},     // +z
        {{-1, 1, -1}, {1, 1, -1}, {1, -1, -1}, {-1, -1, -1}}, // -z
    };
    static const float normals[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                        {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    static const int tri[6] = {0, 1, 2, 0, 2, 3};
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 6; k++) {
            const int *c = faces[f][tri[k]];
            b->v[b->n++] = (im_vertex_t){
                .pos = {(float)(x + c[0] * sx / 2), (float)(y + c[1] * sy / 2),
                        (float)(z + c[2] * sz / 2)},
                .nrm = {normals[f][0], normals[f][1], normals[f][2]},
                .mat = (float)mat,
            };
        }
    return 0;
}

/* Length, width, height of each kind's model (im_model_build's boxes span them). */
static const double s_extent[5][3] = {
    {4.5, 2.2, 2.0},  // other
    {6.8, 3.4, 2.5},  // tracked
    {7.0, 2.5, 3.1},  // wheeled
    {8.5, 14.0, 1.1}, // air
    {0.4, 0.6, 1.8},  // person
};

void im_model_extent (cgs_kind_t kind, double *ret_length_m, double *ret_width_m,
                      double *ret_height_m)
{
    const double *e = s_extent[(unsigned)kind < 5 ? kind : 0];
    *ret_length_m = e[0], *ret_width_m = e[1], *ret_height_m = e[2];
}

int im_model_build (cgs_kind_t kind, im_model_t *ret)
{
    s_build_t b = {0};
    int rc = 0;
    switch (kind) {
    case CGS_KIND_TRACKED: // an APC or tank: tracks, hull, engine deck at the rear, turret
        rc |= s_box (&b, -1.35, 0, 0.45, 0.7, 6.8, 0.9, IM_MAT_RUNNING);
        rc |= s_box (&b, 1.35, 0, 0.45, 0.7, 6.8, 0.9, IM_MAT_RUNNING);
        rc |= s_box (&b, 0, 0, 1.1, 2.0, 6.6, 1.2, IM_MAT_HULL);
        rc |= s_box (&b, 0, -2.4, 1.75, 2.0, 1.6, 0.1, IM_MAT_ENGINE);
        rc |= s_box (&b, 0, 0.5, 2.1, 1.8, 2.2, 0.8, IM_MAT_HULL);
        rc |= s_box (&b, 0, 1.65, 2.2, 1.0, 0.1, 0.3, IM_MAT_GLASS);
        break;
    case CGS_KIND_WHEELED: // a truck: wheels, chassis, cab with its engine ahead, cargo box
        for (int i = 0; i < 3; i++) {
            double y = 2.5 - 2.4 * i;
            rc |= s_box (&b, -1.0, y, 0.5, 0.5, 1.0, 1.0, IM_MAT_RUNNING);
            rc |= s_box (&b, 1.0, y, 0.5, 0.5, 1.0, 1.0, IM_MAT_RUNNING);
        }
        rc |= s_box (&b, 0, 0, 1.1, 2.2, 7.0, 0.4, IM_MAT_HULL);
        rc |= s_box (&b, 0, 2.9, 1.6, 2.2, 1.2, 0.6, IM_MAT_ENGINE);
        rc |= s_box (&b, 0, 1.9, 2.1, 2.4, 1.2, 1.6, IM_MAT_HULL);
        rc |= s_box (&b, 0, 2.55, 2.4, 2.0, 0.1, 0.7, IM_MAT_GLASS);
        rc |= s_box (&b, 0, -1.2, 2.2, 2.5, 4.6, 1.8, IM_MAT_HULL);
        break;
    case CGS_KIND_AIR: // a UAV: fuselage, wing, tail, engine at the back
        rc |= s_box (&b, 0, 0.25, 0.5, 1.0, 8.0, 1.0, IM_MAT_HULL);
        rc |= s_box (&b, 0, 0.75, 0.6, 14.0, 1.5, 0.2, IM_MAT_HULL);
        rc |= s_box (&b, 0, -3.35, 1.025, 3.6, 0.8, 0.15, IM_MAT_HULL);
        rc |= s_box (&b, 0, -3.95, 0.5, 0.7, 0.6, 0.7, IM_MAT_ENGINE);
        break;
    case CGS_KIND_PERSON:
        rc |= s_box (&b, 0, 0, 0.9, 0.6, 0.4, 1.8, IM_MAT_PERSON);
        break;
    default:
        rc |= s_box (&b, 0, 0, 1.0, 2.2, 4.5, 2.0, IM_MAT_HULL);
        rc |= s_box (&b, 0, 1.8, 1.5, 2.0, 0.8, 0.8, IM_MAT_ENGINE);
        break;
    }
    if (rc) {
        free (b.v);
        return -ENOMEM;
    }
    im_model_t m = {.verts = b.v, .nverts = b.n};
    im_model_extent (kind, &m.length_m, &m.width_m, &m.height_m);
    *ret = m;
    return 0;
}

void im_model_fini (im_model_t *m)
{
    if (!m)
        return;
    free (m->verts);
    memset (m, 0, sizeof *m);
}
