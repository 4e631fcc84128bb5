// run.json: the SHA-256 of known strings and files (FIPS 180-2 examples), and a written record
// read back with its facts typed; a missing or mistyped fact is an error naming the file and key.
#include "common/run_metadata.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "common/error.hpp"
#include "common/provenance.hpp"
#include "common/sha256.hpp"
#include "tests/support/errors.hpp"
#include "tests/support/files.hpp"

namespace shapepress {
namespace {

using testing::input_error_of;

std::filesystem::path fresh_folder(const std::string& name) {
  return shapepress::testing::fresh_directory(name);
}

// FIPS 180-2, appendix B: the one-block, two-block and long-message examples, and the empty one.
TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // The 448-bit message: its padding needs a second block.
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  // A million 'a' fed in uneven pieces: the block boundaries fall everywhere.
  Sha256 hash;
  const std::string piece(997, 'a');
  std::size_t fed = 0;
  while (fed + piece.size() <= 1000000)
    hash.update(piece), fed += piece.size();
  hash.update(std::string(1000000 - fed, 'a'));
  EXPECT_EQ(hash.hex_digest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, OfAFileIsOfItsBytes) {
  const auto folder = fresh_folder("sha256_file");
  std::ofstream(folder / "abc.txt", std::ios::binary) << "abc";
  EXPECT_EQ(sha256_file(folder / "abc.txt"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // Longer than the 64 KiB chunk the file is streamed in.
  std::ofstream(folder / "million_a.txt", std::ios::binary) << std::string(1000000, 'a');
  EXPECT_EQ(sha256_file(folder / "million_a.txt"),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  std::ofstream(folder / "empty.txt", std::ios::binary).flush();
  EXPECT_EQ(sha256_file(folder / "empty.txt"), sha256_hex(""));
  EXPECT_NE(input_error_of([&] { sha256_file(folder / "none.txt"); }).find("none.txt"),
            std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST(RunMetadata, WrittenAndReadBackWithTypedFacts) {
  const auto folder = fresh_folder("run_metadata");
  std::ofstream(folder / "config.toml", std::ios::binary) << "abc";
  RunMetadata meta("compact", "shapepress compact --config config.toml --out run");
  meta.input("config", folder / "config.toml")
      .output("punch.csv")
      .fact("reference_gap_m", 0.0101)
      .fact("particles", 500)
      .fact("particle_kind", "sphere")
      .fact("normal_laws", nlohmann::json::array({"hertz"}));
  meta.write(folder / "run.json");

  const RunRecord record = RunRecord::read(folder / "run.json");
  EXPECT_EQ(record.stage(), "compact");
  EXPECT_DOUBLE_EQ(record.number("reference_gap_m"), 0.0101);
  EXPECT_EQ(record.integer("particles"), 500);
  EXPECT_DOUBLE_EQ(record.number("particles"), 500.0);  // an integer is a number too
  EXPECT_EQ(record.text("particle_kind"), "sphere");
  EXPECT_TRUE(record.has("normal_laws"));
  const nlohmann::json& j = record.json();
  EXPECT_EQ(j["schema"], run_metadata_schema);
  EXPECT_EQ(j["version"], shapepress_version());
  EXPECT_EQ(j["revision"], shapepress_git_revision());
  EXPECT_EQ(j["command"], "shapepress compact --config config.toml --out run");
  ASSERT_EQ(j["inputs"].size(), 1u);
  EXPECT_EQ(j["inputs"][0]["role"], "config");
  EXPECT_EQ(j["inputs"][0]["sha256"], sha256_hex("abc"));
  EXPECT_EQ(j["outputs"], nlohmann::json::array({"punch.csv"}));
  EXPECT_TRUE(j["facts"]["reference_gap_m"].is_number_float());  // not a string
  // Atomic: no temporary file is left beside it.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder))
    ++files;
  EXPECT_EQ(files, 2);
  std::filesystem::remove_all(folder);
}

TEST(RunMetadata, MissingOrMistypedFactsNameTheFileAndKey) {
  const auto folder = fresh_folder("run_metadata_bad");
  RunMetadata("plate", "shapepress plate").fact("fills", "4").write(folder / "run.json");
  const RunRecord record = RunRecord::read(folder / "run.json");
  const std::string missing = input_error_of([&] { record.integer("sub_spheres"); });
  EXPECT_NE(missing.find("run.json"), std::string::npos) << missing;
  EXPECT_NE(missing.find("sub_spheres"), std::string::npos) << missing;
  const std::string mistyped = input_error_of([&] { record.integer("fills"); });
  EXPECT_NE(mistyped.find("fills"), std::string::npos) << mistyped;
  EXPECT_NE(mistyped.find("integer"), std::string::npos) << mistyped;
  const std::string absent = input_error_of([&] { RunRecord::read(folder / "none" / "run.json"); });
  EXPECT_NE(absent.find("none/run.json"), std::string::npos) << absent;
  std::ofstream(folder / "broken.json") << "{\"stage\": ";
  EXPECT_NE(input_error_of([&] { RunRecord::read(folder / "broken.json"); }).find("JSON"),
            std::string::npos);
  std::ofstream(folder / "no_facts.json") << R"({"schema": 1, "stage": "plate"})";
  EXPECT_NE(input_error_of([&] { RunRecord::read(folder / "no_facts.json"); }).find("facts"),
            std::string::npos);
  // An input that is not there is named, not hashed as empty.
  RunMetadata meta("plate", "");
  EXPECT_NE(
      input_error_of([&] { meta.input("config", folder / "absent.toml"); }).find("absent.toml"),
      std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST(RunMetadata, BesideAnOutputFile) {
  EXPECT_EQ(run_metadata_beside("templates/bms.h5"), "templates/bms.h5.run.json");
}

}  // namespace
}  // namespace shapepress

namespace shapepress {
namespace {

// A run made from inside its bed's folder names its packing "packed.h5": a reader elsewhere finds
// it from the run's working directory, and never takes a file of that name with other content.
TEST(RunMetadata, ARelativeInputIsFoundFromTheRunsWorkingDirectoryAndCheckedByItsHash) {
  const std::filesystem::path dir = shapepress::testing::fresh_directory("run_input_file");
  const std::filesystem::path bed = dir / "bed";
  std::filesystem::create_directories(bed / "run");
  shapepress::testing::write_text(bed / "packed.h5", "the bed");
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(bed);
  RunMetadata meta("compact", "shapepress compact --packing packed.h5");
  meta.input("packing", "packed.h5");
  std::filesystem::current_path(dir);  // the reader runs elsewhere
  meta.write(bed / "run" / "run.json");
  const RunRecord record = RunRecord::read(bed / "run" / "run.json", "compact");
  EXPECT_EQ(record.input_file("packing"), (bed / "packed.h5").lexically_normal());
  EXPECT_EQ(record.json().at("working_directory").get<std::string>(), bed.generic_string());
  // Changed since: named, with where it looked.
  shapepress::testing::write_text(bed / "packed.h5", "another bed");
  const std::string message = testing::input_error_of([&] { (void)record.input_file("packing"); });
  EXPECT_NE(message.find("packing input packed.h5 is gone or changed"), std::string::npos)
      << message;
  EXPECT_NE(message.find((bed / "packed.h5").string()), std::string::npos) << message;
  EXPECT_NE(testing::input_error_of([&] {
              (void)record.input_file("templates");
            }).find("names no templates"),
            std::string::npos);
  std::filesystem::current_path(before);
}

}  // namespace
}  // namespace shapepress
