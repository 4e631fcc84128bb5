#include "geometry/generate_checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/resume.hpp"

namespace shapepress::geometry {
namespace {

constexpr std::string_view magic = "shapepress generate checkpoint 1";

// The scalar descriptors in the order of a `describe` line (projected_asr follows them).
constexpr std::size_t descriptor_scalars = 14;
std::array<double*, descriptor_scalars> scalars(ShapeDescriptors& d) {
  return {&d.volume_m3,
          &d.area_m2,
          &d.L_m,
          &d.I_m,
          &d.S_m,
          &d.asr,
          &d.elongation,
          &d.flatness,
          &d.sphericity,
          &d.convexity,
          &d.volume_equivalent_diameter_m,
          &d.projected_equivalent_diameter_m,
          &d.projected_asr_mean,
          &d.projected_asr_std};
}

// (Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on " " + text.)
void append_exact(std::string& text, double value) {
  text += ' ';
  text += exact_text(value);
}

void append_draw(std::string& text, std::size_t i, const BaseDraw& d) {
  text += fmt::format("draw {} {} {}\n", i, d.seed, d.redraws);
}

void append_views(std::string& text, std::size_t pass, std::size_t i, const ChoiceViews& v) {
  text += fmt::format("views {} {} {} {}", pass, i, v.size(), v.empty() ? 0 : v.front().size());
  for (const std::vector<std::uint16_t>& choice : v)
    for (std::uint16_t bin : choice)
      text += fmt::format(" {}", bin);
  text += '\n';
}

void append_correction(std::string& text, std::size_t i, const BoxCorrection& c) {
  text += fmt::format("box {} {}", i, c.applied ? 1 : 0);
  for (int k = 0; k < 9; ++k)
    append_exact(text, c.axes(k / 3, k % 3));
  for (int k = 0; k < 3; ++k)
    append_exact(text, c.factors[k]);
  text += '\n';
}

void append_descriptors(std::string& text, std::size_t i, ShapeDescriptors d) {
  text += fmt::format("describe {}", i);
  for (const double* value : scalars(d))
    append_exact(text, *value);
  text += fmt::format(" {}", d.projected_asr.size());
  for (double ratio : d.projected_asr)
    append_exact(text, ratio);
  text += '\n';
}

// Reads one file's records onto `work`, each continuing its list.
class RecordReader {
 public:
  RecordReader(std::filesystem::path file, std::size_t count, GenerateWork& work)
      : file_(std::move(file)), count_(count), work_(work) {}

  void read() {
    std::ifstream in(file_);
    std::string line;
    if (!in || !std::getline(in, line) || line != magic)
      fail(fmt::format("not a generate checkpoint (no '{}' line)", magic));
    bool ended = false;
    while (std::getline(in, line)) {
      if (ended) fail("a record after 'end'");
      line_.clear();
      line_.str(line);
      std::string kind;
      line_ >> kind;
      if (kind == "draw") {
        read_draw();
      } else if (kind == "views") {
        read_views();
      } else if (kind == "box") {
        read_correction();
      } else if (kind == "describe") {
        read_descriptors();
      } else if (kind == "end") {
        ended = true;
      } else {
        fail(fmt::format("unknown record '{}'", kind));
      }
    }
    if (!ended) fail("no 'end' line (a truncated file)");
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(fmt::format("{}: {} (a damaged checkpoint)", file_.string(), why));
  }

  std::string token() {
    std::string t;
    if (!(line_ >> t)) fail("a record cut short");
    return t;
  }
  std::uint64_t integer() {
    const std::string t = token();
    if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos || t.size() > 20)
      fail(fmt::format("'{}' is not a count", t));
    return std::stoull(t);
  }
  double real() { return parse_exact(token(), file_); }
  // The index of the next record of a list of `size`: it must be that size.
  void next_of(std::size_t size, const char* what) {
    const std::uint64_t i = integer();
    if (i != size || i >= count_)
      fail(fmt::format("{} of particle {} where particle {} of {} was due", what, i, size, count_));
  }
  void shaped() const {
    if (work_.draws.size() != count_) fail("a shape before every particle was drawn");
  }

  void read_draw() {
    next_of(work_.draws.size(), "a draw");
    BaseDraw d;
    d.seed = integer();
    d.redraws = static_cast<int>(std::min<std::uint64_t>(integer(), 1000000));
    work_.draws.push_back(d);
  }

