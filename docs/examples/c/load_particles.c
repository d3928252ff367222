/* A particle file's spheres through sphray's C API: libsphray_particles loads the file,
 * libsphray traces a row of rays along -z through them and prints what each hits.
 *
 *   cc -std=c99 -O2 load_particles.c $(pkg-config --cflags --libs sphray_particles) \
 *      -o load_particles
 *   ./load_particles cloud.xyz [RADIUS]    (RADIUS: for a text file without a radius column)
 *
 * Exit status 0, or 1 with sphray's one-line message (FILE:LINE: ...) on stderr. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sphray/sphray.h>
#include <sphray/sphray_particles.h>

enum { kRays = 8 };

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s FILE.sphp|FILE.xyz|FILE.csv [RADIUS]\n", argv[0]);
    return 2;
  }
  const float radius = argc > 2 ? strtof(argv[2], NULL) : 0.0f;
  sphray_particles* particles;
  if (sphray_particles_load(argv[1], radius, &particles) != SPHRAY_OK) {
    fprintf(stderr, "%s\n", sphray_particles_last_error());
    return 1;
  }
  sphray_particle_arrays a;
  sphray_particles_arrays(particles, &a);
  sphray_scene* scene;
  /* The arrays are packed: stride 0. The scene copies them, so the file's arrays can go. */
  int status = sphray_scene_create(a.cx, a.cy, a.cz, a.r, a.count, 0, NULL, &scene);
  const size_t count = a.count;
  const int colours = a.red != NULL;
  sphray_particles_release(particles);
  if (status != SPHRAY_OK) {
    fprintf(stderr, "%s\n", sphray_last_error());
    return 1;
  }
  printf("%zu particles%s\n", count, colours ? ", with colours" : "");
  /* Rays from z = 100 down the x axis, from x = -2 to x = 1.5. */
  sphray_ray rays[kRays];
  sphray_hit hits[kRays];
  for (int i = 0; i < kRays; ++i) {
    const sphray_ray ray = {
        -2.0f + 0.5f * (float)i, 0.0f, 100.0f, 0.0f, 0.0f, -1.0f, 0.0f, INFINITY};
    rays[i] = ray;
  }
  sphray_intersect(scene, rays, kRays, hits, NULL);
  for (int i = 0; i < kRays; ++i) {
    if (hits[i].id == SPHRAY_NO_HIT)
      printf("ray from x = %4.1f: no hit\n", rays[i].ox);
    else
      printf("ray from x = %4.1f: particle %u at t = %g\n", rays[i].ox, hits[i].id, hits[i].t);
  }
  sphray_scene_release(scene);
  return 0;
}
