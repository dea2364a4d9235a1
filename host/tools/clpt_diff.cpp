// clpt-diff: compares a rendered image with a reference. Prints relMSE, MSE, RMSE, SMAPE,
// means, the largest difference and NaN/Inf counts, plus a per-pixel z-test when either
// file carries "variance.R/G/B" channels. Exit status as diff(1): 0 fine, 1 a check given
// on the command line failed, 2 trouble (bad command line, unreadable or mismatched
// inputs, unwritable error map). The formulas are in docs/clpt-diff.md.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "stats/diff_report.h"
#include "stats/image_stats.h"
#include "util/error.h"
#include "util/srgb.h"

namespace clpt {
namespace {

constexpr int kExitOk = 0, kExitCheckFailed = 1, kExitTrouble = 2;

struct DiffOptions {
  std::string image, reference;
  bool json = false;
  std::string error_map;
  std::vector<double> error_range = {1e-6, 1.0};
  std::optional<double> max_relmse;
  std::optional<double> min_z_pass;
  double alpha = 0.01;
  double variance_floor = kRelativeVarianceFloor;
};

const char* kFooter = R"(Figures (means over the pixel-channels where both values are finite):
  relMSE = mean((v - r)^2 / (|r| + 0.01)^2)     MSE = mean((v - r)^2)     RMSE = sqrt(MSE)
  SMAPE  = mean(|v - r| / (|v| + |r| + 1e-4))   (in [0, 1))
z-test (when either file has variance.R/G/B channels, the variance of the mean):
  z = |v - r| / sqrt(max(var_v + var_r, floor * max(|v|, |r|)^2)) per pixel-channel,
  passing when |z| < t, t Sidak-corrected: P(|Z| > t) = 1 - (1 - alpha)^(1/n).
Error map (.png): the mean over channels of (v - r)^2 / (|r| + 0.01)^2 per pixel, viridis
  on a log10 scale from MIN (darkest) to MAX (brightest); NaN/Inf pixels are red.
Exit status: 0 fine, 1 a --max-relmse or --min-z-pass check failed (NaN or Inf values
fail every check), 2 bad command line, unreadable or mismatched inputs, or an unwritable
error map. See docs/clpt-diff.md.)";

struct Parser {
  CLI::App app{"clpt-diff: compare a rendered image with a reference.", "clpt-diff"};
  DiffOptions o;

