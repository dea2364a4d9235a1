/* Primary sample space: the sampler of a Metropolis chain (Kelemen, Szirmay-Kalos, Antal and
 * Csonka 2002, "A Simple and Robust Mutation Strategy for the Metropolis Light Transport
 * Algorithm"; the lazy bookkeeping is pbrt-v4's MLTSampler, pbrt 4th ed. §13.4).
 *
 * A path is a deterministic function of the vector u in [0,1)^dims its sample_1d/sample_2d
 * calls read: dimension d is coordinate d (the dense layout of sampler/dimensions.h's stream
 * 0), or, in a program built with CLPT_MLT_MULTIPLEXED (multiplexed MLT over bdpt's
 * strategies), the camera stream's dimension d is coordinate 2d and the light stream's
 * (DIM_BDPT_LIGHT_STREAM) 2d + 1, so that both subpaths' leading dimensions are in the
 * vector whatever their lengths (pbrt-v4's MLTSampler interleaves its streams the same way).
 * A chain keeps its vector in device memory, one PssCoord per coordinate at
 * coords[d * stride] (MltParams.dim_stride: interleaved with the other chains' on GPUs,
 * contiguous on CPUs). A proposal is either
 *   a large step: a fresh uniform vector (Kelemen's "large step", probability
 *                 MltParams.large_step), or
 *   a small step: every coordinate moved by a Gaussian of standard deviation sigma, wrapped
 *                 into [0, 1) (pbrt-v4's perturbation; Kelemen's was exponential); in
 *                 multiplexed MLT the light subpath's coordinates by sigma / 4
 *                 (PSS_LIGHT_SIGMA_SCALE).
 * Coordinates are updated lazily, when the path reads them: a coordinate last brought up to
 * date at iteration m and read at iteration i takes the last accepted large step's value if
 * that came after m, then the i - m small steps it missed as one Gaussian of standard deviation
 * sigma * sqrt(i - m) (the sum of independent Gaussians; wrapping commutes with it). The
 * chain's vector therefore is, in distribution, what eager updates of every coordinate at
 * every iteration would give, at the cost of the coordinates a path actually reads. A
 * sample_2d whose two coordinates both take a small step draws their two normal numbers as
 * one Box-Muller pair (pss_gaussian2: one logarithm and one sine-cosine for both, 1.05x the
 * mutations per second of mmlt on the Cornell box), independent of each other and of every
 * other coordinate's, so the step is the same Gaussian as one at a time.
 * A rejected proposal restores the coordinates it changed (value and iteration) from their
 * backups and takes the iteration back.
 *
 * Random numbers are counter-based: proposal n of a chain draws its perturbations and its
 * large step's values from key hash(chain, n), so a rejected proposal's successor never
 * repeats it, and a large step's values can be recomputed from its key when a coordinate it
 * did not read is read later. A fresh sampler (no chain: coords null) gives the values of a
 * large step with key large_key, which is how the bootstrap's paths and a chain's start
 * state share their vector. */
#ifndef CLPT_SAMPLER_PSS_CL
#define CLPT_SAMPLER_PSS_CL

/* clang-format off: render_types.h must come first, it defines u32, which dimensions.h uses */
#include "shared/render_types.h"
/* clang-format on */
#include "sampler/dimensions.h"
#include "core/math.cl"
#include "sampler/hash.cl"
#include "shared/mlt_types.h"

/* Salts separating a proposal key's uses. */
#define PSS_SALT_UNIFORM 0x68e31da4u
#define PSS_SALT_GAUSS 0xb5297a4du
#define PSS_SALT_LARGE 0x1b56c4e9u
#define PSS_SALT_ACCEPT 0x3c6ef372u
#define PSS_SALT_PICK 0xa54ff53au
#define PSS_SALT_GAUSS2 0x510e527fu /* pss_gaussian2's pairs */

