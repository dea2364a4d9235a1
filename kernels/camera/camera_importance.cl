/* The camera as a sensor that light paths connect to (light tracing, BDPT's t = 1): for a
 * scene point, where its light lands on the film and with what importance.
 *
 * Pinhole with film area A on the plane at distance 1 (kernels/camera/camera.cl), after
 * pbrt-v3 §16.1.1 and Veach 1997 ch. 8: a film point is sampled uniformly (density 1/A), and
 * the film area dA seen under angle theta from the forward axis spans dw = cos^3(theta) dA, so
 *   pdf_w(theta) = 1 / (A cos^3 theta)            (density of camera_ray's direction)
 *   We(theta)    = 1 / (A cos^4 theta)            (importance, normalised so that
 *                                                  integral We cos dw over the film = 1).
 * A thin lens spreads the pinhole over a disk of area A_lens: We gains a factor 1 / A_lens
 * and the connection samples the lens point with density 1 / A_lens, so the two cancel in
 * `weight`; theta is then the angle of the ray from the lens point.
 * Orthographic cameras have a delta direction: no light path can reach them (the light
 * tracer refuses them). */
#ifndef CLPT_CAMERA_CAMERA_IMPORTANCE_CL
#define CLPT_CAMERA_CAMERA_IMPORTANCE_CL

#include "camera/camera.cl"

typedef struct CameraConnection {
  float3 p;      /* point on the lens (the pinhole itself without an aperture) */
  float3 wi;     /* unit direction from the scene point towards p */
  float dist;    /* distance from the scene point to p */
  float2 raster; /* film position in pixels (x right, y down) */
  float We;      /* importance of the ray p -> scene point: 1 / (A cos^4 theta), / A_lens */
  float pdf_w;   /* density camera_ray gives that ray's direction: 1 / (A cos^3 theta) */
  float weight;  /* We cos(theta) / (dist^2 pdf_lens): the factor a light vertex's
                  * f |cos| multiplies to give its contribution to the film's integral */
  int valid;     /* 0: behind the camera or off the film */
} CameraConnection;

static inline CameraConnection camera_connect(__constant const CameraData* cam, u32 width,
                                              u32 height,
                                              float3 x, float2 u_lens) {
  CameraConnection c;
  c.valid = 0;
  c.We = 0.0f;
  c.pdf_w = 0.0f;
  c.weight = 0.0f;
  c.raster = (float2)(-1.0f);
  c.wi = (float3)(0.0f);
  c.dist = 0.0f;
  const float3 o = vload3(0, cam->origin), f = vload3(0, cam->forward);
  c.p = o;
  float lens_area = 1.0f;
  if (cam->lens_radius > 0.0f) {
    const float2 d = cam->lens_radius * warp_concentric_disk(u_lens);
    c.p = o + d.x * normalize(vload3(0, cam->right)) + d.y * normalize(vload3(0, cam->up));
    lens_area = PI_F * cam->lens_radius * cam->lens_radius;
  }
  const float3 to_x = x - c.p;
  const float dist2 = dot(to_x, to_x);
  if (!(dist2 > 0.0f) || cam->type != CAMERA_PERSPECTIVE) return c;
  c.dist = sqrt(dist2);
  const float3 d = to_x / c.dist;
  const float cos_t = dot(d, f);
  if (!(cos_t > 0.0f)) return c;
  float2 film;
  if (cam->lens_radius > 0.0f) {
    /* The film point whose pinhole ray reaches the same point of the plane in focus. */
    const float3 focus = c.p + d * (cam->focus_distance / cos_t);
    film = camera_film_of_direction(cam, focus - o);
  } else {
    film = camera_film_of_direction(cam, d);
  }
  if (!(fabs(film.x) <= 1.0f && fabs(film.y) <= 1.0f)) return c;
  c.raster = film_raster(film, width, height);
  c.wi = -d;
  const float area = camera_film_area(cam);
  const float cos2 = cos_t * cos_t;
  c.pdf_w = 1.0f / (area * cos2 * cos_t);
  c.We = 1.0f / (area * lens_area * cos2 * cos2);
  c.weight = 1.0f / (area * cos2 * cos_t * dist2);
  c.valid = isfinite(c.weight) && c.raster.x >= 0.0f && c.raster.y >= 0.0f;
  return c;
}

/* Density per steradian with which camera_ray picks direction d (unit) from its lens point:
 * 1 / (A cos^3 theta) for a film point uniform over the whole film (area A), theta the angle
 * between d and the forward axis; 0 behind the camera. The same for a thin lens: the film
 * point maps linearly onto the plane in focus. */
static inline float camera_ray_pdf_w(__constant const CameraData* cam, float3 d) {
  const float c = dot(d, vload3(0, cam->forward));
  if (!(c > 0.0f) || cam->type != CAMERA_PERSPECTIVE) return 0.0f;
  return 1.0f / (camera_film_area(cam) * c * c * c);
}

#endif
