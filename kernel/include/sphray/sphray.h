/* sphray's C API: the same queries as the C++ API (sphray.hpp), through a stable C ABI, for
 * tracers written in C, Rust, Zig, Julia, .NET or anything else with a C foreign-function
 * interface. C99; includable from C and C++; no C++ type crosses it.
 *
 *   sphray_scene* scene;
 *   if (sphray_scene_create(cx, cy, cz, r, n, 0, NULL, &scene) != SPHRAY_OK)
 *     fprintf(stderr, "%s\n", sphray_last_error());
 *   sphray_intersect(scene, rays, ray_count, hits, NULL);  // hits[i].id == SPHRAY_NO_HIT: a miss
 *   sphray_scene_release(scene);
 *
 * Every query takes its arguments in one order: the scene, what it is asked about (rays or
 * points) and their count, the query's own parameters, the outputs, and last the options
 * (sphray_query_args; NULL for the defaults), as Embree's rtcIntersect takes its
 * RTCIntersectArguments.
 *
 * The contract is the C++ API's (docs/kernel.md) and so are the results, bit for bit: these
 * functions only check their arguments and forward to it. Every function that can fail
 * returns SPHRAY_OK (0) or one of the error codes below and then sets a message for the
 * calling thread (sphray_last_error()); none throws, aborts or crashes on bad arguments.
 * Empty work is success: a count of 0 reads and writes nothing (its arrays may be NULL; the
 * scene must still be live and the options valid), and a scene of 0 spheres answers every ray
 * with a miss.
 * Threading: any number of threads may query the same scene at once. sphray_scene_refit while
 * other threads query the scene is safe but racy: it writes the new values over the scene's
 * own arrays in place, so such a query reads each sphere's values old or new (possibly a mix
 * of both) and never freed memory; call it between queries for consistent answers. create,
 * set_masks and release must not run concurrently with anything else on the same scene.
 * ABI: docs/kernel.md, "From C and other languages"; the library's SONAME is libsphray.so.1. */
#ifndef SPHRAY_SPHRAY_H
#define SPHRAY_SPHRAY_H

#include <stddef.h>
#include <stdint.h>

#include "sphray/api.h"
#include "sphray/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes. Values never change; new codes may be added. */
#define SPHRAY_OK 0
#define SPHRAY_ERROR_NULL_POINTER 1     /* a required pointer argument is NULL */
#define SPHRAY_ERROR_INVALID_ARGUMENT 2 /* a bad stride, accel, alignment or count */
#define SPHRAY_ERROR_TOO_LARGE 3        /* a count over the library's limits */
#define SPHRAY_ERROR_OUT_OF_MEMORY 4    /* an allocation failed; nothing was changed */
#define SPHRAY_ERROR_RELEASED_SCENE 5   /* the scene handle was released */
#define SPHRAY_ERROR_INTERNAL 6         /* anything else the library caught; a bug */
#define SPHRAY_ERROR_PRECISION 7        /* a float call on a double scene, or the other way */

/* How a scene answers queries. AUTO: a BVH from 128 spheres on, brute force below (the
 * renderer's measured crossover, docs/bvh.md). Both give the same hits, bit for bit. */
#define SPHRAY_ACCEL_AUTO 0
#define SPHRAY_ACCEL_BRUTE 1
#define SPHRAY_ACCEL_BVH 2

/* Instruction sets, for sphray_scene_args.isa. AUTO: the one sphray_bvh_isa(count) names. */
#define SPHRAY_ISA_AUTO 0
#define SPHRAY_ISA_SCALAR 1
#define SPHRAY_ISA_SSE4_2 2
#define SPHRAY_ISA_AVX2 3
#define SPHRAY_ISA_AVX512 4
#define SPHRAY_ISA_NEON 5

/* The id of a miss. */
#define SPHRAY_NO_HIT 0xffffffffu

/* The points (ox, oy, oz) + t (dx, dy, dz) for tmin < t < tmax. The direction need not be unit
 * length. For an infinite tmax use INFINITY (math.h). */
typedef struct sphray_ray {
  float ox, oy, oz;
  float dx, dy, dz;
  float tmin, tmax;
} sphray_ray;

/* A closest hit: sphere id and ray parameter t; a miss has id == SPHRAY_NO_HIT, t == tmax. */
typedef struct sphray_hit {
  float t;
  uint32_t id;
} sphray_hit;

/* Where a ray meets its hit sphere: the point on the sphere, the outward unit normal,
 * front_face (1: the ray arrived from outside, 0 otherwise) and the point's error bound per
 * coordinate, which sphray_spawn() uses. A miss gives point = the ray at tmax, normal and
 * error 0, front_face 0. */
