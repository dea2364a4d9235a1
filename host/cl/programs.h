// Every OpenCL program clpt builds, in one list: the integrators construct their programs
// from these rows, and `clpt --dump-kernels` writes each one's resolved source, so the
// compile checks of other vendors' compilers (scripts/kernel_compile_check.py) see exactly
// what a device is given.
#pragma once

#include <filesystem>
#include <vector>

#include "cl/program.h"

namespace clpt::programs {

inline constexpr cl::ProgramSpec kPt{"pt", "integrators/pt.cl", ""};  // pt and direct
inline constexpr cl::ProgramSpec kAo{"ao", "integrators/ao.cl", ""};
inline constexpr cl::ProgramSpec kLt{"lt", "integrators/lt.cl", ""};
inline constexpr cl::ProgramSpec kBdpt{"bdpt", "integrators/bdpt.cl", ""};
inline constexpr cl::ProgramSpec kPhoton{"photon", "integrators/photon.cl", ""};  // pm's maps
inline constexpr cl::ProgramSpec kPm{"pm", "integrators/pm.cl", ""};
inline constexpr cl::ProgramSpec kSppm{"sppm", "integrators/sppm.cl", ""};
inline constexpr cl::ProgramSpec kIc{"ic", "integrators/ic.cl", ""};
inline constexpr cl::ProgramSpec kIndirect1{"indirect1", "integrators/indirect1.cl", ""};
inline constexpr cl::ProgramSpec kPssmlt{"pssmlt", "integrators/mlt.cl", ""};
inline constexpr cl::ProgramSpec kMmlt{"mmlt", "integrators/mlt.cl", "-DCLPT_MLT_MULTIPLEXED=1"};
inline constexpr cl::ProgramSpec kVcm{"vcm", "integrators/vcm.cl", ""};
inline constexpr cl::ProgramSpec kAov{"aov", "integrators/aov.cl", ""};  // --aov, beside any integrator
inline constexpr cl::ProgramSpec kRaybench{"raybench", "tools/raybench.cl", ""};  // clpt-raybench

// All of the above, in this order.
const std::vector<cl::ProgramSpec>& all();

// Writes DIR/<name>.cl (the resolved source, #line markers included) for every program and
// DIR/programs.tsv (name, entry file, the full build options; a header line first). DIR
// must be absent, empty, or an earlier dump (it has programs.tsv); Error(Usage) otherwise,
// Error(Io) when a file cannot be written. Reads the kernels as a build would
// (CLPT_KERNEL_DIR included); needs no OpenCL device. Returns the number of programs.
size_t dump(const std::filesystem::path& dir);

}  // namespace clpt::programs
