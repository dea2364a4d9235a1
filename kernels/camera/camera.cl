/* Camera rays for a film point: pinhole or orthographic, each optionally through a thin lens.
 * The film plane is defined here once: film point (sx, sy) in [-1, 1]^2 is the point
 * forward + sx*right + sy*up at distance 1 in front of the pinhole; film_point / film_raster
 * and camera_ray / camera_film_of_direction are each other's inverses (camera_importance.cl
 * projects scene points with the second of each pair). */
#ifndef CLPT_CAMERA_CAMERA_CL
#define CLPT_CAMERA_CAMERA_CL

#include "core/warp.cl"
#include "shared/render_types.h"

/* Film coordinates of pixel (x, y) (y = 0 is the top row) offset by u in [0,1)^2,
 * mapped to [-1, 1]^2 with +y up. */
static inline float2 film_point(u32 x, u32 y, u32 width, u32 height, float2 u) {
  return (float2)(2.0f * ((float)x + u.x) / (float)width - 1.0f,
                  1.0f - 2.0f * ((float)y + u.y) / (float)height);
}

/* Inverse of film_point: the raster position (pixels, x right, y down) of film point `film`. */
static inline float2 film_raster(float2 film, u32 width, u32 height) {
  return (float2)(0.5f * (film.x + 1.0f) * (float)width, 0.5f * (1.0f - film.y) * (float)height);
}

/* Area of the film, [-1, 1]^2 on the plane at distance 1 in front of a pinhole. */
static inline float camera_film_area(__constant const CameraData* cam) {
  return 4.0f * length(vload3(0, cam->right)) * length(vload3(0, cam->up));
}

/* Inverse of the perspective camera_ray for the pinhole ray: the film point whose ray has
 * direction d (any length, dot(d, forward) > 0). right, up and forward are orthogonal. */
static inline float2 camera_film_of_direction(__constant const CameraData* cam, float3 d) {
  const float3 r = vload3(0, cam->right), u = vload3(0, cam->up), f = vload3(0, cam->forward);
  const float3 q = d / dot(d, f); /* on the film plane: f + sx r + sy u */
  return (float2)(dot(q, r) / dot(r, r), dot(q, u) / dot(u, u));
}

/* A pixel's ray cone (--texture-filter trilinear; the textures' footprint): a width of
 * *width + *spread d at distance d along a camera ray, one pixel across: 2 |up| d / height for
 * a perspective camera (|up| = tan(fov_y / 2)), 2 |up| / height throughout for an
 * orthographic one (Akenine-Moller et al. 2019; a thin lens's aperture is left out). Both 0
 * without cones (p->texture_cones 0). */
static inline void camera_pixel_cone(__constant const RenderParams* p, float* width, float* spread) {
  *width = *spread = 0.0f;
  if (!p->texture_cones) return;
  const float pixel = 2.0f * length(vload3(0, p->camera.up)) / (float)p->height;
  if (p->camera.type == CAMERA_ORTHOGRAPHIC) *width = pixel;
  else *spread = pixel;
}

/* The ray through film point `film`; `lens` in [0,1)^2 picks the point on the aperture. */
static inline void camera_ray(__constant const CameraData* cam, float2 film, float2 lens,
                              float3* org,
                              float3* dir) {
  const float3 o = vload3(0, cam->origin), r = vload3(0, cam->right), u = vload3(0, cam->up),
               f = vload3(0, cam->forward);
  if (cam->type == CAMERA_ORTHOGRAPHIC) {
    *org = o + film.x * r + film.y * u;
    *dir = f;
  } else {
    *org = o;
    *dir = normalize(f + film.x * r + film.y * u);
  }
  if (cam->lens_radius > 0.0f) {
    /* Where the pinhole ray meets the plane in focus stays sharp; the origin moves over
     * the aperture disk. dot(dir, f) > 0 for every film point. */
    const float3 focus = *org + *dir * (cam->focus_distance / dot(*dir, f));
    const float2 d = cam->lens_radius * warp_concentric_disk(lens);
    *org += d.x * normalize(r) + d.y * normalize(u);
    *dir = normalize(focus - *org);
  }
}

#endif