typedef struct sphray_hit_surface {
  float px, py, pz;
  float nx, ny, nz;
  float ex, ey, ez;
  int32_t front_face;
} sphray_hit_surface;

/* A scene: an owned copy of the spheres, and the BVH when it has one. Opaque. */
typedef struct sphray_scene sphray_scene;

/* "0.3.0": the loaded library's version (not the ABI's: that is the SONAME's 2), as
 * SPHRAY_VERSION_STRING was when it was built. */
SPHRAY_API const char* sphray_version(void);

/* The loaded library's SPHRAY_VERSION_NUMBER (10000 major + 100 minor + patch). A program can
 * check that it runs against the version it was built with, or a later one:
 *   if (sphray_version_number() < SPHRAY_VERSION_NUMBER) ... */
SPHRAY_API int sphray_version_number(void);

/* The instruction set the queries run on: "scalar", "sse4.2", "avx2", "avx512" or "neon"
 * (SPHRAY_ISA in the environment forces one, as for the C++ API). */
SPHRAY_API const char* sphray_active_isa(void);

/* The instruction set the BVH of a scene of sphere_count spheres is laid out for and walked
 * with, named as above: the one that walks trees of that size fastest on this CPU (by a rule on
 * its vendor and family), or SPHRAY_ISA's. */
SPHRAY_API const char* sphray_bvh_isa(size_t sphere_count);

/* The message of the last failure on the calling thread ("" if none yet). A successful call
 * leaves it as it was: read it only after a non-zero status. Valid until the thread's next
 * call into the library. */
SPHRAY_API const char* sphray_last_error(void);

/* A fixed name for a status code: "SPHRAY_OK", "SPHRAY_ERROR_NULL_POINTER", ... */
SPHRAY_API const char* sphray_status_name(int status);

/* How a scene is built, beyond its spheres. Start from SPHRAY_SCENE_ARGS_INIT (struct_size set,
 * every option its default) and change what you need; a NULL sphray_scene_args* means the
 * defaults. struct_size lets later versions add fields at the end without breaking programs
 * built against this header.
 *   accel: SPHRAY_ACCEL_AUTO (default), _BRUTE or _BVH.
 *   isa:   SPHRAY_ISA_AUTO (default: the process's choice, as sphray_bvh_isa(count) names it,
 *          SPHRAY_ISA in the environment included), or one instruction set, which the scene is
 *          laid out for and queried with, whatever the environment says. With AUTO accel a
 *          chosen set gives the scene a tree at every size (a small one is built flat and
 *          answers as brute force on that set's batches); _BRUTE with a chosen set is an
 *          invalid argument, since brute force runs on the process's choice. The results are
 *          the same bits on every set. */
typedef struct sphray_scene_args {
  size_t struct_size; /* sizeof(sphray_scene_args) */
  int accel;
  int isa;
} sphray_scene_args;
#define SPHRAY_SCENE_ARGS_INIT \
  { sizeof(sphray_scene_args), SPHRAY_ACCEL_AUTO, SPHRAY_ISA_AUTO }

/* 1 if this build has the instruction set (a SPHRAY_ISA_ value) and this machine runs it, else
 * 0: the sets a scene may be given. SPHRAY_ISA_AUTO and SPHRAY_ISA_SCALAR always give 1. */
SPHRAY_API int sphray_isa_supported(int isa);

/* Copies count spheres into a new scene: sphere i has centre (cx[i], cy[i], cz[i]), radius r[i]
 * and id i. stride_bytes is the distance between consecutive values of each array: 0 for
 * packed floats (4), or e.g. sizeof(struct my_sphere) to read an array of structures through
 * pointers to the first one's fields. The arrays may be freed after the call; with count 0 they
 * may be NULL (an empty scene: every ray misses). args: NULL, or the options above. Errors:
 * NULL pointer (any argument but args and the arrays of an empty scene), invalid argument
 * (stride not 0 and not a positive multiple of 4, a pointer not aligned for float, an unknown
 * accel or isa, an isa this machine cannot run, an isa with _BRUTE, a struct_size this library
 * does not know), too large (count over 2^32 - 1, the ids' range, or a tree that does not
 * fit), out of memory. On failure *out is untouched. */
SPHRAY_API int sphray_scene_create(const float* cx, const float* cy, const float* cz,
                                   const float* r, size_t count, size_t stride_bytes,
                                   const sphray_scene_args* args, sphray_scene** out);