  Parser() {
    app.set_version_flag("--version", std::string("clpt-diff ") + CLPT_VERSION);
    app.get_formatter()->column_width(30);
    app.footer(kFooter);
    app.add_option("image", o.image, "Image under test (.exr, .png, ...)")->type_name("IMAGE")->required();
    app.add_option("reference", o.reference, "Reference image of the same size")
        ->type_name("REFERENCE")
        ->required();
    app.add_flag("--json", o.json, "Print the figures as JSON");
    app.add_option("--error-map", o.error_map,
                   "Write the per-pixel relative squared error: .png/.jpg a false colour "
                   "map, .exr the values")
        ->type_name("FILE");
    app.add_option("--error-range", o.error_range,
                   "Errors at the two ends of the map's log scale: MIN MAX [1e-6 1]")
        ->type_name("E")
        ->expected(2);
    app.add_option("--max-relmse", o.max_relmse, "Exit 1 when relMSE exceeds X")
        ->type_name("X")
        ->check(CLI::NonNegativeNumber.description(""));
    app.add_option("--min-z-pass", o.min_z_pass,
                   "Exit 1 when fewer than this fraction pass the z-test")
        ->type_name("F")
        ->check(CLI::Range(0.0, 1.0).description(""));
    app.add_option("--alpha", o.alpha, "Family-wise significance of the z-test [0.01]")
        ->type_name("A")
        ->check(CLI::Range(1e-12, 0.5).description(""));
    app.add_option("--variance-floor", o.variance_floor,
                   "z-test variance floor, times max(|v|,|r|)^2 [1e-4]")
        ->type_name("K")
        ->check(CLI::NonNegativeNumber.description(""));
  }
};

// ---- Error map -------------------------------------------------------------------------

// Viridis (matplotlib's perceptually uniform map, van der Walt and Smith 2015) at nine
// evenly spaced stops, sRGB bytes, interpolated linearly in sRGB between them.
constexpr std::array<std::array<int, 3>, 9> kViridis = {{{0x44, 0x01, 0x54},
                                                        {0x47, 0x2d, 0x7b},
                                                        {0x3b, 0x52, 0x8b},
                                                        {0x2c, 0x72, 0x8e},
                                                        {0x21, 0x91, 0x8c},
                                                        {0x28, 0xae, 0x80},
                                                        {0x5e, 0xc9, 0x62},
                                                        {0xad, 0xdc, 0x30},
                                                        {0xfd, 0xe7, 0x25}}};
constexpr std::array<int, 3> kNonFiniteColour = {0xff, 0x00, 0x00};

std::array<double, 3> viridis(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const double x = t * double(kViridis.size() - 1);
  const size_t i = std::min(size_t(x), kViridis.size() - 2);
  const double f = x - double(i);
  std::array<double, 3> c{};
  for (int k = 0; k < 3; ++k)
    c[k] = ((1.0 - f) * kViridis[i][k] + f * kViridis[i + 1][k]) / 255.0;
  return c;
}


void write_error_map(const DiffOptions& o, const Image& image, const Image& reference) {
  const Image err = relative_squared_error(image, reference);
  ImageMetadata meta;
  meta.strings = {{"Software", std::string("clpt-diff ") + CLPT_VERSION}};
  std::string ext = std::filesystem::path(o.error_map).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".exr") {
    write_image(o.error_map, err, meta);
    return;
  }
  // One colour per pixel from the mean of its three channels, t = log10(e / lo) / log10(hi / lo).
  const double lo = o.error_range[0], hi = o.error_range[1];
  Image map(err.width, err.height);
  for (size_t i = 0; i < size_t(err.width) * err.height; ++i) {
    const double e = (double(err.rgb[i * 3]) + err.rgb[i * 3 + 1] + err.rgb[i * 3 + 2]) / 3.0;
    std::array<double, 3> c;
    if (!std::isfinite(e)) {
      for (int k = 0; k < 3; ++k) c[k] = kNonFiniteColour[k] / 255.0;
    } else {
      c = viridis(e <= lo ? 0.0 : std::log10(e / lo) / std::log10(hi / lo));
    }
    // write_image takes linear values and encodes PNG/JPEG as sRGB; the map is defined in sRGB.
    for (int k = 0; k < 3; ++k) map.rgb[i * 3 + k] = float(srgb_to_linear(c[k]));
  }
  write_image(o.error_map, map, meta);
}

// ---- Reports ---------------------------------------------------------------------------

std::string size_text(const Image& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height);
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

void print_input(const char* label, const DiffInput& in, const ImageSummary& summary) {
  std::cout << label << in.path << "  " << size_text(in.file.image);
  const int spp = in.file.int_attribute("clpt:spp", -1);
  if (spp >= 0) std::cout << "  spp " << spp;
  std::cout << "  mean " << num(summary.finite_mean) << " (" << num(summary.channel_finite_mean[0])
            << " " << num(summary.channel_finite_mean[1]) << " "
            << num(summary.channel_finite_mean[2]) << ")  NaN " << summary.nan_count
            << "  Inf " << summary.inf_count
            << (in.file.variance() ? "  variance channels" : "") << "\n";
}

