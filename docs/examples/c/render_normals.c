/* Ray Tracing in One Weekend's first sphere, coloured by its normals, through sphray's C API:
 * the same image as `sphray render -s single -m normals --spp 1 -o image.ppm`, byte for byte.
 *
 *   cc -std=c99 -O2 render_normals.c $(pkg-config --cflags --libs sphray) -lm -o render_normals
 *   ./render_normals image.ppm [WIDTH HEIGHT]        (default 400 x 225, the scene's size)
 *
 * The camera is the renderer's (render/src/frame/camera.cpp), operation for operation, so that
 * every ray has the same bits; the image is a PPM P3 file as the renderer writes it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sphray/sphray.h>

typedef struct vec3 {
  float x, y, z;
} vec3;

static vec3 add(vec3 a, vec3 b) {
  return (vec3){a.x + b.x, a.y + b.y, a.z + b.z};
}
static vec3 sub(vec3 a, vec3 b) {
  return (vec3){a.x - b.x, a.y - b.y, a.z - b.z};
}
static vec3 scale(float s, vec3 v) {
  return (vec3){s * v.x, s * v.y, s * v.z};
}
static vec3 divide(vec3 v, float s) {
  return (vec3){v.x / s, v.y / s, v.z / s};
}
static float dot(vec3 a, vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static vec3 cross(vec3 a, vec3 b) {
  return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static vec3 normalize(vec3 v) {
  return divide(v, sqrtf(dot(v, v)));
}

/* The book's pinhole camera: rays from lookfrom through a viewport at distance 1. */
typedef struct camera {
  vec3 origin, upper_left, pixel_du, pixel_dv;
} camera;

static camera make_camera(vec3 lookfrom, vec3 lookat, vec3 vup, float vfov, int width, int height) {
  const float theta = vfov * 3.14159265358979323846f / 180.0f;
  const float viewport_height = 2.0f * tanf(theta / 2.0f);
  const float viewport_width = viewport_height * (float)width / (float)height;
  const vec3 w = normalize(sub(lookfrom, lookat));
  const vec3 u = normalize(cross(vup, w));
  const vec3 v = cross(w, u);
  const vec3 viewport_u = scale(viewport_width, u);
  const vec3 viewport_v = scale(viewport_height, scale(-1.0f, v)); /* rows run downwards */
  camera c;
  c.origin = lookfrom;
  c.pixel_du = divide(viewport_u, (float)width);
  c.pixel_dv = divide(viewport_v, (float)height);
  c.upper_left = sub(sub(scale(-1.0f, w), divide(viewport_u, 2.0f)), divide(viewport_v, 2.0f));
  return c;
}

/* The ray through the centre of pixel (x, y); the direction is not normalised (as in the book). */
static sphray_ray camera_ray(const camera* c, int x, int y) {
  const float px = (float)x + 0.5f, py = (float)y + 0.5f;
  const vec3 d = add(add(c->upper_left, scale(px, c->pixel_du)), scale(py, c->pixel_dv));
  const sphray_ray ray = {c->origin.x, c->origin.y, c->origin.z, d.x, d.y, d.z, 0.0f, INFINITY};
  return ray;
}

/* The book's sky: white to blue by the direction's height. */
static vec3 sky(const sphray_ray* r) {
  const vec3 d = {r->dx, r->dy, r->dz};
  const float a = 0.5f * (normalize(d).y + 1.0f);
  return add(scale(1.0f - a, (vec3){1, 1, 1}), scale(a, (vec3){0.5f, 0.7f, 1.0f}));
}

static int to_byte(float c) {
  const float clamped = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
  return (int)(unsigned char)(255.999f * clamped);
}

static int fail(const char* what, int status) {
  fprintf(stderr, "%s: %s (%s)\n", what, sphray_last_error(), sphray_status_name(status));
  return 1;
}

int main(int argc, char** argv) {
  /* The library loaded must be the one this program was built against, or a later one. */
  if (sphray_version_number() < SPHRAY_VERSION_NUMBER) {
    fprintf(stderr, "built against sphray %s, but libsphray %s is loaded\n", SPHRAY_VERSION_STRING,
            sphray_version());
    return 1;
  }
  if (argc != 2 && argc != 4) {
    fprintf(stderr, "usage: %s OUTPUT.ppm [WIDTH HEIGHT]\n", argv[0]);
    return 2;
  }
  const int width = argc == 4 ? atoi(argv[2]) : 400;
  const int height = argc == 4 ? atoi(argv[3]) : 225;
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    fprintf(stderr, "expected a width and height of 1 to 16384\n");
    return 2;
  }
  const size_t n = (size_t)width * (size_t)height;

  /* The scene: one sphere of radius 0.5 at (0, 0, -1). */
  const float cx = 0.0f, cy = 0.0f, cz = -1.0f, r = 0.5f;
  sphray_scene* scene = NULL;
  int status = sphray_scene_create(&cx, &cy, &cz, &r, 1, 0, NULL, &scene);
  if (status != SPHRAY_OK) return fail("sphray_scene_create", status);

  const camera cam =
      make_camera((vec3){0, 0, 0}, (vec3){0, 0, -1}, (vec3){0, 1, 0}, 90.0f, width, height);
  sphray_ray* rays = malloc(n * sizeof *rays);
  sphray_hit* hits = malloc(n * sizeof *hits);
  sphray_hit_surface* surfaces = malloc(n * sizeof *surfaces);
  if (rays == NULL || hits == NULL || surfaces == NULL) {
    fprintf(stderr, "out of memory\n");
    return 1;
  }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      rays[(size_t)y * (size_t)width + (size_t)x] = camera_ray(&cam, x, y);
  /* On every core; the hits are the same on any number of threads. */
  sphray_query_args args = SPHRAY_QUERY_ARGS_INIT;
  args.threads = SPHRAY_THREADS_ALL;
  status = sphray_intersect(scene, rays, n, hits, &args);
  if (status != SPHRAY_OK) return fail("sphray_intersect", status);
  status = sphray_surface(scene, rays, hits, n, surfaces);
  if (status != SPHRAY_OK) return fail("sphray_surface", status);

  FILE* out = fopen(argv[1], "w");
  if (out == NULL) {
    perror(argv[1]);
    return 1;
  }
  fprintf(out, "P3\n%d %d\n255\n", width, height);
  for (size_t i = 0; i < n; ++i) {
    vec3 c;
    if (hits[i].id == SPHRAY_NO_HIT) {
      c = sky(&rays[i]);
    } else { /* the normal, from [-1, 1] to [0, 1] */
      const vec3 normal = {surfaces[i].nx, surfaces[i].ny, surfaces[i].nz};
      c = scale(0.5f, add(normal, (vec3){1, 1, 1}));
    }
    fprintf(out, "%d %d %d\n", to_byte(c.x), to_byte(c.y), to_byte(c.z));
  }
  if (fclose(out) != 0) {
    perror(argv[1]);
    return 1;
  }
  printf("%s: %dx%d, sphray %s on %s\n", argv[1], width, height, sphray_version(),
         sphray_active_isa());
  free(surfaces);
  free(hits);
  free(rays);
  sphray_scene_release(scene);
  return 0;
}
