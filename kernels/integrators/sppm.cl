/* Stochastic progressive photon mapping (Hachisuka and Jensen 2009), --integrator sppm.
 * One pass per sample index: the host emits the pass's photons (photon.cl, first hits not
 * stored: direct light is NEE's), sppm_grid_insert hashes them (kernels/spatial/hash_grid.cl),
 * then sppm_pass traces each pixel's camera ray to its visible point (through delta
 * scatterings, kernels/integrators/estimators/photon/visible_point.cl), adds emission and direct light
 * to the pixel's sum, and gathers the photons within the pixel's radius R:
 *     Phi = beta sum_p f(x, wo, wi_p) Phi_p   over the M photons on x's surface within R,
 * with photon bounce b in [2, max_depth - depth]. The statistics then shrink (alpha):
 *     N' = N + alpha M,  R' = R sqrt(N' / (N + M)),  tau' = (tau + Phi) R'^2 / R^2,
 * and the pixel's estimate after K passes is (direct sum + tau / (pi R^2)) / K, photon
 * powers being already divided by the photon paths of a pass. sppm_pass writes
 * K times that into the film's sum, so the film resolves it like any other. */
#include "camera/pixel_ray.cl"
#include "integrators/estimators/photon/visible_point.cl"
#include "integrators/estimators/photon/density.cl"
#include "spatial/hash_grid.cl"

__kernel void sppm_grid_insert(__global const Photon* photons, u32 count, float inv_cell, u32 mask,
                               volatile __global u32* heads, __global u32* next) {
  const u32 i = get_global_id(0);
  if (i >= count) return;
  grid_insert(photons, i, inv_cell, mask, heads, next);
}

/* The flux of the pass's photons around vp within radius r (before vp's throughput), and
 * their number. */
static inline float3 sppm_gather(__global const Photon* photons, __global const u32* heads,
                                 __global const u32* next, float inv_cell, u32 mask, u32 max_depth,
                                 const VisiblePoint* vp, float r, u32* m) {
  float3 phi = (float3)(0.0f);
  const float r2 = r * r;
  const float3 x = vp->sh.p;
  const int3 lo = grid_cell(x - (float3)(r), inv_cell), hi = grid_cell(x + (float3)(r), inv_cell);
  /* The cell side is at least every pixel's radius (the host's choice), so 2 cells per
   * axis; the bound only guards against a radius that is not. */
  if (hi.x - lo.x > 3 || hi.y - lo.y > 3 || hi.z - lo.z > 3) return phi;
  const u32 max_bounce = max_depth - vp->depth;
  const PhotonShading shading = photon_shading(&vp->sh, vp->wo);
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const int3 c = (int3)(cx, cy, cz);
        for (u32 e = heads[grid_bucket(c, mask)]; e != 0u; e = next[e - 1u]) {
          __global const Photon* ph = photons + (e - 1u);
          const float3 pp = vload3(0, ph->p);
          const float3 d = pp - x;
          if (dot(d, d) > r2) continue;
          const int3 pc = grid_cell(pp, inv_cell);
          if (pc.x != cx || pc.y != cy || pc.z != cz) continue; /* another cell's photon */
          const u32 b = photon_bounce(ph->flags);
          if (b < 2u || b > max_bounce || !photon_on_surface(&vp->sh, ph)) continue;
          ++*m;
          phi += photon_reflected(&vp->sh, &shading, ph);
        }
      }
  return phi;
}

/* pixel_count: width x height, or 0 for the host's warm-up launch. */
__kernel void sppm_pass(SCENE_KERNEL_ARGS __constant const RenderParams* params, float alpha,
                        u32 pixel_count, u32 sample,
                        __global const Photon* photons, __global const u32* heads,
                        __global const u32* next, float inv_cell, u32 mask,
                        __global SppmPixel* pixels, __global float4* film_sum,
                        __global u32* ray_counts, volatile __global u32* max_radius) {
  const u32 pixel = get_global_id(0);
  if (pixel >= pixel_count) return;
  const SceneView scene = SCENE_VIEW();
  const u32 x = pixel % params->width, y = pixel / params->width;
  SppmPixel px = pixels[pixel];
  float4 film = film_sum[pixel];
  float3 tau = vload3(0, px.tau), direct = vload3(0, px.direct);
  u32 rays = 0;

  const Sampler sampler = sampler_init(params, pixel, sample);
  float3 org, dir;
  pixel_ray(params, &sampler, x, y, &org, &dir);
  VisiblePoint vp;
  float3 Ld;
  if (photon_visible_point(params, &scene, &sampler, 0, org, dir, 0u, 0u, VP_EMISSION_ALL, &rays,
                           &vp)) {
    Ld = vp.L + vp.beta * photon_direct(params, &scene, &sampler, &vp, &rays);
    u32 m = 0;
    const float3 phi = vp.beta * sppm_gather(photons, heads, next, inv_cell, mask,
                                             params->max_depth, &vp, px.radius, &m);
    if (!is_finite3(phi)) {
      film.w += 1.0f;
    } else if (m > 0u) {
      const float n_new = px.n + alpha * (float)m;
      const float r_new = px.radius * sqrt(n_new / (px.n + (float)m));
      tau = (tau + phi) * ((r_new * r_new) / (px.radius * px.radius));
      px.n = n_new;
      px.radius = r_new;
    }
  } else {
    Ld = vp.L;
  }
  if (is_finite3(Ld))
    direct += Ld;
  else
    film.w += 1.0f;
  vstore3(tau, 0, px.tau);
  vstore3(direct, 0, px.direct);
  pixels[pixel] = px;
  film.xyz = direct + tau * (1.0f / (M_PI_F * px.radius * px.radius));
  film_sum[pixel] = film;
  ray_counts[pixel] += rays;
  atomic_max(max_radius, as_uint(px.radius));
}
