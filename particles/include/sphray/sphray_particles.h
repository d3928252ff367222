/* sphray's particle file loader for C: the spheres of a .sphp, .xyz, .csv, .ply or .pdb file
 * (docs/scenes.md, "Particle files") in arrays that sphray_scene_create (sphray.h) takes as
 * they are. A library of its own, libsphray_particles.so.0, so that libsphray never reads a
 * file. C99; includable from C and C++; no C++ type or exception crosses it.
 *
 *   sphray_particles* p;
 *   sphray_particle_arrays a;
 *   if (sphray_particles_load("cloud.xyz", 0.5f, &p) != SPHRAY_OK)
 *     fprintf(stderr, "%s\n", sphray_particles_last_error());
 *   sphray_particles_arrays(p, &a);
 *   sphray_scene_create(a.cx, a.cy, a.cz, a.r, a.count, 0, NULL, &scene);
 *   sphray_particles_release(p);   // after the scene is made: the scene has its own copy
 *
 * Status codes are sphray.h's, plus SPHRAY_ERROR_PARTICLE_FILE; every function that can fail
 * returns one and then sets a message for the calling thread (sphray_particles_last_error()),
 * which for a bad file names the file and the line (text) or particle (binary):
 * "sphray_particles_load: cloud.xyz:2: expected column 3 (z) to be a number, got \"x\"".
 * Threading: any number of threads may load files and read the same handle at once; release
 * must not run concurrently with anything else on the same handle. */
#ifndef SPHRAY_SPHRAY_PARTICLES_H
#define SPHRAY_SPHRAY_PARTICLES_H

#include <stddef.h>

#include "sphray/sphray.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The file cannot be read as particles (missing, unreadable, a bad line, a bad header, an
 * unknown extension). A value of its own, far from sphray.h's codes. */
#define SPHRAY_ERROR_PARTICLE_FILE 100

/* The particles of one file. Opaque. */
typedef struct sphray_particles sphray_particles;

/* A handle's particles as one packed array per quantity (count floats each), particle i being
 * sphere id i: sphray_scene_create(a.cx, a.cy, a.cz, a.r, a.count, 0, args, &scene). red,
 * green and blue (in [0, 1]) are NULL when the file has no colour columns (a .sphp file never
 * has). The arrays live as long as the handle. */
typedef struct sphray_particle_arrays {
  size_t count;
  const float *cx, *cy, *cz, *r;
  const float *red, *green, *blue;
} sphray_particle_arrays;

/* Reads the particle file at path, its format chosen by its extension (.sphp, .xyz, .csv; any
 * case), into a new handle. radius > 0 is the radius of every particle of a text file without
 * a radius column; radius <= 0 gives none (such a file is then refused). Every format's particles
 * are checked as the command checks them (finite centres of at most 1e17 in magnitude, radii in
 * (0, 1e17]). Errors: NULL pointer (path or out), particle file, too large,
 * out of memory. On failure *out is untouched. */
SPHRAY_API int sphray_particles_load(const char* path, float radius, sphray_particles** out);

/* The handle's particle count, in *count. */
SPHRAY_API int sphray_particles_count(const sphray_particles* particles, size_t* count);

/* The handle's arrays, in *out. */
SPHRAY_API int sphray_particles_arrays(const sphray_particles* particles,
                                       sphray_particle_arrays* out);

/* Frees the handle and its arrays; the handle must not be used again. */
SPHRAY_API int sphray_particles_release(sphray_particles* particles);

/* The message of the last failure of a sphray_particles_ function on the calling thread (""
 * if none yet). Valid until the thread's next call into this library. */
SPHRAY_API const char* sphray_particles_last_error(void);

#ifdef __cplusplus
}
#endif

#endif /* SPHRAY_SPHRAY_PARTICLES_H */
