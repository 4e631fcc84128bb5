// The two imaging stages as a user runs them: synth-images then shape-stats, the files they
// write, and every bad-input case of issue 7 (exit 2, cause and file named; a mixed batch
// still processes the good images).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/command.hpp"

namespace shapepress::imaging {
namespace {

namespace fs = std::filesystem;
using shapepress::testing::run_shapepress;

class ShapeStatsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("shapepress_e2e_imaging_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static nlohmann::json read_json(const std::string& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  }
  static int data_rows(const std::string& csv) {
    std::ifstream in(csv);
    std::string line;
    int rows = -1;  // the header
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') ++rows;
    return rows;
  }
  void write_pgm(const std::string& name, int w, int h, const std::function<int(int, int)>& value) {
    std::ofstream out(path(name), std::ios::binary);
    out << "P5\n" << w << " " << h << "\n255\n";
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        out.put(static_cast<char>(value(x, y)));
  }
  fs::path dir_;
};

TEST_F(ShapeStatsCli, SyntheticSemImagesEndToEnd) {
  auto synth = run_shapepress("-q synth-images --out " + path("syn") +
                              " --images 2 --touching-fraction 0 --pixel-size 0.8um");
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  auto stats = run_shapepress("-q shape-stats " + path("syn/synth_000.tif") + " " +
                              path("syn/synth_001.tif") + " --out " + path("stats"));
  ASSERT_EQ(stats.exit_code, 0) << stats.output;
  for (const char* file : {"particles.csv", "summary.json", "overlays/synth_000_overlay.png",
                           "overlays/synth_001_overlay.png", "plots/size_distribution.png",
                           "plots/asr_histogram.png", "plots/fourier_spectrum.png"})
    EXPECT_TRUE(fs::exists(path("stats/") + file)) << file;

  const int truth =
      data_rows(path("syn/synth_000_truth.csv")) + data_rows(path("syn/synth_001_truth.csv"));
  EXPECT_EQ(data_rows(path("stats/particles.csv")), truth);  // no touching pairs: exact count
  nlohmann::json s = read_json(path("stats/summary.json"));
  EXPECT_EQ(s["particle_count"].get<int>(), truth);
  // Pixel size and information bar come from the FEI metadata written by synth-images.
  EXPECT_EQ(s["images"][0]["pixel_size_source"], "sem-metadata");
  EXPECT_DOUBLE_EQ(s["images"][0]["pixel_size_m"].get<double>(), 8e-7);
  EXPECT_EQ(s["images"][0]["info_bar_rows"].get<int>(), 40);
  // The keys the geometry stage reads. Sizes: synth's default median is 50 px = 40 µm
  // (log-normal, clamped to 30–120 px), so x50 (volume) lies between 24 and 96 µm.
  for (const char* key : {"D2", "D3", "D8", "decay_exponent"})
    EXPECT_TRUE(s["fourier"][key].is_number()) << key;
  EXPECT_GT(s["size"]["x50_m"].get<double>(), 24e-6);
  EXPECT_LT(s["size"]["x50_m"].get<double>(), 96e-6);
  EXPECT_LE(s["size"]["x10_m"].get<double>(), s["size"]["x50_m"].get<double>());
  EXPECT_LE(s["size"]["x50_m"].get<double>(), s["size"]["x90_m"].get<double>());
  EXPECT_EQ(s["asr"]["quantiles"].size(), s["asr"]["quantile_levels"].size());
  EXPECT_GT(s["asr"]["mean"].get<double>(), 0.4);
  EXPECT_LE(s["asr"]["mean"].get<double>(), 1.0);
  // Both stages wrote their run.json: the settings and counts typed, the images hashed.
  const nlohmann::json synth_run = read_json(path("syn/run.json"));
  EXPECT_EQ(synth_run["stage"], "synth-images");
  EXPECT_EQ(synth_run["facts"]["images"], 2);
  EXPECT_EQ(synth_run["facts"]["particles"], truth);
  EXPECT_DOUBLE_EQ(synth_run["facts"]["pixel_size_m"].get<double>(), 8e-7);
  const nlohmann::json stats_run = read_json(path("stats/run.json"));
  EXPECT_EQ(stats_run["stage"], "shape-stats");
  EXPECT_EQ(stats_run["facts"]["particles"], truth);
  EXPECT_EQ(stats_run["facts"]["images"], 2);
  ASSERT_EQ(stats_run["inputs"].size(), 2u);
  EXPECT_EQ(stats_run["inputs"][0]["role"], "image");
  EXPECT_EQ(stats_run["inputs"][0]["sha256"].get<std::string>().size(), 64u);
}

TEST_F(ShapeStatsCli, PngNeedsAPixelSizeAndFindsTheBar) {
  ASSERT_EQ(run_shapepress("-q synth-images --out " + path("syn") + " --format png").exit_code, 0);
  auto missing =
      run_shapepress("-q shape-stats " + path("syn/synth_000.png") + " --out " + path("a"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("pixel size unknown"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("synth_000.png"), std::string::npos) << missing.output;
  auto given = run_shapepress("-q shape-stats " + path("syn/synth_000.png") +
                              " --pixel-size 0.5um --out " + path("b"));
  ASSERT_EQ(given.exit_code, 0) << given.output;
  nlohmann::json s = read_json(path("b/summary.json"));
  EXPECT_EQ(s["images"][0]["pixel_size_source"], "--pixel-size");
  EXPECT_EQ(s["images"][0]["info_bar_rows"].get<int>(), 40);  // detected: no metadata in a PNG
}

TEST_F(ShapeStatsCli, BadInputsAreNamed) {
  auto missing =
      run_shapepress("-q shape-stats " + path("nope.tif") + " --pixel-size 1um --out " + path("o"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("nope.tif: no such image file"), std::string::npos)
      << missing.output;

  std::ofstream(path("notes.png")) << "not an image";
  auto unreadable = run_shapepress("-q shape-stats " + path("notes.png") +
                                   " --pixel-size 1um --out " + path("o"));
  EXPECT_EQ(unreadable.exit_code, 2);
  EXPECT_NE(unreadable.output.find("cannot be read as an image"), std::string::npos)
      << unreadable.output;

  std::ofstream(path("empty.png")).close();
  auto empty = run_shapepress("-q shape-stats " + path("empty.png") + " --pixel-size 1um --out " +
                              path("o"));
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.output.find("empty file"), std::string::npos) << empty.output;

  write_pgm("black.pgm", 64, 64, [](int, int) { return 0; });
  auto black = run_shapepress("-q shape-stats " + path("black.pgm") + " --pixel-size 1um --out " +
                              path("o"));
  EXPECT_EQ(black.exit_code, 2);
  EXPECT_NE(black.output.find("uniform"), std::string::npos) << black.output;

  // One particle, cut by the image edge: excluded like ImageJ's "exclude on edges".
  write_pgm("edge.pgm", 100, 100,
            [](int x, int y) { return std::hypot(x - 2, y - 50) < 20 ? 220 : 30; });
  auto none =
      run_shapepress("-q shape-stats " + path("edge.pgm") + " --pixel-size 1um --out " + path("o"));
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.output.find("no particle found"), std::string::npos) << none.output;
  EXPECT_FALSE(fs::exists(path("o/summary.json")));  // nothing processed: nothing written
  auto kept = run_shapepress("-q shape-stats " + path("edge.pgm") +
                             " --pixel-size 1um --keep-edge-particles --crop-bottom 10 --out " +
                             path("kept"));
  EXPECT_EQ(kept.exit_code, 0) << kept.output;
  EXPECT_EQ(data_rows(path("kept/particles.csv")), 1);
  EXPECT_EQ(read_json(path("kept/summary.json"))["images"][0]["height_px"].get<int>(), 90);

  auto bad_option = run_shapepress("-q shape-stats " + path("edge.pgm") +
                                   " --pixel-size 1um --split-neck 2 --out " + path("o"));
  EXPECT_EQ(bad_option.exit_code, 2);
  EXPECT_NE(bad_option.output.find("--split-neck"), std::string::npos) << bad_option.output;
}

TEST_F(ShapeStatsCli, MixedBatchProcessesTheGoodImages) {
  ASSERT_EQ(run_shapepress("-q synth-images --out " + path("syn")).exit_code, 0);
  std::ofstream(path("broken.tif")) << "II*\0garbage";
  auto batch = run_shapepress("-q --threads 2 shape-stats " + path("missing.tif") + " " +
                              path("syn/synth_000.tif") + " " + path("broken.tif") + " --out " +
                              path("stats"));
  EXPECT_EQ(batch.exit_code, 2) << batch.output;  // something was skipped
  EXPECT_NE(batch.output.find("missing.tif"), std::string::npos) << batch.output;
  EXPECT_NE(batch.output.find("broken.tif"), std::string::npos) << batch.output;
  nlohmann::json s = read_json(path("stats/summary.json"));
  EXPECT_EQ(s["images"].size(), 1u);
  EXPECT_EQ(s["skipped"].size(), 2u);
  EXPECT_GT(s["particle_count"].get<int>(), 30);
}

TEST_F(ShapeStatsCli, BlobsSampleImage) {
  auto run = run_shapepress("-q shape-stats " + std::string(SHAPEPRESS_TEST_DATA) +
                            "/imaging/blobs_raw.pgm --pixel-size 1um --out " + path("blobs"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // ImageJ finds 46 blobs off the edges at threshold 128 (blobs_raw_imagej.csv); Otsu, the
  // neck split and the 20 px minimum area move that by a few.
  int n = data_rows(path("blobs/particles.csv"));
  EXPECT_GE(n, 40);
  EXPECT_LE(n, 60);
}

// Issue 22: ImageJ's sample GIF read, the --imagej preset giving ImageJ's own count on a real
// photograph (tests/data/imaging/coins_ij_ws0.csv: 23), with its watershed too (issue 42), and
// a file that is not a readable image (a truncated GIF) an exit 2 naming it.
TEST_F(ShapeStatsCli, ImageJPresetAndGifInput) {
  const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/imaging/";
  auto coins = run_shapepress("-q shape-stats " + data + "coins.png --imagej --polarity bright " +
                              "--pixel-size 1um --no-overlays --out " + path("coins"));
  ASSERT_EQ(coins.exit_code, 0) << coins.output;
  EXPECT_EQ(data_rows(path("coins/particles.csv")), 23);

  auto blobs = run_shapepress("-q shape-stats " + data + "blobs.gif --imagej --split imagej " +
                              "--pixel-size 1um --no-overlays --out " + path("blobs"));
  ASSERT_EQ(blobs.exit_code, 0) << blobs.output;
  EXPECT_EQ(data_rows(path("blobs/particles.csv")), 47);  // ImageJ's Watershed: 47

  // --split imagej takes ImageJ's tolerance, 0.5 px, unless --split-prominence is given: on
  // gravel's top-right quarter ImageJ's watershed finds 235 (gravel256_tr_ij_ws1.csv), 229 with
  // 0.6 px, the prominence flood's default.
  auto gravel = run_shapepress("-q shape-stats " + data +
                               "gravel256_tr.png --imagej --split imagej --polarity bright " +
                               "--pixel-size 1um --no-overlays --out " + path("gravel"));
  ASSERT_EQ(gravel.exit_code, 0) << gravel.output;
  EXPECT_EQ(data_rows(path("gravel/particles.csv")), 235);

  { std::ofstream(path("truncated.gif"), std::ios::binary) << "GIF89a"; }
  auto bad = run_shapepress("-q shape-stats " + path("truncated.gif") + " --pixel-size 1um --out " +
                            path("bad"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("truncated.gif: cannot be read as an image"), std::string::npos)
      << bad.output;
}

// Issue 22: a 16-bit TIFF end to end. blobs16.tif holds blobs_raw.pgm's values × 257 (written by
// ImageJ): shape-stats writes the same particles for both, row by row and column by column
// (within float rounding: 1e-6 relative), image name aside; and a file in a format that is not
// read (a Targa image) is an exit 2 naming it.
TEST_F(ShapeStatsCli, SixteenBitTiffGivesTheParticlesOfItsEightBitTwin) {
  const std::string data = std::string(SHAPEPRESS_TEST_DATA) + "/imaging/";
  for (const char* image : {"blobs16.tif", "blobs_raw.pgm"}) {
    auto run = run_shapepress("-q shape-stats " + data + image + " --polarity bright " +
                              "--pixel-size 1m --no-overlays --out " + path(image));
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  auto rows = [](const std::string& csv) {  // the numbers of each data row, image name left out
    std::ifstream in(csv);
    std::vector<std::vector<double>> table;
    bool header = true;
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      if (std::exchange(header, false)) continue;
      std::vector<double> row;
      std::istringstream fields(line.substr(line.find(',') + 1));
      for (std::string field; std::getline(fields, field, ',');)
        row.push_back(std::stod(field));
      table.push_back(row);
    }
    return table;
  };
  const auto deep = rows(path("blobs16.tif/particles.csv"));
  const auto eight = rows(path("blobs_raw.pgm/particles.csv"));
  EXPECT_GT(deep.size(), 40u);
  ASSERT_EQ(deep.size(), eight.size());
  for (std::size_t i = 0; i < deep.size(); ++i) {
    ASSERT_EQ(deep[i].size(), eight[i].size());
    for (std::size_t k = 0; k < deep[i].size(); ++k)
      EXPECT_NEAR(deep[i][k], eight[i][k], 1e-6 * std::max(1.0, std::abs(eight[i][k])))
          << "particle " << i + 1 << " column " << k + 2;
  }

  // An uncompressed 2×2 true-colour Targa (a valid file): OpenCV reads no Targa.
  {
    std::ofstream tga(path("photo.tga"), std::ios::binary);
    const unsigned char header[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, 0};
    tga.write(reinterpret_cast<const char*>(header), sizeof header);
    for (int i = 0; i < 12; ++i)
      tga.put(static_cast<char>(i * 20));
  }
  auto tga = run_shapepress("-q shape-stats " + path("photo.tga") + " --pixel-size 1um --out " +
                            path("tga"));
  EXPECT_EQ(tga.exit_code, 2) << tga.output;
  EXPECT_NE(tga.output.find("photo.tga: cannot be read as an image"), std::string::npos)
      << tga.output;
}

}  // namespace
}  // namespace shapepress::imaging
