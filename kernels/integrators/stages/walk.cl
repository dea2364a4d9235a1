/* The random walk: the one loop every integrator that follows a path runs, camera side
 * (radiance) or light side (importance), with the rules written once:
 *   trace    walk_next: closest hit; the medium's transmittance; shade (textures over the
 *            walk's ray cone, camera side); normals to wo;
 *   scatter  walk_scatter: a BSDF sample taken with the walk's dimensions, its weight (times
 *            Veach's shading correction on the light side), Russian roulette, the next ray's
 *            offset origin and the medium it enters.
 * An integrator is an iterator over the vertices (as pbrt-v4's RandomWalk and SmallVCM's
 * single loop): it asks for the next vertex, does its own work there (emission and NEE,
 * camera connections, photon deposits, visible points, light vertices), and asks the walk to
 * scatter. Its own quantities (MIS state, flux scale) stay in the integrator.
 *
 *   PathWalk w = walk_from_camera(org, dir, 0u, stream);      (or walk_from_light, ...)
 *   while (walk_next(s, sampler, &w, rays)) {
 *     ... the vertex w.sh, w.wo (bounce w.depth) ...
 *     const BsdfSample bs = walk_sample_bsdf(sampler, &w);
 *     if (!walk_scatter(p, s, sampler, &w, &bs)) break;
 *   }
 *
 * Throughput: `beta` starts at the integrator's value (1 for a camera path, a photon's
 * power, bdpt's Le / pdf) and takes every factor of the walk; `rr_weight` takes the same
 * factors from 1, and is what the roulette reads, so a path's start value never decides its
 * survival.
 *
 * Roulette (stages/russian_roulette.cl): WALK_RR_PATH is --rr / --rr-depth, applied when
 * leaving a vertex of bounce d with d + 1 >= rr_depth, survival from rr_weight (pt, lt, bdpt,
 * the camera side of pm and sppm); WALK_RR_ALBEDO is the photon tracer's, at every vertex with
 * the survival of that one scattering's weight (Jensen 2001: a white diffuse surface passes a
 * photon on unchanged); WALK_RR_NONE never stops a path (mlt's subpaths of a fixed length).
 *
 * Volumes (material/volume.cl): the medium is decided when the ray leaves a surface and its
 * transmittance applied when the ray lands; a walk started from a camera or a light starts
 * outside every volume.
 *
 * Dispersion (bsdf/dispersion.cl): the first dispersive glass a walk reaches picks the
 * walk's colour channel (its wavelength), weight 3 on it, in a stream of its own
 * (DIM_DISPERSION_STREAM, bounce d, offset 0 on the camera side and 1 on the light side);
 * every dispersive glass after it on the walk refracts at that wavelength's index.
 *
 * Dimensions (sampler/dimensions.h): vertex d of a walk draws bounce d of stream `stream`.
 * Camera walks number their first hit 0; light walks number it 1, since the light point
 * itself takes bounce 0's dimensions. */
#ifndef CLPT_INTEGRATORS_STAGES_WALK_CL
#define CLPT_INTEGRATORS_STAGES_WALK_CL

#include "bsdf/bsdf.cl"
#include "bsdf/dispersion.cl"
#include "bvh/intersect.cl"
#include "camera/camera.cl"
#include "core/ray.cl"
#include "integrators/stages/russian_roulette.cl"
#include "integrators/stages/shading_correction.cl"
#include "material/material.cl"
#include "material/volume.cl"
#include "sampler/sampler.cl"
#include "shared/render_types.h"

/* walk_next, walk_sample_bsdf and walk_scatter are always inlined (CLPT_INLINE, from
 * bvh/intersect.cl): PoCL left them out of line, which kept the PathWalk in memory and cost
 * pt 2-3 % on the Cornell box (docs/BENCHMARKS.md). */
#define WALK_RR_PATH 0u
#define WALK_RR_ALBEDO 1u
#define WALK_RR_NONE 2u