int run(int argc, char** argv) {
  Parser p;
  try {
    p.app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << p.app.help();
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << p.app.version() << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    throw Error(ExitCode::Usage, std::string(e.what()) + "\nRun 'clpt-diff --help' for the options.");
  }
  const DiffOptions& o = p.o;
  if (!(o.error_range[0] > 0.0 && o.error_range[1] > o.error_range[0] && std::isfinite(o.error_range[1])))
    throw Error(ExitCode::Usage, "--error-range " + num(o.error_range[0]) + " " + num(o.error_range[1]) +
                                     ": needs 0 < MIN < MAX");
  if (!o.error_map.empty()) check_output_path(o.error_map);

  // Any image clpt renders; the pixels are read as the file holds them.
  const ImageLimits film = film_image_limits("clpt-diff compares images of at most that size");
  const DiffInput img{o.image, read_image_channels(o.image, film)};
  const DiffInput ref{o.reference, read_image_channels(o.reference, film)};
  DiffSettings settings;
  settings.alpha = o.alpha;
  settings.variance_floor = o.variance_floor;
  const DiffReport report = diff_images(img, ref, settings);
  const ImageComparison& cmp = report.comparison;
  const std::optional<ZTestResult>& z = report.z;
  if (!z && o.min_z_pass)
    throw Error(ExitCode::BadInput, "--min-z-pass needs a variance: neither " + o.image + " nor " +
                                        o.reference + " has variance.R/G/B channels");

  if (!o.error_map.empty()) write_error_map(o, img.file.image, ref.file.image);

  // Checks. Non-finite values are left out of the figures, so they fail any check instead.
  std::vector<std::string> failures;
  const size_t nonfinite = cmp.image.nan_count + cmp.image.inf_count + cmp.reference.nan_count +
                           cmp.reference.inf_count;
  if ((o.max_relmse || o.min_z_pass) && nonfinite > 0)
    failures.push_back(std::to_string(nonfinite) + " NaN/Inf pixel-channels");
  if (o.max_relmse && !(cmp.rel_mse <= *o.max_relmse))
    failures.push_back("relMSE " + num(cmp.rel_mse) + " > " + num(*o.max_relmse));
  if (o.min_z_pass) {
    if (z->skipped > 0)
      failures.push_back("z-test: " + std::to_string(z->skipped) +
                         " pixel-channels could not be tested (NaN/Inf value or variance)");
    if (!(z->pass_fraction() >= *o.min_z_pass))
      failures.push_back("z-test pass fraction " + num(z->pass_fraction()) + " < " +
                         num(*o.min_z_pass));
  }

  if (o.json) {
    nlohmann::ordered_json j = diff_json(img, ref, report, settings);
    j["checks_passed"] = failures.empty();
    j["failures"] = failures;
    std::cout << j.dump(2) << "\n";
  } else {
    print_input("image      ", img, cmp.image);
    print_input("reference  ", ref, cmp.reference);
    std::cout << "compared     " << cmp.compared << " pixel-channels (both values finite)\n"
              << "relMSE       " << num(cmp.rel_mse) << "\n"
              << "MSE          " << num(cmp.mse) << "\n"
              << "RMSE         " << num(cmp.rmse) << "\n"
              << "SMAPE        " << num(cmp.smape) << "\n"
              << "max |v - r|  " << num(cmp.max_abs_diff) << "\n";
    if (z) {
      std::cout << "z-test       " << num(100.0 * z->pass_fraction()) << " % of " << z->tested
                << " pixel-channels pass |z| < " << num(z->threshold) << " (Sidak, alpha "
                << num(z->alpha) << ", variance from " << report.variance_from << "); "
                << z->failed() << " fail, max |z| " << num(z->max_abs_z);
      if (z->skipped) std::cout << ", " << z->skipped << " not tested (NaN/Inf)";
      std::cout << "\n";
    } else {
      std::cout << "z-test       not run: neither file has variance.R/G/B channels\n";
    }
  }
  for (const std::string& f : failures) std::cerr << "clpt-diff: check failed: " << f << "\n";
  return failures.empty() ? kExitOk : kExitCheckFailed;
}

}  // namespace
}  // namespace clpt

int main(int argc, char** argv) {
  try {
    return clpt::run(argc, argv);
  } catch (const clpt::Error& e) {
    std::cerr << "clpt-diff: error: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "clpt-diff: error: " << e.what() << "\n";
  }
  return clpt::kExitTrouble;
}
