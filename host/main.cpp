#include "app/cli.h"

#ifdef CLPT_MPI
#include "mpi/mpi_cluster.h"
#endif

int main(int argc, char** argv) {
#ifdef CLPT_MPI
  // Under mpirun, the ranks render together (docs/scaling.md); MPI is finalised at return.
  const auto cluster = clpt::start_mpi_if_launched(&argc, &argv);
  return clpt::run_cli(argc, argv, cluster.get());
#else
  return clpt::run_cli(argc, argv);
#endif
}
