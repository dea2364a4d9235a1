// Robustness (issue 6): clpt under hostile conditions, as a user would meet them.
//   OutOfMemory.*       a scene or film larger than the device allows: exit 3, a message that
//                       says how much memory, no output file
//   UnwritableOutput.*  outputs that cannot be written even by root: exit 4 (or 1), a message
//                       naming the file, nothing left behind
//   BuildFailure.*      a kernel with a syntax error through --kernel-dir: exit 3, build log
//                       with file and line
//   NoNaN.*             degenerate but legal geometry rendered with pt and ao: every pixel
//                       finite and no sample dropped
//   ScaleInvariance.*   the Cornell box scaled by k renders as at k = 1 (one DISABLED_ case
//                       records what fails today)
// See docs/robustness.md.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

#include <chrono>
#include <csignal>
#include <thread>

#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "io/png_codec.h"
#include "render/renderer.h"
#include "support/gltf_plane.h"
#include "support/device.h"
#include "support/mesh.h"
#include "support/scenes.h"

extern char** environ;

namespace clpt::robustness_test {
namespace {
namespace fs = std::filesystem;

const std::string kCornell = std::string(CLPT_SOURCE_DIR) + "/scenes/cornell_box.gltf";

std::string slurp(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// A private folder for one test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    std::string templ = (fs::temp_directory_path() / "clpt-robust-XXXXXX").string();
    if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed for " + templ);
    path_ = templ;
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    return names;
  }

 private:
  fs::path path_;
};

struct Result {
  int exit_code = -1;  // -1: did not exit normally (killed by a signal)
  int signal = 0;
  std::string out, err;
  long max_rss_kib = 0;  // the child's peak resident memory
};

// Runs the clpt executable with `args` and extra environment variables set in the child only
// (tests/support/run.h cannot set them). stdout/stderr go to files in `scratch`. The child is
// killed after `timeout_s` seconds so a hang fails the test instead of the whole suite.
// Everything the child needs is prepared before fork(): the test process has PoCL's threads,
// so the child only calls async-signal-safe functions (open, dup2, execve).
Result run_clpt_env(const std::vector<std::string>& args,
                    const std::map<std::string, std::string>& env, const TempDir& scratch,
                    int timeout_s = 300) {
  const std::string out_path = scratch / "stdout.txt", err_path = scratch / "stderr.txt";
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) {
    const std::string kv = *e;
    if (!env.count(kv.substr(0, kv.find('=')))) env_strings.push_back(kv);
  }
  for (const auto& [k, v] : env) env_strings.push_back(k + "=" + v);
  std::vector<char*> envp, argv;
  for (std::string& kv : env_strings) envp.push_back(kv.data());
  envp.push_back(nullptr);
  argv.push_back(const_cast<char*>(CLPT_BINARY));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = ::open("/dev/null", O_RDONLY);
    if (o < 0 || e < 0 || in < 0) ::_exit(126);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::dup2(in, 0);
    ::execve(CLPT_BINARY, argv.data(), envp.data());
    ::_exit(127);
  }
  Result r;
  if (pid < 0) return r;
  int status = 0;
  struct rusage usage {};
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  while (::wait4(pid, &status, WNOHANG, &usage) != pid) {
    if (std::chrono::steady_clock::now() > give_up) {
      ::kill(pid, SIGKILL);
      ::wait4(pid, &status, 0, &usage);
      r.err = "(killed after " + std::to_string(timeout_s) + " s)\n";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.max_rss_kib = usage.ru_maxrss;
  r.out = slurp(out_path);
  r.err += slurp(err_path);
  fs::remove(out_path);
  fs::remove(err_path);
  return r;
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// OutOfMemory. PoCL 3.1 reads POCL_MEMORY_LIMIT as an integer number of GiB: the device then
// reports that much global memory and a maximum single allocation of a quarter of it rounded
// up to a power of two (POCL_MEMORY_LIMIT=1: 1 GiB global, 256 MiB per buffer). PoCL does not
// lower its own accounting limit, so only the per-buffer maximum is enforced: clpt's
// cl::Buffer checks it before clCreateBuffer and throws Error(Device).

const std::map<std::string, std::string> kOneGiB = {{"POCL_MEMORY_LIMIT", "1"}};

TEST(OutOfMemory, PoclMemoryLimitIsInEffect) {
  // The premise of the tests below: the device reports 1024 MiB and small renders still work.
  TempDir dir;
  const Result r = run_clpt_env({"--list-devices"}, kOneGiB, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "1024 MiB")) << r.out;
  const Result v = run_clpt_env(
      {kCornell, "--device", "pocl", "--resolution", "8x8", "--spp", "1", "-o", dir / "small.exr"},
      kOneGiB, dir);
  EXPECT_EQ(v.exit_code, 0) << "a small render must still work under the limit: " << v.err;
  EXPECT_TRUE(fs::exists(dir / "small.exr"));
}

TEST(OutOfMemory, FilmLargerThanTheDeviceAllowsIsExit3) {
  TempDir dir;
  // 8192 x 4096 pixels x 16 bytes (float4 sums) = 512 MiB for one film buffer.
  const Result r = run_clpt_env({kCornell, "--device", "pocl", "--resolution", "8192x4096",
                                 "--spp", "1", "-o", dir / "big.exr"},
                                kOneGiB, dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.signal, 0) << "clpt was killed by signal " << r.signal << ": " << r.err;
  EXPECT_TRUE(contains(r.err, "film")) << r.err;
  EXPECT_TRUE(contains(r.err, "512 MiB")) << "the message must say how much was needed: " << r.err;
  EXPECT_TRUE(contains(r.err, "256 MiB")) << "and how much the device allows: " << r.err;
  EXPECT_TRUE(contains(r.err, "allocate")) << r.err;
  EXPECT_TRUE(dir.entries().empty()) << "no output and no temporary file may be left";
}

// Writes a .gltf + .bin: one primitive with `vertices` vertices (a line of points, only the
// first three used by its single triangle) placed by `instances` nodes. The loader keeps every
// vertex of every instance, so the scene's vertex buffer is 32 x vertices x instances bytes
// while the file stays small and the BVH trivial.
void write_many_vertices_gltf(const fs::path& gltf, uint32_t vertices, uint32_t instances) {
  std::vector<float> pos(size_t(vertices) * 3);
  for (uint32_t i = 0; i < vertices; ++i) {
    pos[3 * i + 0] = float(i % 1024) * 1e-3f;
    pos[3 * i + 1] = float(i / 1024) * 1e-3f;
    pos[3 * i + 2] = 0.0f;
  }
  const uint32_t idx[3] = {0, 1, 1024};
  const fs::path bin = gltf.parent_path() / "many.bin";
  {
    std::ofstream f(bin, std::ios::binary);
    f.write(reinterpret_cast<const char*>(pos.data()), std::streamsize(pos.size() * sizeof(float)));
    f.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  const size_t pos_bytes = pos.size() * sizeof(float);
  std::ostringstream j;
  j << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)";
  for (uint32_t k = 0; k < instances; ++k) j << (k ? "," : "") << k;
  j << "]}],\"nodes\":[";
  for (uint32_t k = 0; k < instances; ++k)
    j << (k ? "," : "") << R"({"mesh":0,"translation":[0,0,)" << -0.01 * k << "]}";
  j << R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
    << R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" << vertices
    << R"(,"type":"VEC3","min":[0,0,0],"max":[1.1,)" << float(vertices / 1024) * 1e-3f << R"(,0]},)"
    << R"({"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}],)"
    << R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" << pos_bytes << "},"
    << R"({"buffer":0,"byteOffset":)" << pos_bytes << R"(,"byteLength":12}],)"
    << R"("buffers":[{"uri":"many.bin","byteLength":)" << pos_bytes + 12 << "}]}";
  std::ofstream(gltf) << j.str();
}

