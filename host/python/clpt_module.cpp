// The Python module `clpt` (docs/python.md): the renderer the CLI runs, called in-process.
//
//   clpt.render(scene, **options) -> clpt.Render   image, variance, layers as NumPy arrays,
//                                                   stats (the --stats dictionary), metadata
//   clpt.devices() -> list of dict                  the OpenCL devices, as --list-devices
//   clpt.diff(image, reference, alpha, variance_floor) -> dict   clpt-diff --json's figures
//   clpt.read_image(path) -> dict                   an image file's pixels, layers, metadata
//
// Options are the command line's, by the same parser: `max_depth=5` is `--max-depth=5`, True
// a flag, a tuple `resolution=(W, H)` is WxH, other tuples are joined with commas (S,T and
// R,G,B), and `limit` takes a dict or a list of NAME=VALUE. So every option, its checks and
// its error messages are the CLI's; a bad one raises clpt.Error (exit_code as the CLI's).
// The GIL is released while rendering; Ctrl-C is seen between passes: the render stops as
// the CLI's does (the output, if one was asked for, is written) and KeyboardInterrupt is
// raised.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "app/render_job.h"
#include "cl/device.h"
#include "io/image_io.h"
#include "options.h"
#include "stats/diff_report.h"
#include "util/error.h"
#include "util/log.h"

namespace py = pybind11;

namespace clpt {
namespace {

// The exception type clpt.Error; set in PYBIND11_MODULE.
PyObject* g_error_type = nullptr;

// Sets the Python error clpt.Error(message) with its exit_code.
void set_error(const std::string& message, int exit_code) {
  py::object e = py::reinterpret_borrow<py::object>(g_error_type)(message);
  e.attr("exit_code") = exit_code;
  PyErr_SetObject(g_error_type, e.ptr());
}

[[noreturn]] void raise_error(const std::string& message, int exit_code) {
  set_error(message, exit_code);
  throw py::error_already_set();
}

// --- Options: Python keywords to the CLI's arguments ---------------------------------------

std::string option_name(const std::string& key) {
  std::string name = "--" + key;
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}

std::string text_of(const py::handle& value) {
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();  // every digit
  return py::str(value).cast<std::string>();  // str, int, os.PathLike (str of a Path is its path)
}

std::vector<std::string> command_line(const std::string& scene, const py::kwargs& options) {
  std::vector<std::string> args = {"clpt", scene};
  for (const auto& item : options) {
    const std::string key = item.first.cast<std::string>();
    const py::handle value = item.second;
    const std::string name = option_name(key);
    if (value.is_none()) continue;
    if (py::isinstance<py::bool_>(value)) {
      if (value.cast<bool>()) args.push_back(name);
      continue;
    }
    if (key == "limit") {  // repeated: a dict {name: value} or a sequence of "NAME=VALUE"
      if (py::isinstance<py::dict>(value)) {
        for (const auto& l : value.cast<py::dict>()) args.push_back(name + "=" + text_of(l.first) + "=" + text_of(l.second));
      } else if (py::isinstance<py::str>(value)) {
        args.push_back(name + "=" + text_of(value));
      } else {
        for (const auto& l : value) args.push_back(name + "=" + text_of(l));
      }
      continue;
    }
    if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
      const char* sep = key == "resolution" ? "x" : ",";
      std::string joined;
      for (const auto& v : value) joined += (joined.empty() ? "" : sep) + text_of(v);
      args.push_back(name + "=" + joined);
      continue;
    }
    args.push_back(name + "=" + text_of(value));
  }
  return args;
}

Options parse(const std::string& scene, const py::kwargs& kwargs) {
  const std::vector<std::string> args = command_line(scene, kwargs);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  const std::optional<Options> opt = parse_options(int(argv.size()), argv.data());
  if (!opt) raise_error("help and version are the command line's; see help(clpt)", int(ExitCode::Usage));
  if (opt->list_devices) raise_error("list_devices: use clpt.devices()", int(ExitCode::Usage));
  if (!opt->dump_kernels.empty()) raise_error("dump_kernels is the command line's", int(ExitCode::Usage));
  return *opt;
}

// --- Results ---------------------------------------------------------------------------

py::array_t<float> to_array(const Image& image) {
  py::array_t<float> a({size_t(image.height), size_t(image.width), size_t(3)});
  std::memcpy(a.mutable_data(), image.rgb.data(), image.rgb.size() * sizeof(float));
  return a;
}

// A layer: (height, width, 3), or (height, width) for a one-channel layer (Depth, IndexMA).
py::array_t<float> layer_array(const NamedChannel& l) {
  if (l.channels.size() != 1) return to_array(l.image);
  py::array_t<float> a({size_t(l.image.height), size_t(l.image.width)});
  float* dst = a.mutable_data();
  for (size_t i = 0; i < size_t(l.image.width) * l.image.height; ++i) dst[i] = l.image.rgb[i * 3];
  return a;
}

Image from_array(const py::handle& value, const char* what) {
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 || a.shape(1) < 1)
    raise_error(std::string(what) + ": expected a path, a clpt.Render or an array of shape (height, width, 3)",
                int(ExitCode::Usage));
  Image image(uint32_t(a.shape(1)), uint32_t(a.shape(0)));
  std::memcpy(image.rgb.data(), a.data(), image.rgb.size() * sizeof(float));
  return image;
}

