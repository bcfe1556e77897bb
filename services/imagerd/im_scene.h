/* im_scene — what imagerd draws, built on the CPU: the terrain as a mesh in
 * square chunks, each with its bounding box and index ranges for several
 * levels of detail (every node, every 2nd, every 4th ...) and a skirt that
 * hides the cracks between neighbours at different levels; and a simple 3-D
 * model for each kind of entity (tracked, wheeled, UAV, person, other) made
 * of boxes, each face tagged with the material its infrared temperature comes
 * from. Pure: no GL, no logging. */
#ifndef IM_SCENE_H
#define IM_SCENE_H

#include "cgs_geo.h"
#include "cgs_scenario.h"
#include "cgs_terrain.h"

#include <stddef.h>
#include <stdint.h>

/* Materials (a vertex's last attribute). */
typedef enum {
    IM_MAT_GROUND = 0,  // terrain
    IM_MAT_HULL = 1,    // a vehicle's body
    IM_MAT_ENGINE = 2,  // engine deck or exhaust: hot while running
    IM_MAT_RUNNING = 3, // tracks, wheels: warm from running
    IM_MAT_GLASS = 4,   // windows, optics: cold in the infrared
    IM_MAT_PERSON = 5,  // a person: body temperature
} im_material_t;

/* One vertex: position (local frame, or model axes: x right, y forward,
 * z up), unit normal, material. */
typedef struct {
    float pos[3];
    float nrm[3];
    float mat;
} im_vertex_t;

#define IM_MAX_LODS 6

typedef struct {
    int col0, row0, col1, row1;                      // its nodes, inclusive
    cgs_enu_t lo, hi;                                // bounding box (skirt included)
    uint32_t first[IM_MAX_LODS], count[IM_MAX_LODS]; // index range of each level
} im_chunk_t;

typedef struct {
    int cols, rows;
    double e0_m, n0_m, res_m;
    im_vertex_t *verts; // cols × rows nodes, then their skirt twins
    size_t nverts;
    uint32_t *indices; // triangles
    size_t nindices;
    im_chunk_t *chunks;
    size_t nchunks;
    int lods;
    double skirt_m;
} im_terrain_mesh_t;

/* Build the mesh of terrain t in chunks of chunk_cells × chunk_cells cells
 * (a power of two, 2..1024) with lods levels (1..IM_MAX_LODS; level l takes
 * every 2^l-th node, and the chunk's last row and column always). 0,
 * -EINVAL or -ENOMEM; *ret is filled only on success. */
int im_terrain_mesh_build (const cgs_terrain_t *t, int chunk_cells, int lods,
                           im_terrain_mesh_t *ret);
void im_terrain_mesh_fini (im_terrain_mesh_t *m);
/* The level of detail for a chunk seen from eye: 0 within lod_distance_m of
 * its box, one level coarser for every doubling of the distance beyond. */
int im_chunk_lod (const im_terrain_mesh_t *m, const im_chunk_t *c, cgs_enu_t eye,
                  double lod_distance_m);

/* A model: triangles in model axes (x right, y forward, z up, origin on the
 * ground at the model's centre). */
typedef struct {
    im_vertex_t *verts;
    size_t nverts;
    double length_m, width_m, height_m; // its extent
} im_model_t;

/* The extent of a kind's model: length (along its heading), width, height. */
void im_model_extent (cgs_kind_t kind, double *ret_length_m, double *ret_width_m,
                      double *ret_height_m);
/* The model of an entity kind. 0 or -ENOMEM. */
int im_model_build (cgs_kind_t kind, im_model_t *ret);
void im_model_fini (im_model_t *m);

#endif
