// Outputs are atomic: a writer killed mid-write leaves nothing under the final name; HDF5 files
// round-trip and carry provenance; an unwritable folder is an input error naming the path.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/hdf5_file.hpp"

namespace shapepress {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class FilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("shapepress-files-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

TEST_F(FilesTest, AtomicFileAppearsOnlyOnCommit) {
  fs::path target = folder_ / "out.csv";
  {
    AtomicOutputFile file(target);
    file.stream() << "a,b\n1,2\n";
    EXPECT_FALSE(fs::exists(target));
    file.commit();
  }
  std::ifstream in(target);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "a,b");
}

TEST_F(FilesTest, UncommittedFileLeavesNothing) {
  fs::path target = folder_ / "abandoned.csv";
  {
    AtomicOutputFile file(target);
    file.stream() << "partial";
  }
  EXPECT_FALSE(fs::exists(target));
  EXPECT_TRUE(fs::is_empty(folder_)) << "temporary file left behind";
}

// A child process writes slowly and is SIGKILLed mid-write: no file under the final name.
TEST_F(FilesTest, WriterKilledMidWriteLeavesNoFinalFile) {
  fs::path csv_target = folder_ / "killed.csv";
  fs::path h5_target = folder_ / "killed.h5";
  fs::path started = folder_ / "started";
  pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    AtomicOutputFile file(csv_target);
    H5Writer h5(h5_target, Provenance{"test", "", 1});
    std::vector<double> values(1000, 1.0);
    h5.write("/particles/x", values);
    std::ofstream(started) << "1";
    for (;;) {
      file.stream() << "1,2,3\n";
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  for (int i = 0; i < 500 && !fs::exists(started); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(started)) << "writer never started";
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_FALSE(fs::exists(csv_target));
  EXPECT_FALSE(fs::exists(h5_target));
}

TEST_F(FilesTest, UnwritableFolderIsAnInputErrorNamingThePath) {
  fs::path locked = folder_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  fs::path target = locked / "sub" / "out.csv";
  if (::geteuid() == 0) {
    // root may write anywhere; a path under a regular file is unwritable for everyone.
    std::ofstream(folder_ / "file") << "x";
    target = folder_ / "file" / "out.csv";
  }
  try {
    AtomicOutputFile file(target);
    FAIL() << "wrote into an unwritable place";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(target.parent_path().string()));
  }
  fs::permissions(locked, fs::perms::owner_all);
}

TEST_F(FilesTest, Hdf5RoundTripWithProvenanceAndUnits) {
  fs::path target = folder_ / "data.h5";
  std::vector<double> x{1.0, 2.5, -3.0, 4.0, 5.0, 6.0};
  std::vector<std::int64_t> ids{7, 8, 9};
  std::vector<std::int32_t> counts{1, 2};
  std::vector<std::uint8_t> flags{0, 1, 1};
  {
    H5Writer writer(target, Provenance{"shapepress test", "a = 1\n", 42});
    writer.write("/particles/position", x, {2, 3});
    writer.unit("/particles/position", "m");
    writer.write("/particles/id", ids);
    writer.write("/bonds/count", counts);
    writer.write("/bonds/intact", flags);
    writer.write_strings("/names", {"bottom", "punch"});
    writer.attribute("/particles", "count", std::int64_t{2});
    writer.attribute("/particles", "time_s", 1.5e-3);
    writer.commit();
  }
  H5Reader reader(target);
  std::vector<std::size_t> shape;
  EXPECT_EQ(reader.doubles("/particles/position", &shape), x);
  EXPECT_EQ(shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(reader.int64s("/particles/id"), ids);
  EXPECT_EQ(reader.int32s("/bonds/count"), counts);
  EXPECT_EQ(reader.uint8s("/bonds/intact"), flags);
  EXPECT_EQ(reader.strings("/names"), (std::vector<std::string>{"bottom", "punch"}));
  EXPECT_EQ(reader.attribute_string("/particles/position", "unit"), "m");
  EXPECT_EQ(reader.attribute_int64("/particles", "count"), 2);
  EXPECT_DOUBLE_EQ(reader.attribute_double("/particles", "time_s"), 1.5e-3);
  EXPECT_EQ(reader.attribute_string("/", "command_line"), "shapepress test");
  EXPECT_EQ(reader.attribute_string("/", "config_text"), "a = 1\n");
  EXPECT_EQ(reader.attribute_int64("/", "seed"), 42);
  EXPECT_FALSE(reader.attribute_string("/", "shapepress_version").empty());
  EXPECT_FALSE(reader.attribute_string("/", "git_revision").empty());
  EXPECT_TRUE(reader.has("/particles/id"));
  EXPECT_FALSE(reader.has("/walls/punch"));
  EXPECT_THAT(reader.members("/particles"), ::testing::ElementsAre("id", "position"));
}

TEST_F(FilesTest, Hdf5ReaderNamesMissingFileWrongFileAndMissingDataset) {
  EXPECT_THROW(H5Reader(folder_ / "none.h5"), InputError);
  std::ofstream(folder_ / "text.h5") << "not hdf5";
  try {
    H5Reader reader(folder_ / "text.h5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("not an HDF5 file"));
  }
  {
    H5Writer writer(folder_ / "ok.h5", Provenance{});
    writer.write("/a", std::vector<double>{1.0});
    writer.commit();
  }
  H5Reader reader(folder_ / "ok.h5");
  try {
    reader.doubles("/particles/radius");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/particles/radius"));
    EXPECT_THAT(e.what(), HasSubstr("ok.h5"));
  }
}

// The bytes of `file` with one bit flipped in the values `bytes` (found where the file holds
// them): a change of the last digit of a number, which only a checksum can see.
std::string with_a_bit_flipped(const fs::path& file, const std::string& bytes) {
  std::ifstream in(file, std::ios::binary);
  std::string image((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = image.find(bytes);
  EXPECT_NE(at, std::string::npos) << "the values are not stored as they are in " << file;
  if (at != std::string::npos) image[at] = static_cast<char>(image[at] ^ 0x01);
  return image;
}

TEST_F(FilesTest, Hdf5DamagedValuesStringsAndAttributesAreAnInputErrorNamingTheFile) {
  const fs::path target = folder_ / "data.h5";
  const std::vector<double> x{1.0, 2.5, -3.0, 4.0, 5.0, 6.0};
  {
    H5Writer writer(target, Provenance{"shapepress test", "a = 1\n", 42});
    writer.write("/particles/position", x, {2, 3});
    writer.write_strings("/names", {"bottom", "punch"});
    writer.attribute("/particles", "material", std::string_view("powder-material"));
    writer.commit();
  }
  const auto refused = [&](const std::string& image, const auto& read) {
    std::ofstream(folder_ / "damaged.h5", std::ios::binary) << image;
    try {
      const H5Reader reader(folder_ / "damaged.h5");
      read(reader);
      ADD_FAILURE() << "the damage was not seen";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("damaged.h5"));
    }
  };
  // A dataset's values: Fletcher-32.
  refused(with_a_bit_flipped(
              target, std::string(reinterpret_cast<const char*>(x.data()), sizeof(double) * 2)),
          [](const H5Reader& r) { r.doubles("/particles/position"); });
  // Fixed-length strings in a dataset, and in an attribute (the object header's checksum).
  refused(with_a_bit_flipped(target, "bottom"), [](const H5Reader& r) { r.strings("/names"); });
  refused(with_a_bit_flipped(target, "powder-material"),
          [](const H5Reader& r) { r.attribute_string("/particles", "material"); });
}

TEST_F(FilesTest, Hdf5StringsAreFixedLengthAndEmptyOnesRoundTrip) {
  const fs::path target = folder_ / "strings.h5";
  {
    H5Writer writer(target, Provenance{});
    writer.write_strings("/names", {"", "a much longer name", "b"});
    writer.write_strings("/none", {});
    writer.attribute("/", "empty", std::string_view());
    writer.commit();
  }
  const H5Reader reader(target);
  EXPECT_EQ(reader.strings("/names"), (std::vector<std::string>{"", "a much longer name", "b"}));
  EXPECT_TRUE(reader.strings("/none").empty());
  EXPECT_EQ(reader.attribute_string("/", "empty"), "");
  EXPECT_EQ(reader.attribute_int64("/", "shapepress_hdf5_layout"), 2);
}

TEST_F(FilesTest, CsvRoundTripWithCommentsAndUnitsInNames) {
  fs::path target = folder_ / "punch.csv";
  {
    CsvWriter csv(target, {"time_s", "force_N"});
    csv.comment("H0_m = 0.0525");
    csv.row({0.0, 1.0});
    csv.row({1e-6, 2.5});
    csv.commit();
  }
  CsvTable table = read_csv(target);
  EXPECT_EQ(table.columns, (std::vector<std::string>{"time_s", "force_N"}));
  EXPECT_EQ(table.column("force_N"), (std::vector<double>{1.0, 2.5}));
  EXPECT_THROW(table.column("stress_Pa"), InputError);
}

}  // namespace
}  // namespace shapepress