  void read_views() {
    shaped();
    const std::uint64_t pass = integer();
    if (pass > work_.views.size() || pass > 1 ||
        (pass == work_.views.size() && pass > 0 && work_.views.back().size() != count_))
      fail(fmt::format("silhouettes of fit pass {} out of order", pass));
    if (pass == work_.views.size()) work_.views.emplace_back();
    std::vector<ChoiceViews>& views = work_.views[pass];
    next_of(views.size(), "silhouettes");
    const std::uint64_t choices = integer(), directions = integer();
    if (choices == 0 || choices > 10000 || directions == 0 || directions > 10000)
      fail(fmt::format("{} shapes of {} views", choices, directions));
    ChoiceViews v(choices, std::vector<std::uint16_t>(directions));
    for (std::vector<std::uint16_t>& choice : v)
      for (std::uint16_t& bin : choice) {
        const std::uint64_t b = integer();
        if (b > 0xffff) fail(fmt::format("bin {}", b));
        bin = static_cast<std::uint16_t>(b);
      }
    views.push_back(std::move(v));
  }

  void read_correction() {
    shaped();
    next_of(work_.corrections.size(), "a box stretch");
    BoxCorrection c;
    c.applied = integer() != 0;
    for (int k = 0; k < 9; ++k)
      c.axes(k / 3, k % 3) = real();
    for (int k = 0; k < 3; ++k)
      c.factors[k] = real();
    work_.corrections.push_back(c);
  }

  void read_descriptors() {
    const bool fitted = !work_.views.empty() && work_.views.back().size() == count_;
    if (!fitted && work_.corrections.size() != count_)
      fail("descriptors before every particle was shaped");
    next_of(work_.descriptors.size(), "descriptors");
    ShapeDescriptors d;
    for (double* value : scalars(d))
      *value = real();
    const std::uint64_t directions = integer();
    if (directions > 10000) fail(fmt::format("{} views", directions));
    for (std::uint64_t k = 0; k < directions; ++k)
      d.projected_asr.push_back(real());
    work_.descriptors.push_back(std::move(d));
  }

  std::filesystem::path file_;
  std::size_t count_;
  GenerateWork& work_;
  std::istringstream line_;
};

}  // namespace

GenerateCheckpoints::GenerateCheckpoints(std::filesystem::path folder, const GenerateWork& written)
    : folder_(std::move(folder)),
      draws_(written.draws.size()),
      corrections_(written.corrections.size()),
      descriptors_(written.descriptors.size()) {
  for (const std::vector<ChoiceViews>& pass : written.views)
    views_.push_back(pass.size());
}

void GenerateCheckpoints::write(const GenerateWork& work) {
  std::string text(magic);
  text += '\n';
  for (; draws_ < work.draws.size(); ++draws_)
    append_draw(text, draws_, work.draws[draws_]);
  views_.resize(work.views.size(), 0);
  for (std::size_t pass = 0; pass < work.views.size(); ++pass)
    for (std::size_t& i = views_[pass]; i < work.views[pass].size(); ++i)
      append_views(text, pass, i, work.views[pass][i]);
  for (; corrections_ < work.corrections.size(); ++corrections_)
    append_correction(text, corrections_, work.corrections[corrections_]);
  for (; descriptors_ < work.descriptors.size(); ++descriptors_)
    append_descriptors(text, descriptors_, work.descriptors[descriptors_]);
  text += "end\n";
  write_file_atomically(folder_ / fmt::format("particles_{:010d}.history", work.steps()), text);
}

GenerateWork read_generate_checkpoints(const std::filesystem::path& folder, std::size_t count,
                                       std::int64_t& latest_step) {
  static const std::regex name(R"(particles_(\d{10})\.history)");
  std::vector<std::pair<std::int64_t, std::filesystem::path>> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, m, name)) files.emplace_back(std::stoll(m[1].str()), entry.path());
  }
  std::sort(files.begin(), files.end());
  GenerateWork work;
  latest_step = 0;
  for (const auto& [step, file] : files) {
    RecordReader(file, count, work).read();
    if (work.steps() != step)
      throw InputError(
          fmt::format("{}: its records end at step {}, its name says {} (a damaged checkpoint)",
                      file.string(), work.steps(), step));
    latest_step = step;
  }
  return work;
}

}  // namespace shapepress::geometry