TEST(OutOfMemory, SceneLargerThanTheDeviceAllowsIsExit3) {
  TempDir dir, out;
  // 65536 vertices x 136 instances = 8,912,896 vertices x 32 bytes = 272 MiB > 256 MiB.
  write_many_vertices_gltf(dir.path() / "many.gltf", 65536, 136);
  // 1.4 GB of host memory from a 0.8 MB file: more than the loader's default budget per byte
  // of the file (1024), raised here to reach the device's limit.
  const Result r = run_clpt_env({dir / "many.gltf", "--device", "pocl", "--resolution", "16x16",
                                 "--spp", "1", "--limit", "memory-per-file-byte=4096", "-o",
                                 out / "scene.exr"},
                                kOneGiB, out);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.signal, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "vertex buffer")) << r.err;
  EXPECT_TRUE(contains(r.err, "272 MiB")) << r.err;
  EXPECT_TRUE(contains(r.err, "256 MiB")) << r.err;
  EXPECT_TRUE(out.entries().empty()) << "no output and no temporary file may be left";
}

// ---------------------------------------------------------------------------------------------
// UnwritableOutput. Tests run as root in CI, and permissions do not stop root, so these use
// paths that fail for everyone.

const std::vector<std::string> kTiny = {"--device", "pocl", "--resolution", "8x8", "--spp", "1"};

std::vector<std::string> tiny(std::vector<std::string> args) {
  args.insert(args.end(), kTiny.begin(), kTiny.end());
  return args;
}

TEST(UnwritableOutput, ParentIsARegularFile) {
  TempDir dir;
  std::ofstream(dir / "existing_file") << "not a folder";
  const std::string target = dir / "existing_file/out.exr";
  const Result r = run_clpt_env(tiny({kCornell, "-o", target}), {}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(contains(r.err, target)) << "the message must name the file: " << r.err;
  EXPECT_TRUE(contains(r.err, "is a file, not a folder")) << r.err;
  EXPECT_EQ(slurp(dir / "existing_file"), "not a folder");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"existing_file"});
}

TEST(UnwritableOutput, FolderOnAReadOnlyFileSystem) {
  // procfs refuses new files even to root. /proc/sys is a folder there; /proc itself is
  // checked too. Both pass access(W_OK) for root; the up-front check creates a probe file, so
  // the run fails before it renders, with exit 4 naming the file.
  for (const std::string target : {"/proc/clpt-robustness-out.exr",
                                    "/proc/sys/clpt-robustness-out.png"}) {
    SCOPED_TRACE(target);
    TempDir dir;
    const Result r = run_clpt_env(tiny({kCornell, "-o", target}), {}, dir);
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_TRUE(contains(r.err, target)) << r.err;
    EXPECT_FALSE(contains(r.err, "rendered ")) << "must fail before rendering: " << r.err;
    EXPECT_FALSE(fs::exists(target));
    // No temporary file either (write_image names them .<stem>.tmp<pid><ext>).
    for (const auto& e : fs::directory_iterator(fs::path(target).parent_path()))
      EXPECT_FALSE(contains(e.path().filename().string(), "clpt-robustness")) << e.path();
  }
}

