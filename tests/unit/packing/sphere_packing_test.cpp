// Reading a sphere packing from HDF5: a snapshot of bodies is refused, not read as loose spheres.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/hdf5_file.hpp"
#include "packing/packing.hpp"
#include "tests/support/errors.hpp"
#include "tests/support/files.hpp"

namespace shapepress::packing {
namespace {

// Two touching spheres as a snapshot writes them, with `extra` (a bond, a clump) when given.
std::filesystem::path two_spheres(const std::string& name, const std::string& extra) {
  const std::filesystem::path file = testing::fresh_directory(name) / "snapshot.h5";
  H5Writer out(file, Provenance{"test", "", std::nullopt});
  const std::vector<double> position{0.0, 0.0, 1e-4, 2e-4, 0.0, 1e-4}, radius{1e-4, 1e-4};
  out.write("/particles/position", position, {2, 3});
  out.write("/particles/radius", radius);
  if (extra == "bond") out.write("/bonds/pairs", std::vector<std::int32_t>{0, 1}, {1, 2});
  if (extra == "clump") out.write("/clumps/range", std::vector<std::int32_t>{0, 2}, {1, 2});
  out.commit();
  return file;
}

TEST(SpherePacking, ASnapshotOfSpheresReadsAsSpheres) {
  const SphereList spheres = read_spheres(two_spheres("spheres", ""));
  ASSERT_EQ(spheres.radius.size(), 2u);
  EXPECT_DOUBLE_EQ(spheres.x[1], 2e-4);
}

TEST(SpherePacking, ASnapshotOfBondedBodiesIsRefusedNamingRestart) {
  const std::filesystem::path file = two_spheres("bonded", "bond");
  const std::string message = testing::input_error_of([&] { read_spheres(file); });
  for (const std::string& part :
       {file.string(), std::string{"bonded (BMS)"}, std::string{"--restart"}})
    EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(SpherePacking, ASnapshotOfRigidClumpsIsRefused) {
  const std::filesystem::path file = two_spheres("rigid", "clump");
  const std::string message = testing::input_error_of([&] { read_spheres(file); });
  for (const std::string& part :
       {file.string(), std::string{"rigid (CMS)"}, std::string{"--restart"}})
    EXPECT_NE(message.find(part), std::string::npos) << message;
}

}  // namespace
}  // namespace shapepress::packing