/* The instruction set (a SPHRAY_ISA_ value, never AUTO) the scene's tree is laid out for and
 * walked with, in *isa; for a scene without a tree, the one brute force runs on
 * (sphray_active_isa(); views of a few spheres may take a narrower one, with the same bits). */
SPHRAY_API int sphray_scene_isa(const sphray_scene* scene, int* isa);

/* New centres and radii for the same spheres (same count, same ids): written over the scene's
 * copy in place, and a BVH refitted (its shape kept: docs/bvh.md). Masks are kept. Queries
 * running meanwhile on other threads do not crash (see "Threading" above). Same arguments and
 * errors as sphray_scene_create, and invalid argument when count differs from the scene's. */
SPHRAY_API int sphray_scene_refit(sphray_scene* scene, const float* cx, const float* cy,
                                  const float* cz, const float* r, size_t count,
                                  size_t stride_bytes);

/* Gives sphere i the 32-bit mask masks[i] (stride_bytes apart, 0 for packed), for every sphere
 * of the scene; masks NULL gives every sphere every bit again. A ray sees sphere i only if its
 * mask shares a bit with masks[i]: rays have every bit unless a query's sphray_query_args give
 * them masks (docs/queries.md, "Masks"). A tree takes the new masks without a
 * rebuild; sphray_scene_refit keeps them. Errors: invalid argument (stride not 0 and not a
 * positive multiple of 4, masks not aligned for uint32_t), out of memory. */
SPHRAY_API int sphray_scene_set_masks(sphray_scene* scene, const uint32_t* masks,
                                      size_t stride_bytes);

/* The scene's sphere count, in *count. */
SPHRAY_API int sphray_scene_size(const sphray_scene* scene, size_t* count);

/* Frees the scene's spheres and tree. The handle then reports SPHRAY_ERROR_RELEASED_SCENE
 * wherever it is passed, for good: no later sphray_scene_create returns it again. */
SPHRAY_API int sphray_scene_release(sphray_scene* scene);

/* A query's options. Start from SPHRAY_QUERY_ARGS_INIT (struct_size set, every option its
 * default) and change what you need; a NULL sphray_query_args* means the defaults. struct_size
 * lets later versions add fields at the end without breaking programs built against this
 * header.
 *   masks:   NULL (default): every ray has every bit; or one 32-bit mask per ray, masks[i] for
 *            ray i, which sees sphere j only if masks[i] & (sphere j's mask) != 0
 *            (sphray_scene_set_masks). Rays only: a point query refuses masks.
 *   threads: 0 or 1 (default): the calling thread alone; n: up to n threads, the calling one
 *            and n - 1 started for the call, in chunks of 4096 rays or points;
 *            SPHRAY_THREADS_ALL: one per core. The same results, in the same places, whatever
 *            the count. */
typedef struct sphray_query_args {
  size_t struct_size; /* sizeof(sphray_query_args) */
  const uint32_t* masks;
  unsigned threads;
} sphray_query_args;
#define SPHRAY_THREADS_ALL 0xffffffffu
#define SPHRAY_QUERY_ARGS_INIT \
  { sizeof(sphray_query_args), NULL, 0 }

/* Errors of every query that takes sphray_query_args, beyond its own: invalid argument when
 * args->struct_size is not one this library knows, or masks are given to a point query. */

/* hits[i] = the closest hit of rays[i], for i < count. */
SPHRAY_API int sphray_intersect(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                                sphray_hit* hits, const sphray_query_args* args);

/* occluded[i] = 1 if rays[i] hits any sphere in (tmin, tmax), else 0. On a scene with a BVH,
 * coherent rays (shadow rays towards one light from neighbouring hits) go through it in
 * packets, as the C++ stream call takes them; each answer is still the single ray's. */
SPHRAY_API int sphray_occluded(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                               unsigned char* occluded, const sphray_query_args* args);

/* Rays as one array per quantity, the layout a wavefront tracer keeps its paths in: ray i goes
 * from (ox[i], oy[i], oz[i]) along (dx[i], dy[i], dz[i]) for tmin[i] < t < tmax[i]. tmin and
 * tmax may be NULL: every ray then takes 0 and INFINITY. */
typedef struct sphray_ray_arrays {
  const float *ox, *oy, *oz;
  const float *dx, *dy, *dz;
  const float *tmin, *tmax;
} sphray_ray_arrays;

/* t[i], id[i] = the closest hit of ray i of rays, for i < count: the hit sphray_intersect gives
 * the same ray, bit for bit, without packing the rays into sphray_ray structs. */
