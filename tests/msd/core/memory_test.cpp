// Memory estimated before allocating (msd/core/memory.hpp): the limit defaults
// to half the machine's memory, a grid over it is refused with the estimate,
// the limit and the field that raises it.
#include "msd/core/memory.hpp"

#include "msd/core/types.hpp"
#include "msd/mesh/cubic_grid.hpp"
#include "msd/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

TEST(Memory, TheDefaultLimitIsHalfOfThisMachinesMemory) {
  const double machine = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  EXPECT_EQ(msd::physical_memory_bytes(), machine);
  EXPECT_EQ(msd::MemoryLimit{}.effective_bytes(), 0.5 * machine);
  msd::MemoryLimit set;
  set.bytes = 2e9;
  EXPECT_EQ(set.effective_bytes(), 2e9);
}

TEST(Memory, AnEstimateOverTheLimitIsRefusedWithTheFiguresAndTheField) {
  msd::MemoryLimit limit;
  limit.bytes = 1e9;
  limit.how_to_raise = "mesh.memory_limit_gb in s.yaml";
  limit.context = "s.yaml: mesh.spacing 0.001 m: ";
  EXPECT_NO_THROW(msd::check_memory(1e6, 1000.0, "a solid", limit, ""));  // 1.0 GB: at the limit
  try {
    msd::check_memory(2e6, 1000.0, "a solid", limit, "");
    FAIL() << "2 GB passed a 1 GB limit";
  } catch (const msd::Error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("s.yaml: mesh.spacing 0.001 m: a solid of 2000000 cubes needs about 2.0 GB (1000 bytes per cube"),
              std::string::npos) << w;
    EXPECT_NE(w.find("more than the memory limit of 1.0 GB (set by mesh.memory_limit_gb in s.yaml)"), std::string::npos)
        << w;
    EXPECT_NE(w.find("raise mesh.memory_limit_gb in s.yaml or increase the grid spacing"), std::string::npos) << w;
  }
}

TEST(Memory, MeshingASampleChecksTheEstimateBeforeAllocating) {
  // A 1 m cube at 1 mm: 1e9 cubes, about 64 GB for the grid alone: refused at
  // once (a test that allocated it would not finish).
  const msd::TriangleMesh box = msd::make_box(msd::Vec3::Zero(), msd::Vec3(1, 1, 1));
  msd::SampleMeshOptions o;
  o.spacing = 0.001;
  o.max_cubes = 2'000'000'000;
  o.memory.bytes = 4e9;
  o.memory.how_to_raise = "mesh.memory_limit_gb in big.yaml";
  try {
    msd::mesh_closed_surface(box, o, "big.yaml: geometry");
    FAIL() << "a 1e9-cube grid was meshed";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("a grid of 1000000000 cubes needs about"), std::string::npos) << e.what();
  }
  // The solid stage: a grid that fits, a solid that does not.
  o.spacing = 0.01;  // 1e6 cubes: 64 MB of grid, 3 GB of solid at 3000 B
  o.memory.bytes = 1e9;
  try {
    msd::mesh_closed_surface(box, o, "big.yaml: geometry");
    FAIL() << "a solid over the limit was meshed";
  } catch (const msd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("a solid of 1000000 cubes needs about"), std::string::npos) << e.what();
  }
}
