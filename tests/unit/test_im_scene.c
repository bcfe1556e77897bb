/* test_im_scene — imagerd's terrain mesh and entity models:
 *   - the mesh of a small grid terrain: vertex positions are the nodes'
 *     (east e0 + c·res, north n0 + r·res, the node's height), each with a
 *     twin hanging skirt_m below; normals are the analytic normal of a
 *     tilted plane h = a·e + b·n + c, (−a, −b, 1)/|…|, at every node (edges
 *     too), and of a paraboloid at interior nodes (central differences are
 *     exact for a quadratic);
 *   - chunks tile the grid; a chunk's level-0 range is exactly its cells
 *     (two counter-clockwise triangles per cell, 6·cells² indices) and its
 *     skirts (two triangles per edge cell, hanging to the twins); every
 *     level's surface covers the chunk's area with the nodes it takes, its
 *     triangle count a quarter of the level before; every index is a vertex;
 *     chunk boxes hold their vertices; the ranges account for every index;
 *   - im_chunk_lod: 0 near, one level more per doubling of the distance,
 *     clamped to the last level;
 *   - bad chunk sizes and level counts refused;
 *   - the skirts are deep enough to hide the cracks between neighbouring
 *     chunks a level apart (fBm hills and mountains);
 *   - models: for every kind, the vertices span exactly im_model_extent
 *     (length along y, width along x, height along z from the ground at 0),
 *     centred on the origin; every triangle's winding (cross product) agrees
 *     with its stored normal, which points out of its box; materials valid.
 * Needs -Iservices/imagerd (and -Icommon). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cgs_terrain.h"
#include "im_scene.h"
#include "test_util.h"

/* ---- helpers ----------------------------------------------------------------------- */

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static double s_uniform (double lo, double hi)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    uint64_t x = s_rng * 0x2545F4914F6CDD1Dull;
    return lo + (hi - lo) * (double)(x >> 11) / 9007199254740992.0;
}

/* A cols × rows grid at (e0, n0) of spacing res with heights h(e, n). */
typedef double s_height_fn (double e, double n);

static cgs_terrain_t *s_terrain (int cols, int rows, double e0, double n0, double res,
                                 s_height_fn *h)
{
    float *z = malloc ((size_t)cols * (size_t)rows * sizeof *z);
    assert_non_null (z);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++)
            z[(size_t)r * (size_t)cols + (size_t)c] = (float)h (e0 + c * res, n0 + r * res);
    cgs_terrain_t *t = cgs_terrain_new_grid (cols, rows, e0, n0, res, z);
    free (z);
    assert_non_null (t);
    return t;
}

/* Hills and noise: nothing regular for the mesh to get right by accident. */
static double s_hills (double e, double n)
{
    return 150 + 40 * sin (e / 170.0) * cos (n / 230.0) + s_uniform (-3, 3);
}

#define PLANE_A 0.3
#define PLANE_B -0.2
static double s_plane (double e, double n)
{
    return PLANE_A * e + PLANE_B * n + 100;
}

#define PARA_A 2e-4
#define PARA_B -3e-4
static double s_paraboloid (double e, double n)
{
    return PARA_A * e * e + PARA_B * n * n + 0.05 * e + 50;
}

/* Vertex i's position as doubles. */
static void s_pos (const im_terrain_mesh_t *m, uint32_t i, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = m->verts[i].pos[k];
}

/* (b − a) × (c − a), vertical component: twice the signed area seen from
 * above (positive: counter-clockwise). */
static double s_area2_up (const double a[3], const double b[3], const double c[3])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* ---- the mesh ---------------------------------------------------------------------------- */

/* Every node is a vertex at its position and height, with its twin
 * skirt_m below; normals are unit; the grid's geometry is copied. */
