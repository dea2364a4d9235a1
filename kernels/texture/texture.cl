/* Texture reads: texel fetch with the glTF wrap modes, bilinear (or nearest) filtering, the
 * sRGB decode for colour slots, and the texture slots of a material (UV set + transform).
 *
 * Conventions: a texture is width x height RGBA8 texels, row 0 at the top; texel (i, j) has
 * its centre at uv = ((i + 0.5) / width, (j + 0.5) / height), so u = 0 is the left edge and
 * v = 0 the top edge (glTF).
 *
 * Minification: a texture carries its mip levels (TEXTURE_LEVELS_SHIFT; host/render/
 * mipmaps.h). A lookup with a footprint (TexPoint.lod: log2 of the footprint's width in UV
 * units, per UV set) reads level lambda = lod + log2(sqrt(w h |det M|)) (M the slot's
 * KHR_texture_transform), trilinear between the two nearest levels; without one (lod
 * -INFINITY: light paths, paths after a rough bounce, --texture-filter bilinear) or where
 * lambda <= 0 it is the bilinear lookup of level 0, the same operations as with no mip
 * levels at all. */
#ifndef CLPT_TEXTURE_TEXTURE_CL
#define CLPT_TEXTURE_TEXTURE_CL

#include "core/scene_view.cl"

/* The sRGB electro-optical transfer function (IEC 61966-2-1) at k / 255, exactly:
 * c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, computed in 40-digit decimal. */
