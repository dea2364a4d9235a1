// Mip chains of the scene's textures (RGBA, 8 or 16 bits a channel), built at upload (kernels/texture/texture.cl reads
// them with a footprint per lookup: the ray cones of kernels/integrators/stages/walk.cl).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace clpt {

// The levels below level 0 of a width x height RGBA image: level k + 1 is max(1, w / 2) x
// max(1, h / 2) of level k's w x h, down to 1 x 1, each texel the mean of the texels of
// level k it covers (2 per axis, 3 where an odd side leaves one over). sRGB images
// (`srgb`) are averaged in linear light and encoded again; alpha is always linear. `wide`:
// 16 bits a channel in two words a texel (Texture::wide), for the levels too.
// Returns the words of levels 1, 2, ... one after the other; *levels counts level 0 too.
std::vector<uint32_t> build_mip_levels(const std::vector<uint32_t>& texels, uint32_t width, uint32_t height,
                                       bool srgb, uint32_t* levels, bool wide = false);

// Per texture of the scene: whether a colour slot (sRGB: base colour, emissive, specular
// colour, sheen colour, diffuse transmission colour) reads it. A texture read by both
// kinds of slot is filtered as sRGB.
std::vector<bool> textures_read_as_srgb(const Scene& scene);

}  // namespace clpt