static void test_mesh_vertices (void **state)
{
    (void)state;
    const int cols = 65, rows = 65;
    const double e0 = -1000, n0 = 500, res = 30;
    cgs_terrain_t *t = s_terrain (cols, rows, e0, n0, res, s_hills);
    im_terrain_mesh_t m;
    assert_int_equal (im_terrain_mesh_build (t, 16, 3, &m), 0);
    assert_int_equal (m.cols, cols);
    assert_int_equal (m.rows, rows);
    assert_near (m.e0_m, e0, 0);
    assert_near (m.n0_m, n0, 0);
    assert_near (m.res_m, res, 0);
    assert_int_equal (m.lods, 3);
    assert_true (m.skirt_m > 0);
    const size_t nodes = (size_t)cols * (size_t)rows;
    assert_int_equal (m.nverts, 2 * nodes);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            size_t i = (size_t)r * (size_t)cols + (size_t)c;
            const im_vertex_t *v = &m.verts[i], *tw = &m.verts[nodes + i];
            double h = cgs_terrain_node (t, c, r);
            assert_near (v->pos[0], e0 + c * res, 1e-3);
            assert_near (v->pos[1], n0 + r * res, 1e-3);
            assert_near (v->pos[2], h, 1e-4);
            assert_near (tw->pos[0], v->pos[0], 0);
            assert_near (tw->pos[1], v->pos[1], 0);
            assert_near (tw->pos[2], h - m.skirt_m, 1e-3);
            double len =
                sqrt (v->nrm[0] * v->nrm[0] + v->nrm[1] * v->nrm[1] + v->nrm[2] * v->nrm[2]);
            assert_near (len, 1, 1e-6);
            assert_true (v->nrm[2] > 0);
            assert_near (v->mat, IM_MAT_GROUND, 0);
            assert_near (tw->mat, IM_MAT_GROUND, 0);
        }
    im_terrain_mesh_fini (&m);
    assert_null (m.verts);
    assert_null (m.indices);
    assert_null (m.chunks);
    im_terrain_mesh_fini (&m); // twice is harmless
    im_terrain_mesh_fini (NULL);
    cgs_terrain_destroy (&t);
}

/* The normal of the plane h = a·e + b·n + c is (−a, −b, 1)/√(a² + b² + 1) at
 * every node, the grid's edges and corners included. Of the paraboloid
 * h = A·e² + B·n² + 0.05·e + 50 it is (−(2A·e + 0.05), −2B·n, 1)/|…| at the
 * interior nodes, where central differences are exact. */
static void test_mesh_normals (void **state)
{
    (void)state;
    const int cols = 33, rows = 17;
    const double e0 = -500, n0 = 200, res = 10;
    cgs_terrain_t *t = s_terrain (cols, rows, e0, n0, res, s_plane);
    im_terrain_mesh_t m;
    assert_int_equal (im_terrain_mesh_build (t, 8, 2, &m), 0);
    double l = sqrt (PLANE_A * PLANE_A + PLANE_B * PLANE_B + 1);
    for (size_t i = 0; i < (size_t)cols * (size_t)rows; i++) {
        assert_near (m.verts[i].nrm[0], -PLANE_A / l, 2e-5);
        assert_near (m.verts[i].nrm[1], -PLANE_B / l, 2e-5);
        assert_near (m.verts[i].nrm[2], 1 / l, 2e-5);
    }
    im_terrain_mesh_fini (&m);
    cgs_terrain_destroy (&t);

    t = s_terrain (cols, rows, e0, n0, res, s_paraboloid);
    assert_int_equal (im_terrain_mesh_build (t, 8, 2, &m), 0);
    for (int r = 1; r + 1 < rows; r++)
        for (int c = 1; c + 1 < cols; c++) {
            double e = e0 + c * res, n = n0 + r * res;
            double ge = 2 * PARA_A * e + 0.05, gn = 2 * PARA_B * n;
            double len = sqrt (ge * ge + gn * gn + 1);
            const im_vertex_t *v = &m.verts[(size_t)r * (size_t)cols + (size_t)c];
            assert_near (v->nrm[0], -ge / len, 2e-5);
            assert_near (v->nrm[1], -gn / len, 2e-5);
            assert_near (v->nrm[2], 1 / len, 2e-5);
        }
    im_terrain_mesh_fini (&m);
    cgs_terrain_destroy (&t);
}