__constant float SRGB_TO_LINEAR[256] = {
    0.000000000e+00f, 3.035269835e-04f, 6.070539671e-04f, 9.105809506e-04f,
    1.214107934e-03f, 1.517634918e-03f, 1.821161901e-03f, 2.124688885e-03f,
    2.428215868e-03f, 2.731742852e-03f, 3.035269835e-03f, 3.346535764e-03f,
    3.676507324e-03f, 4.024717018e-03f, 4.391442037e-03f, 4.776953481e-03f,
    5.181516702e-03f, 5.605391624e-03f, 6.048833023e-03f, 6.512090793e-03f,
    6.995410187e-03f, 7.499032043e-03f, 8.023192985e-03f, 8.568125618e-03f,
    9.134058702e-03f, 9.721217320e-03f, 1.032982303e-02f, 1.096009401e-02f,
    1.161224518e-02f, 1.228648836e-02f, 1.298303234e-02f, 1.370208305e-02f,
    1.444384360e-02f, 1.520851442e-02f, 1.599629337e-02f, 1.680737575e-02f,
    1.764195449e-02f, 1.850022013e-02f, 1.938236096e-02f, 2.028856306e-02f,
    2.121901038e-02f, 2.217388479e-02f, 2.315336618e-02f, 2.415763245e-02f,
    2.518685963e-02f, 2.624122189e-02f, 2.732089164e-02f, 2.842603950e-02f,
    2.955683444e-02f, 3.071344373e-02f, 3.189603307e-02f, 3.310476657e-02f,
    3.433980681e-02f, 3.560131488e-02f, 3.688945040e-02f, 3.820437160e-02f,
    3.954623528e-02f, 4.091519691e-02f, 4.231141062e-02f, 4.373502926e-02f,
    4.518620439e-02f, 4.666508634e-02f, 4.817182423e-02f, 4.970656598e-02f,
    5.126945837e-02f, 5.286064702e-02f, 5.448027644e-02f, 5.612849005e-02f,
    5.780543019e-02f, 5.951123816e-02f, 6.124605423e-02f, 6.301001765e-02f,
    6.480326669e-02f, 6.662593864e-02f, 6.847816984e-02f, 7.036009570e-02f,
    7.227185068e-02f, 7.421356838e-02f, 7.618538148e-02f, 7.818742181e-02f,
    8.021982031e-02f, 8.228270713e-02f, 8.437621154e-02f, 8.650046204e-02f,
    8.865558629e-02f, 9.084171118e-02f, 9.305896285e-02f, 9.530746663e-02f,
    9.758734714e-02f, 9.989872825e-02f, 1.022417331e-01f, 1.046164841e-01f,
    1.070231030e-01f, 1.094617108e-01f, 1.119324278e-01f, 1.144353738e-01f,
    1.169706678e-01f, 1.195384280e-01f, 1.221387722e-01f, 1.247718176e-01f,
    1.274376804e-01f, 1.301364767e-01f, 1.328683216e-01f, 1.356333297e-01f,
    1.384316150e-01f, 1.412632911e-01f, 1.441284709e-01f, 1.470272665e-01f,
    1.499597898e-01f, 1.529261520e-01f, 1.559264637e-01f, 1.589608351e-01f,
    1.620293756e-01f, 1.651321945e-01f, 1.682694002e-01f, 1.714411007e-01f,
    1.746474037e-01f, 1.778884160e-01f, 1.811642442e-01f, 1.844749945e-01f,
    1.878207723e-01f, 1.912016827e-01f, 1.946178304e-01f, 1.980693196e-01f,
    2.015562538e-01f, 2.050787364e-01f, 2.086368701e-01f, 2.122307574e-01f,
    2.158605001e-01f, 2.195261997e-01f, 2.232279573e-01f, 2.269658735e-01f,
    2.307400485e-01f, 2.345505822e-01f, 2.383975738e-01f, 2.422811225e-01f,
    2.462013267e-01f, 2.501582847e-01f, 2.541520943e-01f, 2.581828529e-01f,
    2.622506575e-01f, 2.663556048e-01f, 2.704977910e-01f, 2.746773121e-01f,
    2.788942635e-01f, 2.831487404e-01f, 2.874408377e-01f, 2.917706498e-01f,
    2.961382708e-01f, 3.005437944e-01f, 3.049873141e-01f, 3.094689228e-01f,
    3.139887134e-01f, 3.185467781e-01f, 3.231432091e-01f, 3.277780981e-01f,
    3.324515363e-01f, 3.371636150e-01f, 3.419144249e-01f, 3.467040564e-01f,
    3.515325995e-01f, 3.564001441e-01f, 3.613067798e-01f, 3.662525956e-01f,
    3.712376805e-01f, 3.762621230e-01f, 3.813260114e-01f, 3.864294338e-01f,
    3.915724777e-01f, 3.967552307e-01f, 4.019777798e-01f, 4.072402119e-01f,
    4.125426135e-01f, 4.178850708e-01f, 4.232676700e-01f, 4.286904966e-01f,
    4.341536362e-01f, 4.396571738e-01f, 4.452011945e-01f, 4.507857828e-01f,
    4.564110232e-01f, 4.620769997e-01f, 4.677837961e-01f, 4.735314961e-01f,
    4.793201831e-01f, 4.851499401e-01f, 4.910208498e-01f, 4.969329951e-01f,
    5.028864580e-01f, 5.088813209e-01f, 5.149176654e-01f, 5.209955732e-01f,
    5.271151257e-01f, 5.332764040e-01f, 5.394794890e-01f, 5.457244614e-01f,
    5.520114015e-01f, 5.583403896e-01f, 5.647115057e-01f, 5.711248295e-01f,
    5.775804404e-01f, 5.840784179e-01f, 5.906188409e-01f, 5.972017884e-01f,
    6.038273389e-01f, 6.104955708e-01f, 6.172065624e-01f, 6.239603917e-01f,
    6.307571363e-01f, 6.375968740e-01f, 6.444796820e-01f, 6.514056374e-01f,
    6.583748173e-01f, 6.653872983e-01f, 6.724431570e-01f, 6.795424696e-01f,
    6.866853124e-01f, 6.938717613e-01f, 7.011018919e-01f, 7.083757799e-01f,
    7.156935005e-01f, 7.230551289e-01f, 7.304607401e-01f, 7.379104088e-01f,
    7.454042095e-01f, 7.529422168e-01f, 7.605245047e-01f, 7.681511472e-01f,
    7.758222183e-01f, 7.835377915e-01f, 7.912979403e-01f, 7.991027380e-01f,
    8.069522577e-01f, 8.148465722e-01f, 8.227857544e-01f, 8.307698768e-01f,
    8.387990117e-01f, 8.468732315e-01f, 8.549926081e-01f, 8.631572135e-01f,
    8.713671192e-01f, 8.796223969e-01f, 8.879231179e-01f, 8.962693534e-01f,
    9.046611744e-01f, 9.130986518e-01f, 9.215818563e-01f, 9.301108584e-01f,
    9.386857285e-01f, 9.473065367e-01f, 9.559733532e-01f, 9.646862479e-01f,
    9.734452904e-01f, 9.822505503e-01f, 9.911020971e-01f, 1.000000000e+00f,
};

static inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : pow((c + 0.055f) / 1.055f, 2.4f);
}

/* Wraps integer texel coordinate i into [0, n) by a TextureWrap mode. */
static inline int texture_wrap(int i, int n, u32 mode) {
  if (mode == WRAP_CLAMP) return clamp(i, 0, n - 1);
  if (mode == WRAP_MIRROR) {
    const int period = 2 * n;
    int m = i % period;
    if (m < 0) m += period;
    return m < n ? m : period - 1 - m;
  }
  int m = i % n; /* WRAP_REPEAT */
  return m < 0 ? m + n : m;
}

/* Brings a texture coordinate into a small range with the same texels (so the integer
 * arithmetic below cannot overflow): repeat has period 1, mirror period 2, clamp stops at the
 * edges anyway. NaN becomes 0. */
static inline float texture_reduce(float x, u32 mode) {
  if (!isfinite(x)) return 0.0f;
  if (mode == WRAP_CLAMP) return clamp(x, -1.0f, 2.0f);
  const float period = mode == WRAP_MIRROR ? 2.0f : 1.0f;
  return x - period * floor(x / period);
}

/* Words a texel of texture t takes in the texel buffer: 2 for TEXTURE_WIDE, else 1. */
static inline u32 texture_words(__global const Texture* t) {
  return (t->flags & TEXTURE_WIDE) != 0u ? 2u : 1u;
}

/* One texel of the level starting at word `offset` with rows `width` texels wide, as RGBA in
 * [0, 1]; `srgb` decodes RGB from sRGB to linear (alpha is linear); `wide`: 16 bits a channel
 * (TEXTURE_WIDE). */
static inline float4 texel_load(const SceneView* s, u32 offset, u32 width, int x, int y, bool srgb,
                                bool wide) {
  if (wide) {
    const u32 i = offset + 2u * ((u32)y * width + (u32)x);
    const u32 rg = s->texels[i], ba = s->texels[i + 1u];
    const float4 c = (float4)((float)(rg & 65535u), (float)(rg >> 16), (float)(ba & 65535u),
                              (float)(ba >> 16)) / 65535.0f;
    if (!srgb) return c;
    return (float4)(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z), c.w);
  }
  const u32 c = s->texels[offset + (u32)y * width + (u32)x];
  const u32 r = c & 255u, g = (c >> 8) & 255u, b = (c >> 16) & 255u, a = c >> 24;
  if (srgb) return (float4)(SRGB_TO_LINEAR[r], SRGB_TO_LINEAR[g], SRGB_TO_LINEAR[b], (float)a / 255.0f);
  return (float4)((float)r, (float)g, (float)b, (float)a) / 255.0f;
}

/* One level (from word `offset`, w x h texels) of texture t at uv: bilinear between the four
 * nearest texel centres (decoded first, so sRGB textures are filtered in linear space), or
 * the nearest texel when `nearest`. */
static inline float4 texture_level_sample(const SceneView* s, __global const Texture* t, u32 offset,
                                          int w, int h, float2 uv, bool srgb, bool nearest) {
  const u32 ws = t->flags & TEXTURE_WRAP_S_MASK, wt = (t->flags >> TEXTURE_WRAP_T_SHIFT) & 3u;
  const bool wide = (t->flags & TEXTURE_WIDE) != 0u;
  const float x = texture_reduce(uv.x, ws) * (float)w, y = texture_reduce(uv.y, wt) * (float)h;
  if (nearest) {
    const int i = texture_wrap((int)floor(x), w, ws), j = texture_wrap((int)floor(y), h, wt);
    return texel_load(s, offset, (u32)w, i, j, srgb, wide);
  }
  const float fx = x - 0.5f, fy = y - 0.5f;
  const float x0 = floor(fx), y0 = floor(fy);
  const float ax = fx - x0, ay = fy - y0;
  const int i0 = texture_wrap((int)x0, w, ws), i1 = texture_wrap((int)x0 + 1, w, ws);
  const int j0 = texture_wrap((int)y0, h, wt), j1 = texture_wrap((int)y0 + 1, h, wt);
  const float4 top = mix(texel_load(s, offset, (u32)w, i0, j0, srgb, wide),
                         texel_load(s, offset, (u32)w, i1, j0, srgb, wide), ax);
  const float4 bottom = mix(texel_load(s, offset, (u32)w, i0, j1, srgb, wide),
                            texel_load(s, offset, (u32)w, i1, j1, srgb, wide), ax);
  return mix(top, bottom, ay);
}

