// Checkpoints: the film's raw sums and how many samples they hold, plus a signature of
// everything that must match for a resumed render to continue the same estimate (scene
// file, resolution, integrator, estimator settings, seed). Written atomically (temporary
// file, then rename) and checksummed; a damaged or mismatched file is a clear error.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace clpt {

struct FilmState {
  uint32_t width = 0, height = 0;
  uint64_t samples_per_pixel = 0;
  std::vector<float> sum, sum_sq;  // 4 floats per pixel, as on the device
  std::vector<uint32_t> ray_counts;
};

// Throws Error(ExitCode::Output) when the file cannot be written.
void write_checkpoint(const std::filesystem::path& path, const std::string& signature,
                      const FilmState& state);

// Throws Error(ExitCode::BadInput) for a missing, damaged or foreign file, and
// Error(ExitCode::Usage) when its signature differs from `signature` (naming both).
FilmState read_checkpoint(const std::filesystem::path& path, const std::string& signature);

}  // namespace clpt