py::object json_to_python(const nlohmann::json& j) {
  if (j.is_null()) return py::none();
  return py::module_::import("json").attr("loads")(j.dump());
}

py::dict metadata_dict(const ImageMetadata& meta) {
  py::dict d;
  for (const auto& [k, v] : meta.strings) d[py::str(k)] = v;
  for (const auto& [k, v] : meta.ints) d[py::str(k)] = v;
  for (const auto& [k, v] : meta.floats) d[py::str(k)] = v;
  return d;
}

// clpt.Render: what render() returns. Arrays are float32, (height, width, 3), linear radiance.
struct Render {
  py::object image, variance, layers, stats, metadata;
  uint64_t spp = 0;
  bool interrupted = false;
  JobResult result;  // for clpt.diff
};

Render make_render(JobResult&& r) {
  Render out;
  out.image = to_array(r.image);
  out.variance = r.variance ? py::object(to_array(*r.variance)) : py::none();
  py::dict layers;
  for (const NamedChannel& l : r.layers) layers[py::str(l.name)] = layer_array(l);
  out.layers = layers;
  out.stats = json_to_python(r.stats);
  out.metadata = metadata_dict(r.metadata);
  out.spp = r.samples_per_pixel;
  out.interrupted = r.interrupted;
  out.result = std::move(r);
  return out;
}

Render render(const std::string& scene, const py::kwargs& kwargs) {
  const Options opt = parse(scene, kwargs);
  log::set_level(opt.quiet ? log::Level::Quiet : opt.verbose ? log::Level::Verbose : log::Level::Normal);
  if (!opt.kernel_dir.empty()) ::setenv("CLPT_KERNEL_DIR", opt.kernel_dir.c_str(), 1);
  const bool writes_image = kwargs.contains("output") && !kwargs["output"].is_none();
  std::atomic<bool> stop{false};
  bool keyboard_interrupt = false;
  JobResult result;
  {
    py::gil_scoped_release no_gil;  // the scene's load, the device's set-up and the render
    RenderJob job(opt, writes_image);
    result = job.run(&stop, [&](uint64_t, uint64_t, double, const std::string&) {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {  // a KeyboardInterrupt (or another handler's exception)
        PyErr_Clear();
        keyboard_interrupt = true;
        stop = true;
      }
    });
    if (writes_image) write_job_image(opt, result);
    if (opt.stats) write_job_stats(*opt.stats, result.stats);
  }
  if (keyboard_interrupt) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  return make_render(std::move(result));
}

py::list devices() {
  py::list list;
  for (const cl::DeviceInfo& d : cl::list_devices()) {
    py::dict e;
    e["device"] = std::to_string(d.platform_index) + ":" + std::to_string(d.device_index);  // for device=
    e["name"] = d.name;
    e["platform"] = d.platform_name;
    e["vendor"] = d.platform_vendor;
    e["version"] = d.version;
    e["driver"] = d.driver_version;
    e["gpu"] = d.is_gpu();
    e["compute_units"] = d.compute_units;
    e["global_memory_bytes"] = d.global_mem_bytes;
    list.append(e);
  }
  return list;
}

// One side of clpt.diff: a file (read as clpt-diff reads it), a clpt.Render (its image and
// variance) or an array.
DiffInput diff_input(const py::handle& value, const char* what) {
  if (py::isinstance<Render>(value)) {
    const Render& r = value.cast<const Render&>();
    DiffInput in{std::string("<clpt.Render>"), {}};
    in.file.image = r.result.image;
    if (r.result.variance) in.file.layers.push_back({kVarianceLayer, *r.result.variance});
    in.file.meta = r.result.metadata;
    return in;
  }
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    const std::string path = py::module_::import("os").attr("fspath")(value).cast<std::string>();
    py::gil_scoped_release no_gil;
    return DiffInput{path, read_image_channels(path, film_image_limits("clpt.diff compares images of at most that size"))};
  }
  DiffInput in{std::string("<array>"), {}};
  in.file.image = from_array(value, what);
  return in;
}

