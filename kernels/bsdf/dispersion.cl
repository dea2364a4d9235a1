/* KHR_materials_dispersion: the glass's index of refraction as a function of wavelength,
 * from its ior n_d (at 587.56 nm, the Fraunhofer d line) and its Abbe number V_d = 20 /
 * dispersion, by the extension's Cauchy form:
 *   n(lambda) = max(n_d + (n_d - 1) / V_d (523655 / lambda^2 - 1.5168), 1),  lambda in nm,
 * so that n(587.56) = n_d and n(F) - n(C) = (n_d - 1) / V_d (F = 486.13 nm, C = 656.27 nm).
 *
 * clpt renders RGB: each channel carries light of one wavelength, the dominant wavelength of
 * its linear-sRGB primary (611.3, 549.1, 464.3 nm). A path that reaches dispersive glass
 * picks one channel there, uniformly, with weight 3 on that channel and 0 on the others, and
 * keeps it for the rest of the path (kernels/integrators/stages/walk.cl, walk_disperse): each
 * channel's expected value is its own transport at its own index, so the image is that of
 * three monochromatic renders, one per channel, with the noise of a third of the paths each.
 * Bidirectional estimators multiply two subpaths' weights: the product is nonzero only where
 * both picked the same channel (9 times its colour, with probability 1/9): still unbiased. */
#ifndef CLPT_BSDF_DISPERSION_CL
#define CLPT_BSDF_DISPERSION_CL

/* Channels: 0 none picked yet, 1 red, 2 green, 3 blue. */
#define DISPERSION_NONE 0u

static inline float dispersion_wavelength(u32 channel) {
  return channel == 1u ? 611.3f : channel == 2u ? 549.1f : 464.3f;
}

/* The weight of picking `channel` with probability 1/3. */
static inline float3 dispersion_weight(u32 channel) {
  return channel == 1u   ? (float3)(3.0f, 0.0f, 0.0f)
         : channel == 2u ? (float3)(0.0f, 3.0f, 0.0f)
                         : (float3)(0.0f, 0.0f, 3.0f);
}

/* The index at `lambda` nm of glass with index n_d and dispersion 20 / V_d. */
static inline float dispersion_ior(float n_d, float dispersion, float lambda) {
  if (!(dispersion > 0.0f)) return n_d;
  return fmax(n_d + (n_d - 1.0f) * (dispersion * (1.0f / 20.0f)) * (523655.0f / (lambda * lambda) - 1.5168f),
              1.0f);
}

#endif