SPHRAY_API int sphray_intersect_arrays(const sphray_scene* scene, const sphray_ray_arrays* rays,
                                       size_t count, float* t, uint32_t* id,
                                       const sphray_query_args* args);

/* surfaces[i] = where rays[i] meets the sphere of hits[i] (a hit from sphray_intersect on the
 * same scene; a miss or an id outside the scene gives the miss surface). */
SPHRAY_API int sphray_surface(const sphray_scene* scene, const sphray_ray* rays,
                              const sphray_hit* hits, size_t count, sphray_hit_surface* surfaces);

/* rays[i] = the ray leaving surfaces[i] along the direction (dirs[3i], dirs[3i+1], dirs[3i+2])
 * (any non-zero length): its origin is offset past the surface's error bound so that it never
 * meets the sphere it leaves again (docs/kernel.md, "Leaving a surface"); tmin 0, tmax
 * infinity. */
SPHRAY_API int sphray_spawn(const sphray_hit_surface* surfaces, const float* dirs, size_t count,
                            sphray_ray* rays);

/* ---- Beyond the closest hit (docs/queries.md) ---- */

/* Every crossing of each ray with the spheres' surfaces in (tmin, tmax): for ray i, the first
 * max_hits crossings, sorted by t, then id, then entry before exit, into
 * hits[i * max_hits .. (i + 1) * max_hits), exits[...] = 1 where the ray leaves its sphere
 * (exits may be NULL), and their total in counts[i] (larger than max_hits when they did not
 * fit; slots past the total are left as they were). max_hits 0: counts only, hits may be NULL.
 * The first crossing is sphray_intersect's hit. Errors as sphray_intersect, and too large when
 * count * max_hits exceeds the address space. Up to 64 hits per ray are gathered on the stack;
 * a larger max_hits makes the call allocate one buffer of max_hits slots per thread (out of
 * memory is then a possible error). */
SPHRAY_API int sphray_intersect_all(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                                    size_t max_hits, sphray_hit* hits, unsigned char* exits,
                                    size_t* counts, const sphray_query_args* args);

/* The nearest max_hits crossings of each ray alone: sphray_intersect_all's first max_hits, bit
 * for bit, into the same slots, with counts[i] = how many were written (at most max_hits), not
 * the total. Through a BVH the walk stops at the max_hits-th crossing found so far, as the
 * closest hit stops at the first (k-buffers, the first layers of transparency). Errors as
 * sphray_intersect_all. */
SPHRAY_API int sphray_intersect_nearest(const sphray_scene* scene, const sphray_ray* rays,
                                        size_t count, size_t max_hits, sphray_hit* hits,
                                        unsigned char* exits, size_t* counts,
                                        const sphray_query_args* args);

/* counts[i] = the number of crossings of rays[i] in (tmin, tmax). */
SPHRAY_API int sphray_count_hits(const sphray_scene* scene, const sphray_ray* rays, size_t count,
                                 size_t* counts, const sphray_query_args* args);

/* The sphere nearest a point by signed distance to its surface, |p - c| - r (negative inside),
 * among those at most max_distance away (INFINITY: any); id SPHRAY_NO_HIT, distance
 * max_distance and p itself when there is none. (px, py, pz): the closest surface point. */
typedef struct sphray_nearest_sphere {
  uint32_t id;
  float distance;
  float px, py, pz;
} sphray_nearest_sphere;

/* out[i] for the point (points[3i], points[3i + 1], points[3i + 2]), for i < count. */
SPHRAY_API int sphray_nearest(const sphray_scene* scene, const float* points, size_t count,
                              float max_distance, sphray_nearest_sphere* out,
                              const sphray_query_args* args);

/* inside[i] = 1 if point i lies inside any sphere (the open balls), else 0. */
SPHRAY_API int sphray_inside(const sphray_scene* scene, const float* points, size_t count,
                             unsigned char* inside, const sphray_query_args* args);

/* The ids of the spheres overlapping the ball (centre[0..2], radius), |c - centre| < r + radius,
 * ascending: the first capacity of them into ids (NULL when capacity is 0), and their number in
 * *total. A negative or NaN radius, or a NaN centre, gives *total = 0. One ball, so no count
 * and no options. */
SPHRAY_API int sphray_overlapping(const sphray_scene* scene, const float* centre, float radius,
                                  size_t capacity, uint32_t* ids, size_t* total);

/* ---- Double precision (docs/double.md) ----
 *
 * A scene holds its spheres in the precision it was created in: sphray_scene_create gives a
 * float scene, sphray_scene_create_d a double one. A double scene answers the _d queries below,
 * with the C++ API's double kernel and its bits (no conversion anywhere); a float query on it,
 * or a _d query on a float scene, fails with SPHRAY_ERROR_PRECISION. sphray_scene_isa,
 * sphray_scene_set_masks, sphray_scene_size and sphray_scene_release take scenes of either
 * precision. */