#ifdef CLPT_MLT_MULTIPLEXED
#define PSS_STREAMS 2u
#else
#define PSS_STREAMS 1u
#endif

/* The light subpath's small steps (mmlt's odd coordinates) are a quarter of the camera
 * subpath's: a light subpath's emission point and direction, moved as far as a camera ray's
 * film position, mostly miss what made the path (the door-ajar scene's gap). Measured
 * (docs/BENCHMARKS.md, session 38; 128x128, depth 8, two or three seeds): the door at 60 s
 * relMSE 0.00164 against 0.00209 with sigma alike (1/2: 0.00187; 2: worse at 20 s), the
 * caustic scene at 30 s 0.00513 against 0.00623, the Cornell box at 10 s 0.00143 against
 * 0.00130. Each coordinate's Gaussian keeps its own fixed width, so a step stays symmetric and
 * the lazy updates exact. */
#define PSS_LIGHT_SIGMA_SCALE 0.25f

/* The coordinate of a sampler dimension (see above); ~0u: none, the dimension is outside the
 * vector. */
static inline u32 pss_coordinate(u32 dimension) {
#if PSS_STREAMS == 2u
  const u32 stream = dimension / DIM_STREAM_STRIDE, d = dimension % DIM_STREAM_STRIDE;
  if (stream == 0u) return 2u * d;
  if (stream == DIM_BDPT_LIGHT_STREAM) return 2u * d + 1u;
  return 0xffffffffu;
#else
  return dimension;
#endif
}

typedef struct Sampler {
  __global PssCoord* coords; /* coordinate 0 of the chain; null: a fresh vector (large_key) */
  u32 stride;                /* coords[d * stride] is coordinate d */
  u32 dims;                  /* coordinates of the vector */
  u32 iteration;             /* the iteration this proposal belongs to */
  u32 last_large;            /* iteration of the last accepted large step */
  u32 large_key;             /* its key */
  u32 step_key;              /* this proposal's key */
  u32 large_step;            /* 1: this proposal is a large step */
  float sigma;
} Sampler;

static inline float pss_uniform(u32 key, u32 d) {
  return fmin(u32_to_unit_float(hash_combine(key ^ PSS_SALT_UNIFORM, d)), 0x1.fffffep-1f);
}

/* A standard normal number for coordinate d of proposal `key` (Box and Muller 1958): its
 * magnitude from a quarter turn (|cos| of a uniform angle is cos of a uniform angle in
 * [0, pi/2)), its sign from an independent bit. The step is thus symmetric by construction,
 * which is all Metropolis' acceptance rule needs of it, so the functions may round as they
 * like: native_sqrt, and core/math.cl's ln_positive and cos_sin_turns, polynomials inline
 * where PoCL's native_log and native_cos call SLEEF out of line (mmlt about 1.09x faster on
 * the door scene, whole processes; before them, the native_ functions had made mlt about 1.17x
 * faster than log, sqrt and cos). */
static inline float pss_gaussian(u32 key, u32 d) {
  const u32 h = hash_combine(key ^ PSS_SALT_GAUSS, d);
  const u32 h2 = hash_u32(h);
  const float u1 = ((float)(h >> 8) + 1.0f) * 0x1.0p-24f; /* (0, 1]: log is finite */
  const float u2 = (float)(h2 >> 9) * 0x1.0p-23f;          /* [0, 1), bit 0 is the sign's */
  const float magnitude = native_sqrt(-2.0f * ln_positive(u1)) * cos_sin_turns(0.25f * u2).x;
  return (h2 & 1u) ? -magnitude : magnitude;
}

/* The sampler for a fresh uniform vector: the values a large step with this key gives. */
static inline Sampler pss_fresh(u32 key, u32 dims) {
  Sampler s;
  s.coords = 0;
  s.stride = 0u;
  s.dims = dims;
  s.iteration = 1u;
  s.last_large = 1u;
  s.large_key = key;
  s.step_key = key;
  s.large_step = 0u;
  s.sigma = 0.0f;
  return s;
}