/* The checks of every chunk of a mesh built from t. */
static void s_check_chunks (const cgs_terrain_t *t, const im_terrain_mesh_t *m, int chunk_cells)
{
    const int cols = m->cols, rows = m->rows;
    const size_t nodes = (size_t)cols * (size_t)rows;
    // Every index is a vertex; the ranges account for every index once.
    for (size_t i = 0; i < m->nindices; i++)
        assert_true (m->indices[i] < m->nverts);
    assert_int_equal (m->nindices % 3, 0);
    unsigned char *used = calloc (m->nindices, 1);
    int *owner = calloc (nodes, sizeof *owner); // cells, by their south-west node
    assert_non_null (used);
    assert_non_null (owner);
    for (size_t k = 0; k < m->nchunks; k++) {
        const im_chunk_t *ch = &m->chunks[k];
        assert_true (ch->col0 >= 0 && ch->col0 < ch->col1 && ch->col1 < cols);
        assert_true (ch->row0 >= 0 && ch->row0 < ch->row1 && ch->row1 < rows);
        assert_true (ch->col1 - ch->col0 <= chunk_cells && ch->row1 - ch->row0 <= chunk_cells);
        for (int r = ch->row0; r < ch->row1; r++)
            for (int c = ch->col0; c < ch->col1; c++)
                owner[(size_t)r * (size_t)cols + (size_t)c]++;
        // The box: the chunk's nodes, from the lowest less the skirt to the highest.
        double hmin = INFINITY, hmax = -INFINITY;
        for (int r = ch->row0; r <= ch->row1; r++)
            for (int c = ch->col0; c <= ch->col1; c++) {
                hmin = fmin (hmin, cgs_terrain_node (t, c, r));
                hmax = fmax (hmax, cgs_terrain_node (t, c, r));
            }
        assert_near (ch->lo.e_m, m->e0_m + ch->col0 * m->res_m, 1e-9);
        assert_near (ch->hi.e_m, m->e0_m + ch->col1 * m->res_m, 1e-9);
        assert_near (ch->lo.n_m, m->n0_m + ch->row0 * m->res_m, 1e-9);
        assert_near (ch->hi.n_m, m->n0_m + ch->row1 * m->res_m, 1e-9);
        assert_near (ch->lo.u_m, hmin - m->skirt_m, 1e-6);
        assert_near (ch->hi.u_m, hmax, 1e-6);
        const int cc = ch->col1 - ch->col0, cr = ch->row1 - ch->row0;
        size_t prev_surface = 0, prev_count = 0;
        for (int l = 0; l < m->lods; l++) {
            const size_t first = ch->first[l], count = ch->count[l];
            assert_true (first + count <= m->nindices);
            assert_int_equal (count % 3, 0);
            int step = 1 << l;
            // The nodes level l takes along each side: every 2^l-th and the last.
            int nc = (cc + step - 1) / step, nr = (cr + step - 1) / step; // its cells
            size_t surface = 0, skirt = 0;
            double area2 = 0;
            for (size_t i = first; i < first + count; i += 3) {
                assert_false (used[i]);
                used[i] = used[i + 1] = used[i + 2] = 1;
                const uint32_t *tri = &m->indices[i];
                double p[3][3];
                int twins = 0;
                for (int j = 0; j < 3; j++) {
                    s_pos (m, tri[j], p[j]);
                    // Inside the chunk's box.
                    assert_true (p[j][0] >= ch->lo.e_m - 1e-3 && p[j][0] <= ch->hi.e_m + 1e-3);
                    assert_true (p[j][1] >= ch->lo.n_m - 1e-3 && p[j][1] <= ch->hi.n_m + 1e-3);
                    assert_true (p[j][2] >= ch->lo.u_m - 1e-3 && p[j][2] <= ch->hi.u_m + 1e-3);
                    uint32_t node = tri[j] >= nodes ? tri[j] - (uint32_t)nodes : tri[j];
                    twins += tri[j] >= nodes;
                    int c = (int)(node % (uint32_t)cols), r = (int)(node / (uint32_t)cols);
                    assert_true (c >= ch->col0 && c <= ch->col1 && r >= ch->row0 && r <= ch->row1);
                    // A node of the level.
                    assert_true ((c - ch->col0) % step == 0 || c == ch->col1);
                    assert_true ((r - ch->row0) % step == 0 || r == ch->row1);
                    // A skirt hangs from the chunk's edge.
                    if (tri[j] >= nodes)
                        assert_true (c == ch->col0 || c == ch->col1 || r == ch->row0 ||
                                     r == ch->row1);
                }
                if (twins == 0) {
                    surface++;
                    double a2 = s_area2_up (p[0], p[1], p[2]);
                    assert_true (a2 > 0); // counter-clockwise seen from above
                    area2 += a2;
                } else {
                    skirt++;
                    assert_true (twins == 1 || twins == 2);
                    // The wall is vertical: its corners lie on one edge line;
                    // it faces out of the chunk.
                    assert_near (s_area2_up (p[0], p[1], p[2]), 0, 1e-2);
                    double u[3], w[3];
                    for (int j = 0; j < 3; j++)
                        u[j] = p[1][j] - p[0][j], w[j] = p[2][j] - p[0][j];
                    double ne = u[1] * w[2] - u[2] * w[1], nn = u[2] * w[0] - u[0] * w[2];
                    double ge = (p[0][0] + p[1][0] + p[2][0]) / 3 - (ch->lo.e_m + ch->hi.e_m) / 2;
                    double gn = (p[0][1] + p[1][1] + p[2][1]) / 3 - (ch->lo.n_m + ch->hi.n_m) / 2;
                    assert_true (ne * ge + nn * gn > 0);
                }
            }
            // The surface: two triangles a cell, covering the chunk's area;
            // the skirt: two triangles an edge cell.
            assert_int_equal (surface, 2 * (size_t)nc * (size_t)nr);
            assert_int_equal (skirt, 2 * 2 * ((size_t)nc + (size_t)nr));
            assert_near (area2 / 2, cc * cr * m->res_m * m->res_m,
                         1e-6 * cc * cr * m->res_m * m->res_m);
            if (l == 0) {
                assert_int_equal (count,
                                  6 * (size_t)cc * (size_t)cr + 12 * ((size_t)cc + (size_t)cr));
            }
            // A quarter of the triangles of the level before, when the cells halve evenly.
            if (l > 0 && cc % step == 0 && cr % step == 0) {
                assert_int_equal (4 * surface, prev_surface);
                assert_true (2 * count < prev_count); // skirts included, it shrinks 2.4–4 times
            }
            prev_surface = surface;
            prev_count = count;
        }
        // Level 0: each of the chunk's cells is covered by exactly two triangles.
        int *cover = calloc ((size_t)cc * (size_t)cr, sizeof *cover);
        assert_non_null (cover);
        for (size_t i = ch->first[0]; i < ch->first[0] + ch->count[0]; i += 3) {
            const uint32_t *tri = &m->indices[i];
            if (tri[0] >= nodes || tri[1] >= nodes || tri[2] >= nodes)
                continue;
            int cmin = cols, rmin = rows, cmax = -1, rmax = -1;
            for (int j = 0; j < 3; j++) {
                int c = (int)(tri[j] % (uint32_t)cols), r = (int)(tri[j] / (uint32_t)cols);
                cmin = c < cmin ? c : cmin, cmax = c > cmax ? c : cmax;
                rmin = r < rmin ? r : rmin, rmax = r > rmax ? r : rmax;
            }
            assert_int_equal (cmax - cmin, 1);
            assert_int_equal (rmax - rmin, 1);
            cover[(size_t)(rmin - ch->row0) * (size_t)cc + (size_t)(cmin - ch->col0)]++;
        }
        for (int i = 0; i < cc * cr; i++)
            assert_int_equal (cover[i], 2);
        free (cover);
    }
    // Chunks tile the grid: every cell in exactly one; every index in a range.
    for (int r = 0; r + 1 < rows; r++)
        for (int c = 0; c + 1 < cols; c++)
            assert_int_equal (owner[(size_t)r * (size_t)cols + (size_t)c], 1);
    for (size_t i = 0; i < m->nindices; i++)
        assert_true (used[i]);
    free (used);
    free (owner);
}