/* Texture `index` at uv, level 0: bilinear, or the nearest texel with TEXTURE_NEAREST. */
static inline float4 texture_sample(const SceneView* s, int index, float2 uv, bool srgb) {
  __global const Texture* t = &s->textures[index];
  return texture_level_sample(s, t, t->offset, (int)t->width, (int)t->height, uv, srgb,
                              (t->flags & TEXTURE_NEAREST) != 0u);
}

static inline u32 texture_levels(__global const Texture* t) {
  return (t->flags >> TEXTURE_LEVELS_SHIFT) & 31u;
}

/* Texture `index` at uv with mip level `lambda` (fractional): level 0 where lambda <= 0 or
 * the texture has no levels (texture_sample), else trilinear between levels floor(lambda)
 * and the next, bilinear within each (TEXTURE_NEAREST is a magnification filter: it does
 * not apply here), clamped at the 1 x 1 level. */
static inline float4 texture_sample_lod(const SceneView* s, int index, float2 uv, bool srgb,
                                        float lambda) {
  __global const Texture* t = &s->textures[index];
  const u32 levels = texture_levels(t);
  if (!(lambda > 0.0f) || levels <= 1u) return texture_sample(s, index, uv, srgb);
  lambda = fmin(lambda, (float)(levels - 1u));
  const int k = (int)floor(lambda);
  const float f = lambda - (float)k;
  const u32 words = texture_words(t);
  u32 offset = t->offset;
  int w = (int)t->width, h = (int)t->height;
  for (int i = 0; i < k; ++i) {
    offset += words * (u32)w * (u32)h;
    w = max(1, w >> 1);
    h = max(1, h >> 1);
  }
  const float4 a = texture_level_sample(s, t, offset, w, h, uv, srgb, false);
  if (!(f > 0.0f)) return a;
  const u32 next = offset + words * (u32)w * (u32)h;
  const float4 b = texture_level_sample(s, t, next, max(1, w >> 1), max(1, h >> 1), uv, srgb, false);
  return mix(a, b, f);
}

/* The UV a texture slot reads: its UV set, then its KHR_texture_transform matrix. */
static inline float2 texture_slot_uv(__global const TextureSlot* slot, float2 uv0, float2 uv1) {
  const float2 uv = slot->texcoord == 1u ? uv1 : uv0;
  return (float2)(slot->m[0] * uv.x + slot->m[1] * uv.y + slot->m[2],
                  slot->m[3] * uv.x + slot->m[4] * uv.y + slot->m[5]);
}

/* Where a material's textures are read: both UV sets, and per set the footprint's width in
 * UV units as log2 (-INFINITY: none, level 0). */
typedef struct TexPoint {
  float2 uv0, uv1;
  float2 lod;
} TexPoint;

/* A material's texture in one slot, or `fallback` when the slot has no texture. */
static inline float4 texture_slot_sample(const SceneView* s, __global const TextureSlot* slot,
                                         const TexPoint* q, bool srgb, float4 fallback) {
  if (slot->texture < 0) return fallback;
  const float2 uv = texture_slot_uv(slot, q->uv0, q->uv1);
  const float lod = slot->texcoord == 1u ? q->lod.y : q->lod.x;
  if (!(lod > -INFINITY)) return texture_sample(s, slot->texture, uv, srgb);
  /* The slot's texels per UV unit: sqrt(w h |det M|), M the transform's linear part. */
  __global const Texture* t = &s->textures[slot->texture];
  const float det = fabs(slot->m[0] * slot->m[4] - slot->m[1] * slot->m[3]);
  const float lambda = lod + 0.5f * log2((float)t->width * (float)t->height * det);
  return texture_sample_lod(s, slot->texture, uv, srgb, lambda);
}

#endif
