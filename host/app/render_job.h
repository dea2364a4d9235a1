// One render as the command line's options describe it, the part the CLI and the Python
// module share: the options' checks, the environment map, the scene, the device and the
// renderer set up in that order (so bad input fails before the slow steps), then the render
// with its option-driven writes (--checkpoint, --save-every) and the --stats document.
// What the caller does with the result differs: clpt writes the image and the statistics
// (write_job_image, write_job_stats), the Python module hands them over as arrays and a
// dictionary.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cl/context.h"
#include "cl/device.h"
#include "io/image_io.h"
#include "options.h"
#include "render/cluster.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace clpt {

struct JobResult {
  Image image;                       // the film's mean (or --bdpt-mosaic's cells)
  uint64_t samples_per_pixel = 0;    // 0: nothing was rendered, there is no image
  bool interrupted = false;
  std::optional<Image> variance;     // of each pixel's estimate, where the film has one
  std::vector<NamedChannel> layers;  // the EXR's extra layers the options ask for
  ImageMetadata metadata;            // the image's, --view and --exposure included
  DisplaySettings display;           // how PNG/JPEG show it
  nlohmann::json stats;              // the --stats document; null for --bdpt-mosaic
  std::vector<NamedChannel> aovs;    // --aov's first-hit layers (and --aov-pfm's albedo, normal)
};

// --aov-pfm's three files beside the output: OUTPUT's path without its extension, plus
// ".color.pfm", ".albedo.pfm", ".normal.pfm".
std::vector<std::string> aov_pfm_paths(const std::string& output);

class RenderJob {
 public:
  // progress(samples done, target (0: none), seconds, note): after each pass; the note is
  // "relMSE x" at most once a second with --reference, else empty. --bdpt-mosaic reports
  // cells done of all cells and no seconds.
  using Progress = std::function<void(uint64_t, uint64_t, double, const std::string&)>;

  // Everything up to the first pass. writes_image: the caller writes opt.output (the CLI
  // does; Python only when given an output), so its path is checked here, before any work;
  // without it, --save-every is refused. Throws Error as the CLI reports it.
  // cluster: the MPI ranks that render this job together (render/cluster.h), each with a
  // RenderJob of the same options; rank 0 writes checkpoints and --save-every images, and its
  // JobResult holds the whole image. Null: this process alone.
  RenderJob(const Options& opt, bool writes_image, const Cluster* cluster = nullptr);
  ~RenderJob();
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  // Renders to the sample target or time limit, or until *stop (checked between passes).
  JobResult run(const std::atomic<bool>* stop, const Progress& progress = {});

  // The first device --device names (and all of them).
  const cl::DeviceInfo& device() const { return devices_.front(); }
  const std::vector<cl::DeviceInfo>& devices() const { return devices_; }

 private:
  JobResult run_mosaic(const std::atomic<bool>* stop, const Progress& progress);

  Options opt_;
  bool writes_image_;
  Cluster alone_;
  const Cluster* cluster_;
  double load_seconds_ = 0.0;
  std::optional<ImageSize> reference_size_;
  std::optional<Image> reference_;
  Scene scene_;
  std::vector<cl::DeviceInfo> devices_;
  std::vector<std::unique_ptr<cl::Context>> contexts_;
  std::string device_names_;  // "A" or "A, B": for the log and the image's metadata
  RenderSettings settings_;
  std::unique_ptr<Renderer> renderer_;
  std::string signature_;  // what a checkpoint's sums depend on
};

// The options' RenderSettings (every field the renderer and integrators read).
RenderSettings render_settings(const Options& opt);

// Writes the result's image to opt.output, as the final write (atomic; the EXR with its
// layers, PNG/JPEG through the display settings); warns and writes nothing when no sample
// was taken.
void write_job_image(const Options& opt, const JobResult& result);

// Writes the --stats document to `where` ("-": stdout), atomically.
void write_job_stats(const std::string& where, const nlohmann::json& stats);

}  // namespace clpt