/* 65 × 65 nodes, chunks of 16, 3 levels: 4 × 4 chunks, each 16 × 16 cells,
 * level 0 1536 + 384 indices, level 1 384 + 192, level 2 96 + 96. */
static void test_mesh_chunks (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_terrain (65, 65, -1000, 500, 30, s_hills);
    im_terrain_mesh_t m;
    assert_int_equal (im_terrain_mesh_build (t, 16, 3, &m), 0);
    assert_int_equal (m.nchunks, 16);
    for (size_t k = 0; k < m.nchunks; k++) {
        assert_int_equal (m.chunks[k].count[0], 1920);
        assert_int_equal (m.chunks[k].count[1], 576);
        assert_int_equal (m.chunks[k].count[2], 192);
    }
    s_check_chunks (t, &m, 16);
    im_terrain_mesh_fini (&m);
    cgs_terrain_destroy (&t);
}

/* Grids whose size is not a multiple of the chunk: partial chunks at the
 * east and north edges, levels coarser than the chunk. */
static void test_mesh_chunks_uneven (void **state)
{
    (void)state;
    static const int cases[][4] = {
        // cols, rows, chunk_cells, lods
        {70, 45, 16, 4}, {2, 2, 2, 1},    {9, 9, 2, 6},    {66, 66, 16, 3},
        {41, 23, 8, 5},  {30, 30, 32, 6}, {17, 100, 4, 3},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cgs_terrain_t *t = s_terrain (cases[i][0], cases[i][1], 100, -200, 7.5, s_hills);
        im_terrain_mesh_t m;
        assert_int_equal (im_terrain_mesh_build (t, cases[i][2], cases[i][3], &m), 0);
        int cells = cases[i][2];
        size_t want =
            (size_t)((cases[i][0] - 2) / cells + 1) * (size_t)((cases[i][1] - 2) / cells + 1);
        assert_int_equal (m.nchunks, want);
        s_check_chunks (t, &m, cells);
        im_terrain_mesh_fini (&m);
        cgs_terrain_destroy (&t);
    }
}