#define SPHRAY_PRECISION_FLOAT 0
#define SPHRAY_PRECISION_DOUBLE 1

/* The scene's precision, SPHRAY_PRECISION_FLOAT or _DOUBLE, in *precision. */
SPHRAY_API int sphray_scene_precision(const sphray_scene* scene, int* precision);

/* sphray_ray, sphray_hit and sphray_hit_surface in double. */
typedef struct sphray_ray_d {
  double ox, oy, oz;
  double dx, dy, dz;
  double tmin, tmax;
} sphray_ray_d;

typedef struct sphray_hit_d {
  double t;
  uint32_t id;
} sphray_hit_d;

typedef struct sphray_hit_surface_d {
  double px, py, pz;
  double nx, ny, nz;
  double ex, ey, ez;
  int32_t front_face;
} sphray_hit_surface_d;

/* A double scene: as sphray_scene_create, with double arrays (stride_bytes 0 for packed
 * doubles, else a positive multiple of 8; pointers aligned for double). A sphere is valid in
 * double's range (docs/double.md, "The contract in double"). */
SPHRAY_API int sphray_scene_create_d(const double* cx, const double* cy, const double* cz,
                                     const double* r, size_t count, size_t stride_bytes,
                                     const sphray_scene_args* args, sphray_scene** out);

/* sphray_scene_refit for a double scene. */
SPHRAY_API int sphray_scene_refit_d(sphray_scene* scene, const double* cx, const double* cy,
                                    const double* cz, const double* r, size_t count,
                                    size_t stride_bytes);

/* sphray_ray_arrays in double. */
typedef struct sphray_ray_arrays_d {
  const double *ox, *oy, *oz;
  const double *dx, *dy, *dz;
  const double *tmin, *tmax;
} sphray_ray_arrays_d;

/* The queries above, on a double scene, with the same arguments in double. */
SPHRAY_API int sphray_intersect_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                                  sphray_hit_d* hits, const sphray_query_args* args);
SPHRAY_API int sphray_occluded_d(const sphray_scene* scene, const sphray_ray_d* rays, size_t count,
                                 unsigned char* occluded, const sphray_query_args* args);
SPHRAY_API int sphray_intersect_arrays_d(const sphray_scene* scene, const sphray_ray_arrays_d* rays,
                                         size_t count, double* t, uint32_t* id,
                                         const sphray_query_args* args);
SPHRAY_API int sphray_surface_d(const sphray_scene* scene, const sphray_ray_d* rays,
                                const sphray_hit_d* hits, size_t count,
                                sphray_hit_surface_d* surfaces);
SPHRAY_API int sphray_spawn_d(const sphray_hit_surface_d* surfaces, const double* dirs,
                              size_t count, sphray_ray_d* rays);
SPHRAY_API int sphray_intersect_all_d(const sphray_scene* scene, const sphray_ray_d* rays,
                                      size_t count, size_t max_hits, sphray_hit_d* hits,
                                      unsigned char* exits, size_t* counts,
                                      const sphray_query_args* args);
SPHRAY_API int sphray_intersect_nearest_d(const sphray_scene* scene, const sphray_ray_d* rays,
                                          size_t count, size_t max_hits, sphray_hit_d* hits,
                                          unsigned char* exits, size_t* counts,
                                          const sphray_query_args* args);
SPHRAY_API int sphray_count_hits_d(const sphray_scene* scene, const sphray_ray_d* rays,
                                   size_t count, size_t* counts, const sphray_query_args* args);

/* The point queries on a double scene: sphray_nearest_sphere in double, and the points (3
 * doubles each), distances and radii in double. */
typedef struct sphray_nearest_sphere_d {
  uint32_t id;
  double distance;
  double px, py, pz;
} sphray_nearest_sphere_d;
SPHRAY_API int sphray_nearest_d(const sphray_scene* scene, const double* points, size_t count,
                                double max_distance, sphray_nearest_sphere_d* out,
                                const sphray_query_args* args);
SPHRAY_API int sphray_inside_d(const sphray_scene* scene, const double* points, size_t count,
                               unsigned char* inside, const sphray_query_args* args);
SPHRAY_API int sphray_overlapping_d(const sphray_scene* scene, const double* centre, double radius,
                                    size_t capacity, uint32_t* ids, size_t* total);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* SPHRAY_SPHRAY_H */
