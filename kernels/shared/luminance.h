/* The luminance weights of linear Rec. 709 / sRGB primaries (ITU-R BT.709): Y = 0.2126 R +
 * 0.7152 G + 0.0722 B. One copy for the kernels (luminance(), the irradiance cache's
 * gradients) and the host (the lights' selection weights, Metropolis' normalisation), which
 * must weigh colours alike. CLPT_LUMINANCE_R etc. are float literals on the device (OpenCL 1.2
 * needs no double) and double ones on the host, the same decimal digits. */
#ifndef CLPT_SHARED_LUMINANCE_H
#define CLPT_SHARED_LUMINANCE_H

#include "shared/compat.h"

#ifdef CLPT_OPENCL_DEVICE
#define CLPT_LUMINANCE_LITERAL(x) x##f
#else
#define CLPT_LUMINANCE_LITERAL(x) x
#endif
#define CLPT_LUMINANCE_R CLPT_LUMINANCE_LITERAL(0.2126)
#define CLPT_LUMINANCE_G CLPT_LUMINANCE_LITERAL(0.7152)
#define CLPT_LUMINANCE_B CLPT_LUMINANCE_LITERAL(0.0722)

#endif
