#include "cl/programs.h"

#include <system_error>

#include "util/atomic_file.h"
#include "util/error.h"

namespace clpt::programs {
namespace fs = std::filesystem;

const std::vector<cl::ProgramSpec>& all() {
  static const std::vector<cl::ProgramSpec> list = {kPt,   kAo,        kLt,     kBdpt,
                                                   kPhoton, kPm,      kSppm,   kIc,
                                                   kIndirect1, kPssmlt, kMmlt, kVcm,
                                                   kAov,     kRaybench};
  return list;
}

namespace {

void write_text(const fs::path& file, const std::string& text) {
  std::string why;
  if (!write_file_atomically(file, [&](std::ostream& out) { out << text; }, &why))
    throw Error(ExitCode::Output, "--dump-kernels: cannot write " + file.string());
}

}  // namespace

size_t dump(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st))
      throw Error(ExitCode::Usage, "--dump-kernels " + dir.string() + ": not a folder");
    if (!fs::is_empty(dir, ec) && !fs::is_regular_file(dir / "programs.tsv"))
      throw Error(ExitCode::Usage, "--dump-kernels " + dir.string() +
                                       ": the folder is not empty and holds no earlier dump "
                                       "(programs.tsv); name a new or empty folder");
  } else if (!fs::create_directories(dir, ec) || ec) {
    throw Error(ExitCode::Output, "--dump-kernels: cannot create the folder " + dir.string() +
                                      (ec ? ": " + ec.message() : ""));
  }
  const cl::KernelSources sources = cl::KernelSources::core();
  std::string table = "# name\tentry file\tbuild options\tIntel GPU options\n";
  for (const cl::ProgramSpec& spec : all()) {
    write_text(dir / (std::string(spec.name) + ".cl"),
               cl::resolve_kernel_source(spec.entry_file, sources));
    table += std::string(spec.name) + '\t' + spec.entry_file + '\t' +
             cl::build_options(spec.options) + '\t' + spec.intel_gpu_options + '\n';
  }
  write_text(dir / "programs.tsv", table);
  return all().size();
}

}  // namespace clpt::programs
