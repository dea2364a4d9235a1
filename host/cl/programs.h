// Every OpenCL program clpt builds, in one list: the integrators construct their programs
// from these rows, and `clpt --dump-kernels` writes each one's resolved source, so the
// compile checks of other vendors' compilers (scripts/kernel_compile_check.py) see exactly
// what a device is given.
#pragma once

#include <filesystem>
#include <vector>

#include "cl/program.h"

namespace clpt::programs {

// Intel's GPUs (Xe-HPG and later) can give a thread 256 registers instead of 128, at half the
// threads per execution unit. Every megakernel below spills at 128 (Intel's ocloc for dg2:
// pt_render around 745, mmlt's mlt_mutate 1 390; docs/BENCHMARKS.md), and scratch traffic in
// the traversal loop costs more than the threads it would keep resident, so they ask for 256,
// as Intel's own Triton backend does for kernels that spill (it rebuilds them with this
// option). Drivers for GPUs without the large register file (Xe-LP: tgllp) ignore it; one that
// refuses it builds without (cl::Program's optional options). ao and raybench do not spill and
// keep 128, as does aov (its first-hit kernel spills 61 at 128 and still 54 at 256: not worth
// half its threads).
inline constexpr const char* kIntelLargeGrf = "-cl-intel-256-GRF-per-thread";

inline constexpr cl::ProgramSpec kPt{"pt", "integrators/pt.cl", "", kIntelLargeGrf};  // pt and direct
inline constexpr cl::ProgramSpec kAo{"ao", "integrators/ao.cl", ""};
inline constexpr cl::ProgramSpec kLt{"lt", "integrators/lt.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kBdpt{"bdpt", "integrators/bdpt.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kPhoton{"photon", "integrators/photon.cl", "", kIntelLargeGrf};  // pm's maps
inline constexpr cl::ProgramSpec kPm{"pm", "integrators/pm.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kSppm{"sppm", "integrators/sppm.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kIc{"ic", "integrators/ic.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kIndirect1{"indirect1", "integrators/indirect1.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kPssmlt{"pssmlt", "integrators/mlt.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kMmlt{"mmlt", "integrators/mlt.cl", "-DCLPT_MLT_MULTIPLEXED=1",
                                       kIntelLargeGrf};
inline constexpr cl::ProgramSpec kVcm{"vcm", "integrators/vcm.cl", "", kIntelLargeGrf};
inline constexpr cl::ProgramSpec kAov{"aov", "integrators/aov.cl", ""};  // --aov, beside any integrator
inline constexpr cl::ProgramSpec kRaybench{"raybench", "tools/raybench.cl", ""};  // clpt-raybench

// All of the above, in this order.
const std::vector<cl::ProgramSpec>& all();

// Writes DIR/<name>.cl (the resolved source, #line markers included) for every program and
// DIR/programs.tsv (name, entry file, the full build options, the options Intel GPUs are
// given on top of them; a header line first). DIR
// must be absent, empty, or an earlier dump (it has programs.tsv); Error(Usage) otherwise,
// Error(Io) when a file cannot be written. Reads the kernels as a build would
// (CLPT_KERNEL_DIR included); needs no OpenCL device. Returns the number of programs.
size_t dump(const std::filesystem::path& dir);

}  // namespace clpt::programs
