// GoogleTest main for suites that run the FEM solver: MPI through fem::Session
// for the whole process, and the same BLAS tuning as the program.
#include "fem/blas_tuning.hpp"
#include "fem/fem.hpp"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  fem::tune_blas_and_reexec(argv);
  fem::Session session(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