/* The level for a chunk: 0 within lod_distance of its box, then one more
 * for every doubling of the distance (1.5·L → 1, 3·L → 2, 6·L → 3), never
 * beyond the last level. The distance is to the box, from any side. */
static void test_chunk_lod (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_terrain (65, 65, -1000, 500, 30, s_hills);
    im_terrain_mesh_t m;
    assert_int_equal (im_terrain_mesh_build (t, 16, 4, &m), 0);
    const im_chunk_t *c = &m.chunks[5];
    const double L = 700;
    cgs_enu_t mid = {(c->lo.e_m + c->hi.e_m) / 2, (c->lo.n_m + c->hi.n_m) / 2,
                     (c->lo.u_m + c->hi.u_m) / 2};
    assert_int_equal (im_chunk_lod (&m, c, mid, L), 0);
    static const double dist[] = {0, 0.5, 0.99, 1.5, 1.9, 2.5, 3.9, 4.5, 7, 12, 100, 1e4};
    static const int want[] = {0, 0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 3};
    for (size_t i = 0; i < sizeof dist / sizeof dist[0]; i++) {
        double d = dist[i] * L;
        cgs_enu_t eyes[4] = {
            {mid.e_m, mid.n_m, c->hi.u_m + d}, // above
            {c->hi.e_m + d, mid.n_m, mid.u_m}, // east
            {mid.e_m, c->lo.n_m - d, mid.u_m}, // south
            {c->lo.e_m - d / sqrt (3), c->hi.n_m + d / sqrt (3), c->hi.u_m + d / sqrt (3)},
        };
        for (int k = 0; k < 4; k++)
            if (im_chunk_lod (&m, c, eyes[k], L) != want[i])
                fail_msg ("distance %g·L from side %d: level %d, expected %d", dist[i], k,
                          im_chunk_lod (&m, c, eyes[k], L), want[i]);
    }
    // Fewer levels: the clamp follows.
    im_terrain_mesh_fini (&m);
    assert_int_equal (im_terrain_mesh_build (t, 16, 2, &m), 0);
    c = &m.chunks[0];
    cgs_enu_t far = {c->hi.e_m + 100 * L, c->hi.n_m, c->hi.u_m};
    assert_int_equal (im_chunk_lod (&m, c, far, L), 1);
    im_terrain_mesh_fini (&m);
    assert_int_equal (im_terrain_mesh_build (t, 16, 1, &m), 0);
    assert_int_equal (im_chunk_lod (&m, &m.chunks[0], far, L), 0);
    im_terrain_mesh_fini (&m);
    cgs_terrain_destroy (&t);
}

/* Chunk sizes that are not a power of two in 2..1024, level counts outside
 * 1..IM_MAX_LODS and no terrain are refused, *ret untouched. */