TEST(UnwritableOutput, OutputIsAnExistingFolder) {
  TempDir dir;
  fs::create_directory(dir / "render.exr");
  const Result r = run_clpt_env(tiny({kCornell, "-o", dir / "render.exr"}), {}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(contains(r.err, dir / "render.exr")) << r.err;
  EXPECT_TRUE(contains(r.err, "folder")) << r.err;
  EXPECT_TRUE(fs::is_directory(dir / "render.exr"));
  EXPECT_TRUE(fs::is_empty(dir / "render.exr"));
  // Without an image extension the format check comes first: a usage error naming the path.
  fs::create_directory(dir / "plainfolder");
  const Result p = run_clpt_env(tiny({kCornell, "-o", dir / "plainfolder"}), {}, dir);
  EXPECT_EQ(p.exit_code, 1) << p.err;
  EXPECT_TRUE(contains(p.err, dir / "plainfolder")) << p.err;
}

TEST(UnwritableOutput, StatisticsFileCannotBeWritten) {
  TempDir dir;
  std::ofstream(dir / "existing_file") << "x";
  const std::string stats = dir / "existing_file/stats.json";
  const Result r =
      run_clpt_env(tiny({kCornell, "-o", dir / "img.exr", "--stats=" + stats}), {}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(contains(r.err, stats)) << r.err;
  // The statistics path is checked before rendering: nothing is rendered or written, and no
  // temporary file is left.
  EXPECT_FALSE(contains(r.err, "rendered ")) << "must fail before rendering: " << r.err;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"existing_file"});
}

TEST(UnwritableOutput, CheckpointFileCannotBeWritten) {
  TempDir dir;
  std::ofstream(dir / "existing_file") << "x";
  const std::string checkpoint = dir / "existing_file/state.clpt";
  const Result r =
      run_clpt_env(tiny({kCornell, "-o", dir / "img.exr", "--checkpoint", checkpoint}), {}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(contains(r.err, checkpoint)) << r.err;
  EXPECT_FALSE(contains(r.err, "rendered ")) << "must fail before rendering: " << r.err;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"existing_file"});
}