/* Two independent standard normal numbers for coordinates d and its partner of proposal
 * `key`: Box and Muller's pair, radius and a full turn's angle, one logarithm for both. */
static inline float2 pss_gaussian2(u32 key, u32 d) {
  const u32 h = hash_combine(key ^ PSS_SALT_GAUSS2, d);
  const u32 h2 = hash_u32(h);
  const float u1 = ((float)(h >> 8) + 1.0f) * 0x1.0p-24f; /* (0, 1]: log is finite */
  const float u2 = (float)(h2 >> 8) * 0x1.0p-24f;          /* [0, 1): the turn */
  return native_sqrt(-2.0f * ln_positive(u1)) * cos_sin_turns(u2);
}

/* Coordinate d (at c), not yet read by this proposal, as the current state holds it: the last
 * accepted large step's value if that came after the coordinate was last brought up to date.
 * Kept as its backup (a rejection restores it); *modified: the iteration it belongs to. */
static inline float pss_backup(const Sampler* s, __global PssCoord* c, u32 d, u32* modified) {
  float value = c->value;
  *modified = c->modified;
  if (*modified < s->last_large) {
    value = pss_uniform(s->large_key, d);
    *modified = s->last_large;
  }
  c->backup = value;
  c->backup_modified = *modified;
  return value;
}

/* A small step's update of coordinate d (at c), not yet read by this proposal, by the standard
 * normal g: the small steps it missed since its backup's iteration as one Gaussian (file
 * comment). */
static inline float pss_small_step(const Sampler* s, __global PssCoord* c, u32 d, float g) {
  u32 modified;
  float value = pss_backup(s, c, d, &modified);
  const float steps = (float)(s->iteration - modified);
#if PSS_STREAMS == 2u
  const float sigma = (d & 1u) ? s->sigma * PSS_LIGHT_SIGMA_SCALE : s->sigma;
#else
  const float sigma = s->sigma;
#endif
  value += sigma * native_sqrt(steps) * g;
  value -= floor(value);
  value = fmin(value, 0x1.fffffep-1f);
  c->value = value;
  c->modified = s->iteration;
  return value;
}

/* Coordinate d as this proposal sees it, brought up to date first (see the file comment). */
static inline float pss_value(const Sampler* s, u32 dimension) {
  /* Out of the vector (a dimension the layout does not give the chain): an independent value
   * per proposal. mlt sizes the vector so that its paths read none but one: dispersion's
   * channel pick (DIM_DISPERSION_STREAM), redrawn at every proposal, which is a symmetric
   * independent proposal on the channel (the current state keeps its own). */
  const u32 d = pss_coordinate(dimension);
  if (d >= s->dims) return pss_uniform(s->step_key, dimension);
  if (!s->coords) return pss_uniform(s->large_key, d);
  __global PssCoord* c = s->coords + (size_t)d * s->stride;
  if (c->modified >= s->iteration) return c->value;
  if (!s->large_step) return pss_small_step(s, c, d, pss_gaussian(s->step_key, d));
  /* A large step: the value before it is kept as the backup, as a small step keeps it. */
  u32 modified;
  pss_backup(s, c, d, &modified);
  const float value = pss_uniform(s->step_key, d);
  c->value = value;
  c->modified = s->iteration;
  return value;
}

static inline float sample_1d(const Sampler* s, u32 dimension) { return pss_value(s, dimension); }

/* Both coordinates of a small step at once when neither has been read by this proposal: the
 * Box-Muller pair of the first one's key (a salt of its own, so no other coordinate's number
 * is drawn from the same hash). Otherwise one at a time. */