static void test_mesh_rejects (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_terrain (65, 65, 0, 0, 30, s_hills);
    im_terrain_mesh_t m, before;
    memset (&m, 0x5a, sizeof m);
    before = m;
    static const int bad_cells[] = {0, 1, 3, 5, 6, 12, 24, 48, 100, 1000, 2048, -2, -16};
    for (size_t i = 0; i < sizeof bad_cells / sizeof bad_cells[0]; i++) {
        if (im_terrain_mesh_build (t, bad_cells[i], 3, &m) != -EINVAL)
            fail_msg ("chunk_cells %d accepted", bad_cells[i]);
        assert_memory_equal (&m, &before, sizeof m);
    }
    assert_int_equal (im_terrain_mesh_build (t, 16, 0, &m), -EINVAL);
    assert_int_equal (im_terrain_mesh_build (t, 16, IM_MAX_LODS + 1, &m), -EINVAL);
    assert_int_equal (im_terrain_mesh_build (t, 16, -1, &m), -EINVAL);
    assert_int_equal (im_terrain_mesh_build (NULL, 16, 3, &m), -EINVAL);
    assert_int_equal (im_terrain_mesh_build (t, 16, 3, NULL), -EINVAL);
    assert_memory_equal (&m, &before, sizeof m);
    // Every power of two in range is taken, and the last level count.
    for (int cells = 2; cells <= 1024; cells *= 2) {
        assert_int_equal (im_terrain_mesh_build (t, cells, IM_MAX_LODS, &m), 0);
        im_terrain_mesh_fini (&m);
    }
    cgs_terrain_destroy (&t);
}

/* The largest vertical gap along the chunks' edges between the outline
 * level l draws (every 2^l-th node of the edge and its last, straight in
 * between) and the one level l + 1 draws: the crack two neighbouring chunks
 * at those levels leave. Both outlines are straight between the nodes of
 * level l, so the largest gap is at one of them. */
static double s_edge_crack (const cgs_terrain_t *t, const im_terrain_mesh_t *m, int l)
{
    double worst = 0;
    for (size_t k = 0; k < m->nchunks; k++) {
        const im_chunk_t *c = &m->chunks[k];
        for (int side = 0; side < 4; side++) {
            bool along_row = side < 2;
            int a = along_row ? c->col0 : c->row0, b = along_row ? c->col1 : c->row1;
            int fixed = side == 0 ? c->row0 : side == 1 ? c->row1 : side == 2 ? c->col0 : c->col1;
            for (int i = a; i <= b; i++) {
                double v[2];
                for (int q = 0; q < 2; q++) {
                    int s = 1 << (l + q);
                    int i0 = a + (i - a) / s * s, i1 = i0 + s < b ? i0 + s : b;
                    double h0 = along_row ? cgs_terrain_node (t, i0, fixed)
                                          : cgs_terrain_node (t, fixed, i0);
                    double h1 = along_row ? cgs_terrain_node (t, i1, fixed)
                                          : cgs_terrain_node (t, fixed, i1);
                    double f = i1 > i0 ? (double)(i - i0) / (i1 - i0) : 0;
                    v[q] = h0 + f * (h1 - h0);
                }
                worst = fmax (worst, fabs (v[0] - v[1]));
            }
        }
    }
    return worst;
}

/* The skirts hide the cracks: a chunk drawn at level l beside one at level
 * l + 1 (neighbours differ by a level) leaves a vertical gap along their
 * shared edge; the skirt hanging skirt_m below either edge covers it only
 * when skirt_m is at least the gap. Checked on fBm terrain 10 km square at
 * 30 m with the shipped chunks (32 cells, 5 levels): the default
 * scenario's rolling hills (relief 250 m, hills of 4 km), and mountains
 * (relief 1000 m, hills of 2 km: steep country, as a real DEM may hold). */
