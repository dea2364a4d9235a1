// The high-spp pt renders that several test processes take as their reference (the Cornell
// box at 8 192 spp for the bdpt, lt and photon-mapping tests, the glossy-and-glass box at
// 16 384): each is rendered once and kept on disk, so the next process that needs the same
// one reads it instead of spending some seconds of CPU on an identical render.
//
// The entry's key holds everything the image depends on: a digest of the test executable
// (host code, scene builders and embedded kernels), the resolved pt kernel source (so
// CLPT_KERNEL_DIR, for mutation testing, is honoured), the device and its driver, the
// scene, size, spp and seed. A missing, mismatched or damaged entry is rendered again and
// rewritten (atomically: a temporary file renamed). The cache lives beside the kernel
// cache (cl::kernel_cache_dir() / "test-references"; ctest points it into the build tree);
// with no cache directory every call renders.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt::test {

enum class ReferenceScene { CornellBox, CornellBoxGlossyGlass };

// pt on the PoCL test device (device_context()) at size x size pixels with RenderSettings'
// defaults otherwise.
FilmResult pt_reference(ReferenceScene scene, uint32_t size, uint64_t spp, uint32_t seed);

// Any scene built in code, rendered with pt and `settings` (square, integrator "pt"), kept
// under `label`, which must name the scene (its first word also names the file); the
// settings that shape the image enter the key themselves, beside the executable, the pt
// source and the device.
FilmResult pt_reference(const std::string& label, const std::function<Scene()>& build,
                        const RenderSettings& settings, uint32_t seed);

// Where pt_reference keeps that render; empty when there is no cache directory.
std::filesystem::path pt_reference_file(ReferenceScene scene, uint32_t size, uint64_t spp,
                                        uint32_t seed);

}  // namespace clpt::test
