// Files written before the HDF5 layout 2 (fixed-length strings, checksummed datasets) are still
// read by the stages' readers: a packing and a templates file of layout 1
// (tests/data/packing/README.md). A file written now is layout 2.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/hdf5_file.hpp"
#include "geometry/templates_file.hpp"
#include "packing/body_packing.hpp"

namespace shapepress {
namespace {

const std::filesystem::path data = std::filesystem::path(SHAPEPRESS_TEST_DATA) / "packing";

TEST(Hdf5Layout, APackingOfLayoutOneIsStillRead) {
  ASSERT_FALSE(H5Reader(data / "packed-layout1.h5").has_attribute("/", "shapepress_hdf5_layout"));
  EXPECT_TRUE(packing::is_body_packing(data / "packed-layout1.h5"));
  const packing::BodyPacking bed = packing::read_packing(data / "packed-layout1.h5");
  EXPECT_EQ(bed.bodies.size(), 6u);
  ASSERT_EQ(bed.templates.size(), 1u);
}

TEST(Hdf5Layout, ATemplatesFileOfLayoutOneIsStillRead) {
  const std::vector<geometry::TemplateRecord> records =
      geometry::read_templates(data / "templates-layout1.h5");
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records.front().body.radii.size(), 10u);
  EXPECT_FALSE(records.front().source.empty());
}

}  // namespace
}  // namespace shapepress
