// A glTF file of one square under a point light, written for tests that check a material
// extension's textures and directions end to end (file -> loader and its generated tangents ->
// material -> BSDF -> integrator): a camera on the z axis (add_camera_on_z) sees the square
// fill its view, and where a highlight sits or how it is stretched says what the BSDF did.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace clpt::test {

// Half the square's side (m).
constexpr double kSquareHalf = 1.5;

// One-texel RGB PNG images written beside the file, named in its images array in this order
// (textures[i] has source i).
using SquareImages = std::vector<std::pair<std::string, std::array<unsigned char, 3>>>;

// <tmp>/clpt-<tag>-<pid>/square.gltf (+ square.bin and the images): the square
// [-1.5, 1.5]^2 in the plane z = 0 facing +z, with NORMAL and TEXCOORD_0 (u along +x, v along
// -y: glTF's convention, so the generated tangent is +x) and no TANGENT, `material` as its
// only material, `extensions` in extensionsUsed, and a point light of intensity 4 cd 1 m above
// the centre. The caller removes the folder.
std::filesystem::path write_square(const std::string& tag, const nlohmann::json& material,
                                   const std::vector<std::string>& extensions,
                                   const SquareImages& images = {});

}  // namespace clpt::test