typedef struct PathWalk {
  SurfaceHit sh;    /* the vertex walk_next reached, normals oriented to wo */
  Hit hit;          /* ... and its ray hit (t from the ray's offset origin) */
  float3 wo;        /* towards where the walk came from */
  float3 org, dir;  /* the ray to the next vertex */
  float3 from;      /* the vertex that ray left (the camera or light point at the start) */
  float3 beta;      /* the integrator's throughput */
  float3 rr_weight; /* the walk's factors alone, for the roulette */
  float pdf_w;      /* the last scattering's density (1 before any) ... */
  int delta;        /* ... and whether it was a delta one (1 before any: a camera ray) */
  u32 medium;       /* what the ray travels in (MEDIUM_NONE: no volume) */
  u32 depth;        /* the bounce of the vertex reached (dimension layout) */
  u32 stream;       /* the dimension stream */
  u32 mode;         /* TRANSPORT_RADIANCE (camera side) or TRANSPORT_IMPORTANCE (light side) */
  u32 roulette;     /* WALK_RR_PATH, WALK_RR_ALBEDO or WALK_RR_NONE */
  float cone_width;  /* the ray cone (textures' footprint): its width at the ray's origin, */
  float cone_spread; /* and its growth per unit of distance; both 0: no cone */
  u32 channel;       /* the wavelength dispersive glass picked (DISPERSION_NONE: none yet) */
} PathWalk;

/* Sets every field of *w but its vertex (sh, hit, wo): the next ray is org, dir, towards the
 * vertex of bounce `depth`, in `medium`. */
static inline void walk_set_ray(PathWalk* w, float3 from, float3 org, float3 dir, float3 beta,
                                u32 medium, u32 depth, u32 stream, u32 mode, u32 roulette) {
  w->org = org;
  w->dir = dir;
  w->from = from;
  w->beta = beta;
  w->rr_weight = (float3)(1.0f);
  w->pdf_w = 1.0f;
  w->delta = 1;
  w->medium = medium;
  w->depth = depth;
  w->stream = stream;
  w->mode = mode;
  w->roulette = roulette;
  w->cone_width = 0.0f;
  w->cone_spread = 0.0f;
  w->channel = DISPERSION_NONE;
}

/* A walk whose next ray is org, dir, towards its vertex of bounce `depth`, in `medium`. */
static inline PathWalk walk_from_ray(float3 from, float3 org, float3 dir, float3 beta, u32 medium,
                                     u32 depth, u32 stream, u32 mode, u32 roulette) {
  PathWalk w;
  walk_set_ray(&w, from, org, dir, beta, medium, depth, stream, mode, roulette);
  return w;
}

/* A camera-side walk from a camera ray (its first hit is bounce `depth`, 0 for a pixel),
 * with a pixel's ray cone (camera_pixel_cone). */
static inline PathWalk walk_from_camera(__constant const RenderParams* p, float3 org, float3 dir,
                                        u32 depth, u32 stream) {
  PathWalk w = walk_from_ray(org, org, dir, (float3)(1.0f), MEDIUM_NONE, depth, stream,
                             TRANSPORT_RADIANCE, WALK_RR_PATH);
  camera_pixel_cone(p, &w.cone_width, &w.cone_spread);
  return w;
}

/* A light-side walk from a ray emitted at `from` (its first hit is bounce 1) carrying beta. */
static inline PathWalk walk_from_light(float3 from, float3 org, float3 dir, float3 beta, u32 stream,
                                       u32 roulette) {
  return walk_from_ray(from, org, dir, beta, MEDIUM_NONE, 1u, stream, TRANSPORT_IMPORTANCE,
                       roulette);
}

/* A camera-side walk w made anew at its own vertex (w->sh, w->wo, bounce depth), keeping its
 * ray cone and channel, to be scattered first: in place, without copying the vertex (pt's one
 * continuation), or after walk_at_vertex has put a vertex in. */
static inline void walk_restart_at_vertex(PathWalk* w, u32 depth, u32 stream) {
  const float cone_width = w->cone_width, cone_spread = w->cone_spread;
  const u32 channel = w->channel;
  walk_set_ray(w, w->sh.p, w->sh.p, -w->wo, (float3)(1.0f), MEDIUM_NONE, depth, stream,
               TRANSPORT_RADIANCE, WALK_RR_PATH);
  w->cone_width = cone_width;
  w->cone_spread = cone_spread;
  w->channel = channel;
}

/* A camera-side walk standing at vertex sh (normals oriented to wo, bounce depth) with the
 * ray cone `cone` (width there, spread) and the dispersion channel of the walk that reached
 * it, to be scattered first: pt's continuation from its first hit, one per branch. */
static inline PathWalk walk_at_vertex(const SurfaceHit* sh, float3 wo, u32 depth, float2 cone,
                                      u32 channel, u32 stream) {
  PathWalk w;
  w.sh = *sh;
  w.wo = wo;
  w.cone_width = cone.x;
  w.cone_spread = cone.y;
  w.channel = channel;
  walk_restart_at_vertex(&w, depth, stream);
  return w;
}

