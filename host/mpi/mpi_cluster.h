// MPI ranks as a Cluster (render/cluster.h): `mpirun -n K clpt scene.gltf ...` splits one render
// across K processes, on one machine or many (docs/scaling.md). Built into the clpt executable
// only, where CMake finds MPI (CLPT_MPI); the library, the tests and the Python module never
// link MPI.
#pragma once

#include <memory>

#include "render/cluster.h"

namespace clpt {

// MPI started when this process was launched by mpirun, srun or another MPI launcher (their
// environment says so); null otherwise, so that a plain `clpt` never initialises MPI. MPI is
// finalised when the returned object is destroyed.
std::unique_ptr<Cluster> start_mpi_if_launched(int* argc, char*** argv);

}  // namespace clpt