static void test_skirt_hides_cracks (void **state)
{
    (void)state;
    static const struct {
        const char *name;
        double relief_m, feature_m;
    } cases[] = {{"rolling hills", 250, 4000}, {"mountains", 1000, 2000}};
    char why[1024] = "";
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cgs_terrain_fbm_t p;
        cgs_terrain_fbm_defaults (&p);
        p.seed = 11;
        p.size_m = 10000;
        p.resolution_m = 30;
        p.relief_m = cases[i].relief_m;
        p.feature_m = cases[i].feature_m;
        cgs_terrain_t *t = cgs_terrain_new_fbm (&p);
        assert_non_null (t);
        im_terrain_mesh_t m;
        assert_int_equal (im_terrain_mesh_build (t, 32, 5, &m), 0);
        for (int l = 0; l + 1 < m.lods; l++) {
            double gap = s_edge_crack (t, &m, l);
            size_t at = strlen (why);
            if (gap > m.skirt_m && at < sizeof why)
                snprintf (why + at, sizeof why - at,
                          "\n%s: levels %d and %d leave a crack of %.1f m, the skirt is %.1f m",
                          cases[i].name, l, l + 1, gap, m.skirt_m);
        }
        im_terrain_mesh_fini (&m);
        cgs_terrain_destroy (&t);
    }
    if (why[0])
        fail_msg ("cracks deeper than the skirt:%s", why);
}

/* ---- models ------------------------------------------------------------------------------- */

static const char *const s_kind_names[] = {"other", "tracked", "wheeled", "air", "person"};

/* For every kind: the vertices span exactly the extent (width along x,
 * length along y, height along z from 0), centred on the origin across and
 * along; the model's extent fields are im_model_extent's. */
static void test_model_extent (void **state)
{
    (void)state;
    char why[2048] = "";
    for (int k = CGS_KIND_OTHER; k <= CGS_KIND_PERSON; k++) {
        im_model_t m;
        assert_int_equal (im_model_build ((cgs_kind_t)k, &m), 0);
        double len, wid, hgt;
        im_model_extent ((cgs_kind_t)k, &len, &wid, &hgt);
        assert_true (len > 0 && wid > 0 && hgt > 0);
        assert_near (m.length_m, len, 0);
        assert_near (m.width_m, wid, 0);
        assert_near (m.height_m, hgt, 0);
        assert_true (m.nverts > 0 && m.nverts % 3 == 0);
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < m.nverts; i++)
            for (int j = 0; j < 3; j++) {
                lo[j] = fmin (lo[j], m.verts[i].pos[j]);
                hi[j] = fmax (hi[j], m.verts[i].pos[j]);
            }
        im_model_fini (&m);
        assert_null (m.verts);
        assert_int_equal (m.nverts, 0);
        // Every kind is checked before the test fails.
        const char *name = s_kind_names[k];
        size_t at = strlen (why);
        if (fabs (hi[0] - lo[0] - wid) > 1e-5 || fabs (hi[1] - lo[1] - len) > 1e-5 ||
            fabs (lo[2]) > 1e-5 || fabs (hi[2] - hgt) > 1e-5)
            at += (size_t)snprintf (why + at, sizeof why - at,
                                    "\n%s: x %g..%g, y %g..%g, z %g..%g; extent: width %g, "
                                    "length %g, height %g from 0",
                                    name, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2], wid, len, hgt);
        if (at < sizeof why && (fabs (lo[0] + hi[0]) > 1e-5 || fabs (lo[1] + hi[1]) > 1e-5))
            snprintf (why + at, sizeof why - at,
                      "\n%s: not centred on the origin: x %g..%g, y %g..%g", name, lo[0], hi[0],
                      lo[1], hi[1]);
    }
    im_model_fini (NULL);
    if (why[0])
        fail_msg ("models against their extent:%s", why);
}

/* For every kind: each triangle's winding gives its stored normal (the
 * cross product (b − a) × (c − a) points along it: counter-clockwise seen
 * from outside); the normal is unit and the same at the three corners.
 * Models are made of boxes, 36 vertices each: each box is closed and
 * outward (its divergence-theorem volume equals its box's volume, and every
 * face's normal points away from the box's centre). Materials are a
 * model's (hull, engine, running gear, glass, person: never ground), whole
 * numbers; a person is all person; vehicles have an engine and running gear. */