/* The dimension of `offset` (sampler/dimensions.h) at the walk's current vertex. */
static inline u32 walk_dim(const PathWalk* w, u32 offset) {
  return stream_dim(bounce_dim(w->depth, offset), w->stream);
}

/* At a dispersive glass: the walk's channel, picked here if none is yet (its weight in beta
 * and rr_weight), and the glass's index at that channel's wavelength. */
static inline void walk_disperse(const Sampler* sampler, PathWalk* w) {
  if (w->channel == DISPERSION_NONE) {
    const float u = sample_1d(sampler, stream_dim(bounce_dim(w->depth, w->mode == TRANSPORT_IMPORTANCE ? 1u : 0u),
                                                  DIM_DISPERSION_STREAM));
    w->channel = min((u32)(u * 3.0f), 2u) + 1u;
    const float3 c = dispersion_weight(w->channel);
    w->beta *= c;
    w->rr_weight *= c;
  }
  w->sh.bsdf.ior = dispersion_ior(w->sh.bsdf.ior, w->sh.bsdf.dispersion, dispersion_wavelength(w->channel));
  w->sh.bsdf.dispersion = 0.0f;
}

/* Traces the walk's ray. False when it escapes (w->dir is its direction); else w->sh, w->hit
 * and w->wo are the new vertex, the medium's transmittance is in beta and rr_weight, and a
 * dispersive glass there has refracted the walk into one wavelength (walk_disperse). */
CLPT_INLINE bool walk_next(const SceneView* s, const Sampler* sampler, PathWalk* w, u32* rays) {
  ++*rays;
  if (!intersect_closest(s, w->org, w->dir, INFINITY, &w->hit)) return false;
  if (w->medium != MEDIUM_NONE) {
    const float3 tr = medium_transmittance(s, w->medium, w->hit.t);
    w->beta *= tr;
    w->rr_weight *= tr;
  }
  w->cone_width += w->cone_spread * w->hit.t;
  surface_shade_cone_to(s, &w->hit, w->org, w->dir, w->cone_width, &w->sh);
  w->wo = -w->dir;
  bsdf_orient(&w->sh, w->wo);
  if (w->sh.bsdf.dispersion > 0.0f) walk_disperse(sampler, w);
  return true;
}

/* The BSDF's own sample at the current vertex, in the walk's dimensions and mode. */
CLPT_INLINE BsdfSample walk_sample_bsdf(const Sampler* sampler, const PathWalk* w) {
  return bsdf_sample(&w->sh, w->wo, sample_2d(sampler, walk_dim(w, DIM_BSDF_DIR)),
                     sample_1d(sampler, walk_dim(w, DIM_BSDF_LOBE)), w->mode);
}

/* Leaves the current vertex along bs (the walk's sample, or another sampler's with the
 * walk's dimensions). Returns 0 when the path ends there: no sample, or the roulette. */
CLPT_INLINE int walk_scatter(__constant const RenderParams* p, const SceneView* s,
                        const Sampler* sampler, PathWalk* w, const BsdfSample* bs) {
  if (!(bs->pdf_w > 0.0f) || is_black(bs->weight)) return 0;
  const float3 weight = w->mode == TRANSPORT_IMPORTANCE
                            ? bs->weight * shading_correction(&w->sh, w->wo, bs->wi)
                            : bs->weight;
  if (w->roulette == WALK_RR_ALBEDO) {
    const float survive = fmin(1.0f, max_component(weight));
    if (!(sample_1d(sampler, walk_dim(w, DIM_RR)) < survive)) return 0;
    w->beta *= weight / survive;
  } else {
    w->beta *= weight;
    w->rr_weight *= weight;
    if (w->roulette == WALK_RR_PATH && w->depth + 1u >= p->rr_depth) {
      const float survive = rr_survival(p, w->rr_weight);
      if (!(sample_1d(sampler, walk_dim(w, DIM_RR)) < survive)) return 0;
      w->beta /= survive;
      w->rr_weight /= survive;
    }
  }
  w->pdf_w = bs->pdf_w;
  w->delta = bs->is_delta;
  /* The cone goes on through a mirror or a refraction (their curvature left out); after a
   * rough bounce the footprint is the BSDF's, not a pixel's: full resolution from there. */
  if (!bs->is_delta) w->cone_width = w->cone_spread = 0.0f;
  w->medium = volume_medium(s, &w->sh, bs->wi);
  w->from = w->sh.p;
  w->org = offset_ray_origin_towards(w->sh.p, w->sh.ng, bs->wi); /* transmission goes through */
  w->dir = bs->wi;
  ++w->depth;
  return 1;
}

#endif