// Outputs never replace an input of the run, each other, or a node that is not a regular file
// (issue 23, class 1: --stats=scene.gltf overwrote the scene, --stats /dev/null replaced the
// device node with a regular file as root).
TEST(UnwritableOutput, NeverOverAnInputAnotherOutputOrANonRegularFile) {
  TempDir dir;
  fs::copy_file(kCornell, dir / "scene.gltf");
  const std::string scene_text = slurp(dir / "scene.gltf");
  const std::string scene = dir / "scene.gltf", img = dir / "img.exr";
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--stats", scene}, std::vector<std::string>{"--checkpoint", scene},
        std::vector<std::string>{"--stats", img}, std::vector<std::string>{"--reference", img}}) {
    SCOPED_TRACE(extra[0] + " " + extra.back());
    std::vector<std::string> args = {scene, "-o", img};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_clpt_env(tiny(args), {}, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, extra.back())) << "the message names the file: " << r.err;
    EXPECT_FALSE(contains(r.err, "rendered ")) << "must fail before rendering: " << r.err;
  }
  EXPECT_EQ(slurp(dir / "scene.gltf"), scene_text) << "the scene must be untouched";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.gltf"});
  // A FIFO and a character device as --stats: exit 4 before rendering, the nodes untouched
  // (a FIFO opened for reading or writing would also block the run).
  const fs::path fifo = dir / "stats.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& target : {fifo.string(), std::string("/dev/null")}) {
    SCOPED_TRACE(target);
    const Result r = run_clpt_env(tiny({scene, "-o", img, "--stats", target}), {}, dir);
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_TRUE(contains(r.err, "not a regular file")) << r.err;
    EXPECT_FALSE(fs::exists(img));
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // --checkpoint and --resume naming one file is how a render continues: allowed.
  const std::string ckpt = dir / "state.ckpt";
  EXPECT_EQ(run_clpt_env(tiny({scene, "-o", img, "--checkpoint", ckpt}), {}, dir).exit_code, 0);
  const Result again = run_clpt_env(
      {scene, "-o", img, "--checkpoint", ckpt, "--resume", ckpt, "--device", "pocl",
       "--resolution", "8x8", "--spp", "2"},
      {}, dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

// Readers of --env, --reference and --resume refuse what is not a regular file (issue 23,
// class 2: a FIFO or a link to /dev/zero made clpt wait forever and ignore SIGTERM).
TEST(UnreadableInput, FifosDevicesAndFoldersAreRefusedAtOnce) {
  TempDir dir;
  const fs::path fifo = dir / "input.fifo", zero = dir / "zero.exr", folder = dir / "folder.exr";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", zero);
  fs::create_directory(folder);
  for (const char* option : {"--env", "--reference", "--resume"})
    for (const fs::path& input : {fifo, zero, folder}) {
      SCOPED_TRACE(std::string(option) + " " + input.string());
      const Result r =
          run_clpt_env(tiny({kCornell, "-o", dir / "img.exr", option, input.string()}), {}, dir);
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_TRUE(contains(r.err, input.string())) << r.err;
      EXPECT_TRUE(contains(r.err, "not a regular file")) << r.err;
      EXPECT_FALSE(fs::exists(dir / "img.exr"));
    }
}

// A camera whose aspect ratio asks for a default image no film holds (issue 23, class 11:
// aspectRatio 0.001 asked for 640 x 640 000 and failed as a device error, exit 3): exit 2
// naming the scene's file and the camera, and the same scene renders with --resolution.
TEST(UnreadableInput, ExtremeCameraAspectIsASceneErrorNamingTheFile) {
  TempDir dir;
  const fs::path valid = fs::path(CLPT_TEST_DATA_DIR) / "valid";
  fs::copy_file(valid / "quad_trs_u8.bin", dir / "quad_trs_u8.bin");
  std::string text = slurp(valid / "quad_trs_u8.gltf");
  const std::string from = "\"aspectRatio\": 1.5";
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << "the test scene's camera changed";
  text.replace(at, from.size(), "\"aspectRatio\": 0.001");
  const std::string scene = dir / "thin.gltf";
  std::ofstream(scene) << text;
  const Result r = run_clpt_env({scene, "--device", "pocl", "--spp", "1", "-o", dir / "t.exr"}, {}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, scene)) << r.err;
  EXPECT_TRUE(contains(r.err, "aspect ratio 0.001")) << r.err;
  EXPECT_TRUE(contains(r.err, "--resolution")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "t.exr"));
  const Result ok = run_clpt_env(tiny({scene, "-o", dir / "t.exr"}), {}, dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// ---------------------------------------------------------------------------------------------
// HostileSizes (issue 23, classes 3 and 4): files whose headers or accessors claim far more
// than their bytes hold. Each is refused with exit 2 (1 for a reference of the wrong size),
// naming the file, and the refused run's peak memory (the child's ru_maxrss, libraries
// included: about 130 MiB for clpt before it sets up a device) stays under 256 MiB.

#if defined(__SANITIZE_ADDRESS__) || defined(CLPT_SANITIZED)
// AddressSanitizer's shadow memory and quarantine multiply every process's footprint: the
// bound is for the Release build; under the sanitizers these tests check exit codes,
// messages and that nothing crashes.
constexpr long kRejectedPeakKiB = 1L << 40;
#else
constexpr long kRejectedPeakKiB = 256 * 1024;
#endif

// A Radiance .hdr whose header claims `w` x `h` but which holds `data` bytes of pixels.
void write_hdr_header(const fs::path& path, int w, int h, const std::string& data) {
  std::ofstream(path, std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << h << " +X " << w << "\n"
                                        << data;
}

// A valid 16 x 16 EXR whose data and display windows are rewritten to claim 8000 x 8000.
void write_lying_exr(const fs::path& path) {
  write_image(path, Image(16, 16), {});
  std::string bytes = slurp(path);
  for (const std::string name : {"dataWindow", "displayWindow"}) {
    const std::string key = name + std::string("\0box2i\0", 7);
    const size_t at = bytes.find(key);
    ASSERT_NE(at, std::string::npos) << name;
    const int32_t window[4] = {0, 0, 7999, 7999};
    std::memcpy(&bytes[at + key.size() + 4], window, sizeof window);
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(HostileSizes, ImagesWhoseHeadersLieAreRefusedBeforeTheirSizeIsAllocated) {
  TempDir dir;
  const fs::path lying_hdr = dir.path() / "lying.hdr", huge_hdr = dir.path() / "huge.hdr",
                 lying_exr = dir.path() / "lying.exr";
  write_hdr_header(lying_hdr, 8000, 8000, std::string("\x02\x02\x1f\x40", 4));  // 55 bytes
  write_hdr_header(huge_hdr, 16000, 16000, "");
  write_lying_exr(lying_exr);
  struct Case {
    std::string option;
    fs::path file;
    int exit_code;
    std::string says;
  };
  const std::vector<Case> cases = {
      // Read whole before: 954 MB for these 55 bytes (issue 23, class 3).
      {"--env", lying_hdr, 2, "cannot read scanlines 0..63 of 8000"},
      {"--env", huge_hdr, 2, "is 16000x16000, larger than the limit of 16384 per side and 67108864 pixels"},
      {"--env", lying_exr, 2, "cannot read image"},
      // No size cap at all before; now its header is compared with the render's size first.
      {"--reference", lying_hdr, 1, "is 8000x8000 but the render is 8x8"},
      {"--reference", lying_exr, 2, "cannot read image"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.option + " " + c.file.string());
    const Result r = run_clpt_env(tiny({kCornell, "-o", dir / "img.exr", c.option, c.file.string()}), {}, dir);
    EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
    EXPECT_TRUE(contains(r.err, c.file.string())) << r.err;
    EXPECT_TRUE(contains(r.err, c.says)) << r.err;
    EXPECT_LT(r.max_rss_kib, kRejectedPeakKiB);
    EXPECT_FALSE(fs::exists(dir / "img.exr"));
  }
  // A raised limit reads the large header (and then finds the data missing).
  const Result raised = run_clpt_env(tiny({kCornell, "-o", dir / "img.exr", "--env", huge_hdr.string(), "--limit",
                                           "image-pixels=1G"}),
                                     {}, dir);
  EXPECT_EQ(raised.exit_code, 2) << raised.err;
  EXPECT_TRUE(contains(raised.err, "cannot read scanlines 0..63 of 16000")) << raised.err;
  EXPECT_LT(raised.max_rss_kib, kRejectedPeakKiB);
}

// Five 8192 x 8192 PNGs (64 KB each on disk, 2^26 texels each, within the per-image limit)
// are 2^28 + 2^26 texels together, more than total-texels (2^28): refused from their headers
// before any is decoded. Before, four were decoded (over 1 GB) before the fifth was refused.
TEST(HostileSizes, TexturesTooLargeTogetherAreRefusedBeforeAnyIsDecoded) {
  TempDir dir;
  const fs::path png = dir.path() / "big.png";
  {
    const std::vector<unsigned char> zeros(size_t(8192) * 8192, 0);
    std::string why;
    ASSERT_TRUE(write_png(png, 8192, 8192, 1, 8, zeros.data(), {}, &why)) << why;
  }
  ASSERT_LT(fs::file_size(png), 200u * 1024u);
  nlohmann::json m = {{"pbrMetallicRoughness",
                       {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 1}}}}},
                      {"normalTexture", {{"index", 2}}},
                      {"emissiveTexture", {{"index", 3}}},
                      {"emissiveFactor", {1, 1, 1}}};
  const fs::path plane = test::write_tilted_plane("hostile-textures", m, {});
  nlohmann::json doc = nlohmann::json::parse(slurp(plane));
  fs::copy_file(plane.parent_path() / "plane.bin", dir.path() / "plane.bin");
  fs::remove_all(plane.parent_path());
  for (int i = 0; i < 5; ++i) {
    doc["images"].push_back({{"uri", "big.png"}});
    doc["textures"].push_back({{"source", i}});
  }
  doc["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 4}}}}}});
  const std::string scene = dir / "textures.gltf";
  std::ofstream(scene) << doc.dump();
  const Result r = run_clpt_env(tiny({scene, "-o", dir / "img.exr"}), {}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, scene)) << r.err;
  EXPECT_TRUE(contains(r.err, "the images the materials use are 335544320 texels together")) << r.err;
  EXPECT_TRUE(contains(r.err, "(image 0 'big.png' 8192x8192, image 1 'big.png' 8192x8192, image 2")) << r.err;
  EXPECT_TRUE(contains(r.err, "--limit total-texels=N")) << r.err;
  EXPECT_LT(r.max_rss_kib, kRejectedPeakKiB);
  EXPECT_FALSE(fs::exists(dir / "img.exr"));

  // --lenient does not decode past the limit either: an image that would pass it becomes the
  // magenta placeholder, decided from its header (here every one, under a limit of 1000).
  const Result lenient = run_clpt_env(
      tiny({scene, "-o", dir / "img.exr", "--lenient", "--limit", "total-texels=1000"}), {}, dir);
  EXPECT_EQ(lenient.exit_code, 0) << lenient.err;
  for (int i = 0; i < 5; ++i)
    EXPECT_TRUE(contains(lenient.err, "image " + std::to_string(i) + " 'big.png' (used by material ")) << lenient.err;
  EXPECT_TRUE(contains(lenient.err, "with it the images the materials use exceed the limit of 1000 texels"))
      << lenient.err;
  EXPECT_LT(lenient.max_rss_kib, kRejectedPeakKiB);
}

// Accessors without bufferView are zeros that cost the file no bytes; instancing multiplies a
// mesh without more file. A 1 KB file used to take 6.7 GB this way (issue 23, class 4).
TEST(HostileSizes, ZeroAccessorsAndInstancingCannotMakeASmallFileCostGigabytes) {
  TempDir dir;
  auto write = [&](const std::string& name, uint64_t instances, uint64_t vertices) {
    std::ostringstream j;
    j << R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_mesh_gpu_instancing"],"scene":0,)"
      << R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0)";
    if (instances)
      j << R"(,"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{"TRANSLATION":1}}})";
    j << R"(}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
      << R"("accessors":[{"componentType":5126,"count":)" << vertices
      << R"(,"type":"VEC3","min":[0,0,0],"max":[0,0,0]},{"componentType":5126,"count":)" << instances
      << R"(,"type":"VEC3"}]})";
    const std::string path = dir / name;
    std::ofstream(path) << j.str();
    EXPECT_LT(fs::file_size(path), 1024u);
    return path;
  };
  struct Case {
    std::string file;
    std::string says;
  };
  const std::vector<Case> cases = {
      // 2^24 zero instances: the zeros' limit counts every read (2^20 together).
      {write("instances.gltf", uint64_t{1} << 24, 3), "accessor 1 (TRANSLATION of node 0 EXT_mesh_gpu_instancing) has no bufferView (all zeros) and count 16777216"},
      // 2^24 zero vertices: used to load (2.7 GB) and render.
      {write("vertices.gltf", 0, uint64_t{1} << 24), "has no bufferView (all zeros) and count 16777216"},
      // Within the zeros' limit, 2^20 - 3 instances of a triangle need about 640 MiB: more than
      // the budget per byte of the file (1024 x its ~400 bytes, at least 256 MiB), before any copy.
      {write("within.gltf", (uint64_t{1} << 20) - 3, 3), "more than the budget of 256.0 MiB"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const Result r = run_clpt_env(tiny({c.file, "-o", dir / "img.exr"}), {}, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, c.file)) << r.err;
    EXPECT_TRUE(contains(r.err, c.says)) << r.err;
    EXPECT_LT(r.max_rss_kib, kRejectedPeakKiB);
    EXPECT_FALSE(fs::exists(dir / "img.exr"));
  }
}