static void test_model_faces (void **state)
{
    (void)state;
    for (int k = CGS_KIND_OTHER; k <= CGS_KIND_PERSON; k++) {
        im_model_t m;
        assert_int_equal (im_model_build ((cgs_kind_t)k, &m), 0);
        const char *name = s_kind_names[k];
        int mats[6] = {0};
        for (size_t i = 0; i < m.nverts; i += 3) {
            const im_vertex_t *v = &m.verts[i];
            double a[3], b[3], n[3];
            for (int j = 0; j < 3; j++) {
                a[j] = v[1].pos[j] - v[0].pos[j];
                b[j] = v[2].pos[j] - v[0].pos[j];
            }
            n[0] = a[1] * b[2] - a[2] * b[1];
            n[1] = a[2] * b[0] - a[0] * b[2];
            n[2] = a[0] * b[1] - a[1] * b[0];
            double ln = sqrt (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            assert_true (ln > 0);
            for (int c = 0; c < 3; c++) {
                double sn = sqrt (v[c].nrm[0] * v[c].nrm[0] + v[c].nrm[1] * v[c].nrm[1] +
                                  v[c].nrm[2] * v[c].nrm[2]);
                assert_near (sn, 1, 1e-6);
                double cosang = (n[0] * v[c].nrm[0] + n[1] * v[c].nrm[1] + n[2] * v[c].nrm[2]) / ln;
                if (!(cosang > 0.9999))
                    fail_msg ("%s: triangle %zu: winding normal (%g, %g, %g) against stored "
                              "(%g, %g, %g)",
                              name, i / 3, n[0] / ln, n[1] / ln, n[2] / ln, v[c].nrm[0],
                              v[c].nrm[1], v[c].nrm[2]);
                assert_near (v[c].mat, v[0].mat, 0);
            }
            float mat = v[0].mat;
            assert_near (mat, floorf (mat), 0);
            assert_true (mat >= IM_MAT_HULL && mat <= IM_MAT_PERSON);
            mats[(int)mat]++;
        }
        if (k == CGS_KIND_PERSON)
            assert_int_equal (mats[IM_MAT_PERSON], (int)m.nverts / 3);
        else
            assert_int_equal (mats[IM_MAT_PERSON], 0);
        if (k == CGS_KIND_TRACKED || k == CGS_KIND_WHEELED) {
            assert_true (mats[IM_MAT_ENGINE] > 0 && mats[IM_MAT_RUNNING] > 0);
            assert_true (mats[IM_MAT_HULL] > 0 && mats[IM_MAT_GLASS] > 0);
        }
        if (k != CGS_KIND_PERSON)
            assert_true (mats[IM_MAT_ENGINE] > 0);

        // Boxes: closed, outward.
        assert_int_equal (m.nverts % 36, 0);
        for (size_t b0 = 0; b0 < m.nverts; b0 += 36) {
            double lo[3] = {INFINITY, INFINITY, INFINITY},
                   hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (size_t i = b0; i < b0 + 36; i++)
                for (int j = 0; j < 3; j++) {
                    lo[j] = fmin (lo[j], m.verts[i].pos[j]);
                    hi[j] = fmax (hi[j], m.verts[i].pos[j]);
                }
            double ctr[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
            double vol = 0;
            for (size_t i = b0; i < b0 + 36; i += 3) {
                const im_vertex_t *v = &m.verts[i];
                double p[3][3];
                for (int c = 0; c < 3; c++)
                    for (int j = 0; j < 3; j++)
                        p[c][j] = v[c].pos[j] - ctr[j];
                // Signed volume of the tetrahedron (centre, a, b, c).
                vol += (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                        p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                        p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) /
                       6;
                double g[3] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3,
                               (p[0][2] + p[1][2] + p[2][2]) / 3};
                double out = g[0] * v[0].nrm[0] + g[1] * v[0].nrm[1] + g[2] * v[0].nrm[2];
                if (!(out > 0))
                    fail_msg ("%s: box %zu: a face's normal points into the box", name, b0 / 36);
            }
            double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
            assert_true (box > 0);
            assert_near (vol, box, 1e-4 * box);
        }
        im_model_fini (&m);
    }
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_mesh_vertices),      cmocka_unit_test (test_mesh_normals),
        cmocka_unit_test (test_mesh_chunks),        cmocka_unit_test (test_mesh_chunks_uneven),
        cmocka_unit_test (test_chunk_lod),          cmocka_unit_test (test_mesh_rejects),
        cmocka_unit_test (test_skirt_hides_cracks), cmocka_unit_test (test_model_extent),
        cmocka_unit_test (test_model_faces),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
