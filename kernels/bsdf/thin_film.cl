/* Thin-film interference (KHR_materials_iridescence): the reflectance, in linear Rec. 709 RGB,
 * of a dielectric film of index eta2 and thickness d (nm) between the outside (index 1, as
 * glTF's) and a base whose normal-incidence reflectance is f0 (per channel).
 *
 * Belcour and Barla 2017 ("A Practical Extension to Microfacet Theory for the Modeling of
 * Varying Iridescence", SIGGRAPH), the form the glTF extension specifies: the Airy sum of the
 * waves bouncing inside the film,
 *     R(lambda) = R12 + Rs + 2 sum_m>=1 C_m cos(m phi(lambda)),
 *     Rs = T121^2 R23 / (1 - R12 R23),  C_m = (Rs - T121) (R12 R23)^(m/2),
 *     phi(lambda) = 2 pi OPD / lambda + phi21 + phi23,  OPD = 2 eta2 d cos(theta2),
 * integrated against the colour matching functions in closed form: the spectral integral of
 * cos(m phi) is the Fourier transform of the CMFs at m OPD, which the paper fits by Gaussians
 * (thin_film_fringes; the constants are the paper's, as the extension quotes them). The
 * interfaces use Schlick's reflectance and phase shifts of 0 or pi (a boundary into a denser
 * medium), as the extension does. The sum stops at m = 4, not at the extension's m = 2: at
 * grazing incidence over a bright base R12 R23 nears 0.5, and the third and fourth terms
 * move colours by up to 0.1 (tests/thin_film_test.cpp compares the whole against a spectral
 * Airy sum: largest difference 0.16 with two terms, 0.066 with four, as with ten). */
#ifndef CLPT_BSDF_THIN_FILM_CL
#define CLPT_BSDF_THIN_FILM_CL

#include "bsdf/fresnel.cl"

/* The fringe terms 2 sum_m C_m S_m for the orders m = 1 .. THIN_FILM_ORDERS, C_m = c0 r^m
 * (per channel), where S_m is the spectral integral of the CMFs times cos(2 pi m opd / lambda +
 * m shift), converted from XYZ to linear Rec. 709 and white-balanced so that opd 0 and shift 0
 * give (1, 1, 1): a spectrally flat reflectance is grey, as the constant term R12 + Rs (added
 * as RGB) already assumes. The extension's sample code leaves this last step out, which tints
 * every fringe term by the RGB of the equal-energy white, (1.205, 0.948, 0.910), and makes a
 * film of vanishing thickness reddish instead of the base. opd in nm.
 *
 * Each Gaussian of the fit gives a term val sqrt(2 pi var) cos(m a) exp(-m^2 b) with
 * a = pos phase + shift and b = var phase^2. The orders come from one cos and one exp per
 * Gaussian: cos(m a) by the Chebyshev recurrence cos((m + 1) a) = 2 cos a cos(m a) -
 * cos((m - 1) a), and exp(-m^2 b) = exp(-b)^(m^2) by multiplying in exp(-b)^(2m + 1) (four
 * cos and four exp for the four orders instead of sixteen each: the film's cost in an
 * iridescent scene, docs/BENCHMARKS.md session 41). */
#define THIN_FILM_ORDERS 4
static inline float3 thin_film_fringes(float opd, float3 shift, float3 c0, float3 r) {
  const float phase = 2.0f * PI_F * 1e-9f * opd;
  const float norm = 1.0f / 1.0685e-7f;
  /* The fit's four Gaussians as lanes: X, Y, Z and X's second lobe (w, added to X). */
  const float4 val = (float4)(5.4856e-13f, 4.4201e-13f, 5.2481e-13f, 9.7470e-14f);
  const float4 pos = (float4)(1.6810e6f, 1.7953e6f, 2.2084e6f, 2.2399e6f);
  const float4 var = (float4)(4.3278e9f, 9.3046e9f, 6.6121e9f, 4.5282e9f);
  const float4 amp = (val * norm) * sqrt(2.0f * PI_F * var);
  const float4 c1 = cos(pos * phase + (float4)(shift, shift.x));
  const float4 g = exp(-(phase * phase) * var);
  float4 c_prev = (float4)(1.0f), c = c1, e = g, step = g * g * g;
  float3 Cm = c0, sum = (float3)(0.0f);
  for (int m = 0; m < THIN_FILM_ORDERS; ++m) {
    const float4 lobes = amp * c * e;
    const float3 xyz = (float3)(lobes.x + lobes.w, lobes.y, lobes.z);
    const float3 rgb =
        (float3)(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
                 -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
                 0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z) *
        /* The same expression at opd 0, shift 0 (the fit's XYZ there is (1.00046, 1.00022,
         * 1.00112)). */
        (float3)(1.0f / 1.2053688f, 1.0f / 0.9483195f, 1.0f / 0.9100097f);
    Cm *= r;
    sum += Cm * 2.0f * rgb;
    const float4 c_next = 2.0f * c1 * c - c_prev;
    c_prev = c;
    c = c_next;
    e *= step; /* exp(-b)^((m + 1)^2) from exp(-b)^(m^2) */
    step *= g * g;
  }
  return sum;
}

/* The index of refraction whose normal-incidence reflectance against index 1 is f0. */
static inline float3 thin_film_ior_from_f0(float3 f0) {
  const float3 s = sqrt(clamp(f0, 0.0f, 0.9999f));
  return (1.0f + s) / (1.0f - s);
}

/* cos1: the cosine of the angle of incidence on the film, outside (>= 0). Clamped to [0, 1]:
 * the Gaussian fit can overshoot by a little. Out of line: every Fresnel term of the glTF
 * BSDF can call it (33 call sites in pt's kernel once inlined), and a film is rare. */
CLPT_NOINLINE float3 thin_film_reflectance(float cos1, float eta2, float d, float3 f0) {
  cos1 = clamp(cos1, 0.0f, 1.0f);
  if (!(d > 0.0f)) return fresnel_schlick(f0, cos1); /* no film */
  const float sin2_2 = (1.0f - cos1 * cos1) / (eta2 * eta2);
  if (sin2_2 >= 1.0f) return (float3)(1.0f);         /* total internal reflection (eta2 < 1) */
  const float cos2 = sqrt(1.0f - sin2_2);
  /* Outside -> film. */
  const float R12 = fresnel_schlick_weight(cos1) * (1.0f - fresnel_f0_from_ior(eta2)) +
                    fresnel_f0_from_ior(eta2);
  const float T121 = 1.0f - R12;
  const float phi21 = eta2 < 1.0f ? 0.0f : PI_F; /* pi - phi12 */
  /* Film -> base. */
  const float3 eta3 = thin_film_ior_from_f0(f0);
  const float3 r1 = (eta3 - eta2) / (eta3 + eta2);
  const float3 R23 = fresnel_schlick(r1 * r1, cos2);
  const float3 phi23 = select((float3)(0.0f), (float3)(PI_F), isless(eta3, (float3)(eta2)));
  const float opd = 2.0f * eta2 * d * cos2;
  const float3 phi = phi21 + phi23;
  const float3 R123 = clamp(R12 * R23, 1e-5f, 0.9999f);
  const float3 r123 = sqrt(R123);
  const float3 Rs = T121 * T121 * R23 / (1.0f - R123);
  return clamp(R12 + Rs + thin_film_fringes(opd, phi, Rs - T121, r123), 0.0f, 1.0f);
}

#endif