// clpt.read_image: an image file as clpt-diff reads it, with its layers and metadata.
py::dict read_image_file(const py::handle& file) {
  const std::string path = py::module_::import("os").attr("fspath")(file).cast<std::string>();
  ImageChannels c;
  {
    py::gil_scoped_release no_gil;
    c = read_image_channels(path, film_image_limits("no film is larger"));
  }
  py::dict layers;
  for (const NamedChannel& l : c.layers) layers[py::str(l.name)] = layer_array(l);
  py::dict d;
  d["image"] = to_array(c.image);
  d["layers"] = layers;
  d["metadata"] = metadata_dict(c.meta);
  return d;
}

py::object diff(const py::handle& image, const py::handle& reference, double alpha, double variance_floor) {
  if (!(alpha >= 1e-12 && alpha <= 0.5)) raise_error("alpha: expected 1e-12 to 0.5", int(ExitCode::Usage));
  if (!(variance_floor >= 0.0)) raise_error("variance_floor: expected a number >= 0", int(ExitCode::Usage));
  const DiffInput a = diff_input(image, "image"), b = diff_input(reference, "reference");
  DiffSettings settings;
  settings.alpha = alpha;
  settings.variance_floor = variance_floor;
  const DiffReport report = diff_images(a, b, settings);
  return json_to_python(diff_json(a, b, report, settings));
}

}  // namespace
}  // namespace clpt

PYBIND11_MODULE(clpt, m) {
  using namespace clpt;
  m.doc() = "clpt, an OpenCL physically based renderer for glTF 2.0 scenes (docs/python.md)";
  m.attr("__version__") = CLPT_VERSION;
  static py::exception<Error> error_type(m, "Error", PyExc_RuntimeError);
  g_error_type = error_type.ptr();
  error_type.doc() = "A render or a diff that failed; exit_code is the code clpt would exit with.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      set_error(e.what(), int(e.code()));
    } catch (const std::bad_alloc&) {
      set_error("out of host memory", int(ExitCode::Device));
    }
  });

  py::class_<Render>(m, "Render", "What clpt.render returns.")
      .def_readonly("image", &Render::image, "The image: float32 (height, width, 3), linear radiance")
      .def_readonly("variance", &Render::variance,
                    "The variance of each pixel's estimate (as the EXR's variance layer), or None "
                    "where the integrator has none (splatting and progressive ones)")
      .def_readonly("layers", &Render::layers, "The EXR's extra layers the options asked for, by name")
      .def_readonly("stats", &Render::stats, "The --stats document as a dict (None for bdpt_mosaic)")
      .def_readonly("metadata", &Render::metadata, "The image's metadata (clpt:spp, clpt:view, ...)")
      .def_readonly("spp", &Render::spp, "Samples per pixel taken")
      .def_readonly("interrupted", &Render::interrupted)
      .def("__repr__", [](const Render& r) {
        return "<clpt.Render " + std::to_string(r.result.image.width) + "x" + std::to_string(r.result.image.height) +
               ", " + std::to_string(r.spp) + " spp>";
      });

  m.def("render", &render, py::arg("scene"),
        "render(scene, **options) -> clpt.Render\n\n"
        "Renders a glTF 2.0 scene with the command line's options as keywords: "
        "integrator='bdpt', spp=64, resolution=(256, 256), device='pocl', max_depth=5, ...; "
        "output='x.exr' also writes the image, stats='s.json' the statistics. "
        "Raises clpt.Error with the CLI's message for bad options or input.");
  m.def("devices", &devices, "devices() -> list of dict: the OpenCL devices clpt can use.");
  m.def("read_image", &read_image_file, py::arg("path"),
        "read_image(path) -> dict(image=array, layers={name: array}, metadata={...})\n\n"
        "An EXR, HDR, PNG or JPEG file as linear float32 (height, width, 3) arrays, with an EXR's "
        "layers (variance, ...) and metadata (clpt:spp, ...).");
  m.def("diff", &diff, py::arg("image"), py::arg("reference"), py::arg("alpha") = 0.01,
        py::arg("variance_floor") = kRelativeVarianceFloor,
        "diff(image, reference, alpha=0.01, variance_floor=1e-4) -> dict\n\n"
        "clpt-diff --json's figures (relmse, mse, rmse, smape, z_test, ...) for two images, "
        "each a file, a clpt.Render or a float array of shape (height, width, 3).");
}