// ---------------------------------------------------------------------------------------------
// BuildFailure: a kernel with a syntax error, loaded with --kernel-dir as a developer would.

TEST(BuildFailure, SyntaxErrorInPtKernelGivesExit3WithFileAndLine) {
  TempDir dir, cache;
  const fs::path kernels = dir.path() / "kernels";
  fs::copy(fs::path(CLPT_SOURCE_DIR) / "kernels", kernels, fs::copy_options::recursive);
  const fs::path pt = kernels / "integrators" / "pt.cl";
  std::vector<std::string> lines;
  {
    std::ifstream in(pt);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_GT(lines.size(), 5u);
  // After the #includes (lines 1-4): line 5 is the broken one.
  lines.insert(lines.begin() + 4, "this_is_not_opencl_xyz here;");
  {
    std::ofstream out(pt, std::ios::trunc);
    for (const std::string& l : lines) out << l << "\n";
  }
  const Result r = run_clpt_env(tiny({kCornell, "--kernel-dir", kernels.string(), "-o",
                                      dir / "out.exr"}),
                                {{"XDG_CACHE_HOME", cache.path().string()},
                                 {"CLPT_CACHE_DIR", cache.path().string()}},
                                dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "pt.cl:5:")) << "the build log must name file and line: " << r.err;
  EXPECT_TRUE(contains(r.err, "this_is_not_opencl_xyz")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

// ---------------------------------------------------------------------------------------------
// NoNaN: degenerate scenes built in code, rendered with pt and ao. Positions stay finite (the
// loader refuses others, so a Scene never holds them). Normals are "unit or zero" by Scene's
// contract and the loader zeroes NaNs, but the renderer is given NaN/Inf normals and UVs
// anyway, as defence in depth against another producer of Scenes. The film drops non-finite samples and counts them, so a finite image alone proves
// little: each case also asserts that no sample was dropped, because a dropped sample is a
// biased (darkened) pixel, and on legal input it is a bug in the kernels. Both are checked
// separately so a failure says which.

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Material diffuse(float rho) {
  Material m;
  m.base_color = glm::vec4(rho, rho, rho, 1.0f);
  m.metallic = 0.0f;
  return m;
}

Material emitter(float radiance) {
  Material m = diffuse(0.5f);
  m.emission = glm::vec3(radiance);
  m.double_sided = true;
  return m;
}

// Appends one triangle with its own three vertices and per-vertex normals and UVs.
void add_triangle(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material,
                  glm::vec3 na = glm::vec3(0.0f), glm::vec3 nb = glm::vec3(0.0f),
                  glm::vec3 nc = glm::vec3(0.0f), glm::vec2 uv = glm::vec2(0.0f)) {
  const uint32_t base = uint32_t(s.positions.size());
  for (const auto& [p, n] : {std::pair{a, na}, std::pair{b, nb}, std::pair{c, nc}}) {
    s.positions.push_back(p);
    s.normals.push_back(n);
    s.uvs.push_back(uv);
  }
  s.triangles.emplace_back(base, base + 1, base + 2);
  s.triangle_materials.push_back(material);
}

uint32_t add_material(Scene& s, const Material& m) {
  s.materials.push_back(m);
  return uint32_t(s.materials.size() - 1);
}

// The Cornell box (0..0.556 wide, camera at z 0.8) with `extra` added to it.
Scene cornell_with(const std::function<void(Scene&)>& extra) {
  Scene s = test::cornell_box();
  extra(s);
  return s;
}

// Every position and the camera scaled by `k` about the origin (radiance is scale invariant).
Scene scaled(Scene s, float k) {
  for (glm::vec3& p : s.positions) p *= k;
  for (Camera& c : s.cameras) c.camera_to_world[3] = glm::vec4(glm::vec3(c.camera_to_world[3]) * k, 1.0f);
  return s;
}

// A spot in view of the Cornell camera, in front of the back wall.
const glm::vec3 kMid(0.278f, 0.25f, -0.3f);

struct NoNaNCase {
  const char* name;
  std::function<Scene()> scene;
};

void PrintTo(const NoNaNCase& c, std::ostream* os) { *os << c.name; }

std::vector<NoNaNCase> no_nan_cases() {
  return {
      {"ZeroAreaTriangles",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.8f));
           for (int i = 0; i < 50; ++i) {
             const glm::vec3 p = kMid + glm::vec3(0.004f * i - 0.1f, 0.0f, 0.0f);
             add_triangle(s, p, p, p, m);
           }
         });
       }},
      {"CollinearTriangles",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.8f));
           for (int i = 0; i < 50; ++i) {
             const glm::vec3 p = kMid + glm::vec3(0.0f, 0.004f * i - 0.1f, 0.0f);
             add_triangle(s, p, p + glm::vec3(0.1f, 0.02f, 0.0f), p + glm::vec3(0.2f, 0.04f, 0.0f), m);
           }
         });
       }},
      {"DuplicateVertexIndices",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.8f));
           const uint32_t base = uint32_t(s.positions.size());
           for (glm::vec3 p : {kMid, kMid + glm::vec3(0.1f, 0.0f, 0.0f), kMid + glm::vec3(0.0f, 0.1f, 0.0f)}) {
             s.positions.push_back(p);
             s.normals.push_back(glm::vec3(0.0f));
             s.uvs.push_back(glm::vec2(0.0f));
           }
           for (glm::uvec3 t : {glm::uvec3(0, 0, 1), glm::uvec3(1, 2, 2), glm::uvec3(2, 2, 2),
                                glm::uvec3(0, 1, 2), glm::uvec3(0, 1, 2)}) {  // and a twin face
             s.triangles.push_back(t + glm::uvec3(base));
             s.triangle_materials.push_back(m);
           }
         });
       }},
      {"OpposingNormalsInterpolateToZero",
       [] {
         return cornell_with([](Scene& s) {
           // n and -n at the corners: the interpolated shading normal is 0 along a line.
           const uint32_t m = add_material(s, diffuse(0.8f));
           const glm::vec3 n(0.0f, 0.0f, 1.0f);
           add_triangle(s, kMid + glm::vec3(-0.15f, -0.15f, 0.0f), kMid + glm::vec3(0.15f, -0.15f, 0.0f),
                        kMid + glm::vec3(0.0f, 0.15f, 0.0f), m, n, -n, -n);
           add_triangle(s, kMid + glm::vec3(-0.15f, 0.0f, 0.05f), kMid + glm::vec3(0.15f, 0.0f, 0.05f),
                        kMid + glm::vec3(0.0f, 0.2f, 0.05f), m, n, -n, glm::vec3(0.0f));
         });
       }},
      {"NaNAndInfNormals",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.8f));
           const glm::vec3 nan3(kNaN), inf3(kInf, -kInf, 0.0f);
           add_triangle(s, kMid + glm::vec3(-0.2f, -0.1f, 0.0f), kMid + glm::vec3(0.0f, -0.1f, 0.0f),
                        kMid + glm::vec3(-0.1f, 0.1f, 0.0f), m, nan3, nan3, nan3);
           add_triangle(s, kMid + glm::vec3(0.0f, -0.1f, 0.0f), kMid + glm::vec3(0.2f, -0.1f, 0.0f),
                        kMid + glm::vec3(0.1f, 0.1f, 0.0f), m, inf3, glm::vec3(0, 0, 1), nan3);
           // And on the floor, which the light reaches and every bounce hits.
           for (glm::vec3& n : s.normals)
             if (n == glm::vec3(0.0f)) n = glm::vec3(kNaN, 0.0f, 0.0f);
         });
       }},
      {"NaNAndInfUVs",
       [] {
         return cornell_with([](Scene& s) {
           for (size_t i = 0; i < s.uvs.size(); ++i)
             s.uvs[i] = i % 2 ? glm::vec2(kNaN) : glm::vec2(kInf, -kInf);
         });
       }},
      {"ZeroAreaEmitters",
       [] {
         return cornell_with([](Scene& s) {
           // Degenerate and collinear emitters next to the box's real light.
           const uint32_t e = add_material(s, emitter(50.0f));
           for (int i = 0; i < 20; ++i) {
             const glm::vec3 p = kMid + glm::vec3(0.01f * i - 0.1f, 0.1f, 0.0f);
             add_triangle(s, p, p, p, e);
             add_triangle(s, p, p + glm::vec3(0.05f, 0.0f, 0.0f), p + glm::vec3(0.1f, 0.0f, 0.0f), e);
           }
         });
       }},
      {"OnlyZeroAreaEmitters",
       [] {
         // No light at all once the degenerate emitters are discarded: a black, finite image.
         Scene s;
         test::add_mesh(s, test::grid_cube(glm::vec3(0.0f), 1.0f, 2), diffuse(0.5f));
         const uint32_t e = add_material(s, emitter(10.0f));
         add_triangle(s, glm::vec3(0.2f, 0.2f, 1.5f), glm::vec3(0.2f, 0.2f, 1.5f), glm::vec3(0.2f, 0.2f, 1.5f), e);
         add_triangle(s, glm::vec3(0.0f, 0.0f, 1.5f), glm::vec3(0.1f, 0.1f, 1.5f), glm::vec3(0.2f, 0.2f, 1.5f), e);
         return s;
       }},
      {"TinyTriangles1e-20",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.8f));
           const uint32_t e = add_material(s, emitter(5.0f));
           for (int i = 0; i < 50; ++i) {
             const glm::vec3 p = kMid + glm::vec3(0.004f * i - 0.1f, 0.0f, 0.0f);
             add_triangle(s, p, p + glm::vec3(1e-20f, 0.0f, 0.0f), p + glm::vec3(0.0f, 1e-20f, 0.0f),
                          i % 2 ? m : e);
           }
         });
       }},
      {"HugeGroundTriangle1e20",
       [] {
         return cornell_with([](Scene& s) {
           const uint32_t m = add_material(s, diffuse(0.5f));
           add_triangle(s, glm::vec3(-1e20f, -0.01f, 1e20f), glm::vec3(1e20f, -0.01f, 1e20f),
                        glm::vec3(0.0f, -0.01f, -1e20f), m);
         });
       }},
      {"WholeSceneAt1e-20", [] { return scaled(test::cornell_box(), 1e-20f); }},
      {"WholeSceneAt1e20", [] { return scaled(test::cornell_box(), 1e20f); }},
  };
}