static inline float2 sample_2d(const Sampler* s, u32 dimension) {
  const u32 d0 = pss_coordinate(dimension), d1 = pss_coordinate(dimension + 1u);
  if (s->coords && !s->large_step && d0 < s->dims && d1 < s->dims) {
    __global PssCoord* c0 = s->coords + (size_t)d0 * s->stride;
    __global PssCoord* c1 = s->coords + (size_t)d1 * s->stride;
    if (c0->modified < s->iteration && c1->modified < s->iteration) {
      const float2 g = pss_gaussian2(s->step_key, d0);
      const float a = pss_small_step(s, c0, d0, g.x);
      return (float2)(a, pss_small_step(s, c1, d1, g.y));
    }
  }
  return (float2)(pss_value(s, dimension), pss_value(s, dimension + 1u));
}

/* ---- A chain's proposals (MltChain holds the counters between them). ---- */

/* Chain c's key: the root of its proposals' keys. */
static inline u32 pss_chain_key(u32 seed,
                                u32 chain) { return hash_combine(hash_u32(seed ^ 0x7f4a7c15u),
                                chain); }

/* Sets a chain to the start state whose vector is the fresh one of `key`, with its
 * coordinates not yet read (their iteration 0 is before the start's large step at 1). */
static inline void pss_chain_start(MltChain* ch, __global PssCoord* coords, u32 stride, u32 dims,
                                   u32 key) {
  for (u32 d = 0; d < dims; ++d) coords[(size_t)d * stride].modified = 0u;
  ch->iteration = 1u;
  ch->last_large = 1u;
  ch->large_key = key;
  ch->proposals = 0u;
}

/* The sampler of the chain's current state (no change to any coordinate). */
static inline Sampler pss_current(const MltChain* ch, __global PssCoord* coords, u32 stride,
                                  u32 dims) {
  Sampler s = pss_fresh(ch->large_key, dims);
  s.coords = coords;
  s.stride = stride;
  s.iteration = ch->iteration;
  s.last_large = ch->last_large;
  return s;
}

/* Starts the chain's next proposal: a large step with probability large_step, else a small
 * step of standard deviation sigma. */
static inline Sampler pss_propose(MltChain* ch, __global PssCoord* coords, u32 stride, u32 dims,
                                  u32 chain_key, float large_step, float sigma) {
  ch->iteration += 1u;
  ch->proposals += 1u;
  Sampler s = pss_current(ch, coords, stride, dims);
  s.step_key = hash_combine(chain_key, ch->proposals);
  s.large_step = u32_to_unit_float(hash_u32(s.step_key ^ PSS_SALT_LARGE)) < large_step ? 1u : 0u;
  s.sigma = sigma;
  return s;
}

/* Metropolis-Hastings acceptance of a proposal of target value `proposed` from a state of
 * value `current`, for the symmetric proposals above (a large step's uniform density and
 * the wrapped Gaussian are both symmetric): min(1, proposed / current); a state of value 0
 * (a chain that started on nothing) accepts anything. */
static inline float pss_acceptance(float proposed, float current) {
  return current > 0.0f ? fmin(1.0f, proposed / current) : 1.0f;
}

/* The uniform number that decides whether proposal `s` is accepted. */
static inline float pss_accept_u(const Sampler* s) {
  return u32_to_unit_float(hash_u32(s->step_key ^ PSS_SALT_ACCEPT));
}

/* The proposal becomes the chain's state. */
static inline void pss_accept(MltChain* ch, const Sampler* s) {
  if (s->large_step) {
    ch->last_large = s->iteration;
    ch->large_key = s->step_key;
  }
}

/* The proposal is dropped: its coordinates go back to their values before it. */
static inline void pss_reject(MltChain* ch, const Sampler* s) {
  for (u32 d = 0; d < s->dims; ++d) {
    __global PssCoord* c = s->coords + (size_t)d * s->stride;
    if (c->modified == s->iteration) {
      c->value = c->backup;
      c->modified = c->backup_modified;
    }
  }
  ch->iteration -= 1u;
}

#endif