class NoNaN : public ::testing::TestWithParam<NoNaNCase> {};

TEST_P(NoNaN, PtAndAoGiveFiniteImagesWithoutDroppedSamples) {
  const Scene scene = GetParam().scene();
  for (const char* integrator : {"pt", "ao"}) {
    SCOPED_TRACE(integrator);
    RenderSettings s;
    s.width = 24;
    s.height = 24;
    s.spp = 8;
    s.max_depth = 4;
    s.seed = 11;
    s.integrator = integrator;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    ASSERT_EQ(out.film.samples_per_pixel, 8u);
    size_t bad_mean = 0, bad_var = 0;
    for (float v : out.film.mean.rgb) bad_mean += !std::isfinite(v);
    for (float v : out.film.variance.rgb) bad_var += !std::isfinite(v);
    EXPECT_EQ(bad_mean, 0u) << "non-finite pixels in the image";
    EXPECT_EQ(bad_var, 0u) << "non-finite pixels in the variance";
    EXPECT_EQ(out.film.dropped_samples, 0u)
        << out.film.dropped_samples << " of " << 24 * 24 * 8 << " samples were NaN/Inf";
    double sum = 0.0;
    for (float v : out.film.mean.rgb) sum += v;
    std::cout << "[ NoNaN    ] " << GetParam().name << " " << integrator << ": mean "
              << sum / double(out.film.mean.rgb.size()) << ", dropped "
              << out.film.dropped_samples << "\n";
  }
}

INSTANTIATE_TEST_SUITE_P(Degenerate, NoNaN, ::testing::ValuesIn(no_nan_cases()),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });


// ---------------------------------------------------------------------------------------------
// ScaleInvariance: radiance does not depend on the unit of length, so the Cornell box scaled
// by k about the origin (camera included) must give the same image as at k = 1. With the same
// seed the sample paths are the same, so the means agree to float rounding (measured: 3e-5
// relative from k = 0.5 to 1e10); 1 % is a loose bound that still sees the failures below.
// The DISABLED_ cases fail today and are kept as the precise statement of what is wrong (see
// docs/robustness.md, "Findings"): run them with --gtest_also_run_disabled_tests.

struct Means {
  double pt = 0.0, ao = 0.0;
  uint32_t emitters = 0;
};

Means cornell_means(float k) {
  const Scene scene = scaled(test::cornell_box(), k);
  Means m;
  for (const char* integrator : {"pt", "ao"}) {
    RenderSettings s;
    s.width = 24;
    s.height = 24;
    s.spp = 32;
    s.max_depth = 4;
    s.seed = 11;
    s.integrator = integrator;
    Renderer r(test::device_context(), scene, s);
    const RenderOutput out = r.render();
    double sum = 0.0;
    for (float v : out.film.mean.rgb) sum += v;
    (std::string(integrator) == "pt" ? m.pt : m.ao) = sum / double(out.film.mean.rgb.size());
    m.emitters = out.stats.emitters;
  }
  return m;
}

void expect_same_as_unit_scale(std::initializer_list<float> scales) {
  static const Means unit = cornell_means(1.0f);
  for (float k : scales) {
    const Means m = cornell_means(k);
    EXPECT_NEAR(m.pt, unit.pt, 0.01 * unit.pt) << "pt at scale " << k;
    EXPECT_NEAR(m.ao, unit.ao, 0.01 * unit.ao) << "ao at scale " << k;
    EXPECT_EQ(m.emitters, unit.emitters) << "emitters at scale " << k;
  }
}

TEST(ScaleInvariance, CornellBoxFromHalfToTenBillion) {
  expect_same_as_unit_scale({0.5f, 2.0f, 1e3f, 1e6f, 1e10f});
}

// Fails today: pt is 8 % darker at k = 0.2 (an 11 cm box), 16 % at 0.01 and 22 % at 0.001
// (ao is unaffected down to 3e-3). Cause: offset_ray_origin (kernels/core/ray.cl) moves a
// ray origin by the absolute 1/65536 along the normal when a coordinate is below 1/32.
TEST(ScaleInvariance, SmallScenesAreLitLikeUnitScenes) {
  expect_same_as_unit_scale({0.2f, 0.01f, 1e-3f});
}

// Emitters of extreme area are kept: build_lights (host/render/light_table.cpp) takes a
// triangle's area in double. With glm::length of the float cross product it overflowed above
// ~1e19 m^2 and underflowed below ~1e-22 m^2, and those emitters were silently dropped.
TEST(ScaleInvariance, EmittersAreKeptAtExtremeAreas) {
  for (float k : {1e-13f, 1e11f}) EXPECT_EQ(cornell_means(k).emitters, 2u) << "scale " << k;
}

// A buffer whose file exists but is no file (issue 23, class 11: a folder or FIFO was reported
// "not found"): exit 2 naming the scene, the buffer and what the path is, without blocking on
// the FIFO or reading /dev/zero.
TEST(UnreadableInput, BufferThatIsAFolderFifoOrDeviceIsNamedAsSuch) {
  const fs::path valid = fs::path(CLPT_TEST_DATA_DIR) / "valid";
  struct Case {
    const char* kind;
    const char* says;
  };
  for (const Case& c : {Case{"folder", "is a directory, not a file"},
                        Case{"fifo", "is not a regular file"}, Case{"device", "is not a regular file"},
                        Case{"missing", "not found next to the scene file"}}) {
    SCOPED_TRACE(c.kind);
    TempDir dir;
    fs::copy_file(valid / "quad_trs_u8.gltf", dir / "quad.gltf");
    const fs::path bin = dir / "quad_trs_u8.bin";
    if (std::string(c.kind) == "folder") fs::create_directory(bin);
    if (std::string(c.kind) == "fifo") {
      ASSERT_EQ(::mkfifo(bin.c_str(), 0600), 0);
    }
    if (std::string(c.kind) == "device") fs::create_symlink("/dev/zero", bin);
    const Result r = run_clpt_env(tiny({dir / "quad.gltf", "-o", dir / "q.exr"}), {}, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, dir / "quad.gltf")) << r.err;
    EXPECT_TRUE(contains(r.err, "buffer 0 uri 'quad_trs_u8.bin'")) << r.err;
    EXPECT_TRUE(contains(r.err, c.says)) << r.err;
    EXPECT_FALSE(fs::exists(dir / "q.exr"));
  }
}
}  // namespace
}  // namespace clpt::robustness_test
