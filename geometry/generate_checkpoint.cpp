#include "geometry/generate_checkpoint.hpp"

#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "common/checkpoint.hpp"
#include "common/error.hpp"

namespace shapepress::geometry {
namespace {

constexpr std::string_view generate_stage = "generate";
constexpr std::string_view record_prefix = "particles";

CheckpointState draw_state(std::size_t i, const BaseDraw& d) {
  return CheckpointState()
      .whole("particle", static_cast<std::int64_t>(i))
      .unsigned_whole("seed", d.seed)
      .whole("redraws", d.redraws);
}

// A particle's silhouettes: its shape choices' bins one after the other, `directions` each.
CheckpointState views_state(std::size_t pass, std::size_t i, const ChoiceViews& v) {
  std::vector<std::int64_t> bins;
  for (const std::vector<std::uint16_t>& choice : v)
    bins.insert(bins.end(), choice.begin(), choice.end());
  return CheckpointState()
      .whole("pass", static_cast<std::int64_t>(pass))
      .whole("particle", static_cast<std::int64_t>(i))
      .whole("directions", v.empty() ? 0 : static_cast<std::int64_t>(v.front().size()))
      .wholes("bins", bins);
}

CheckpointState correction_state(std::size_t i, const BoxCorrection& c) {
  std::vector<double> axes, factors;
  for (int k = 0; k < 9; ++k)
    axes.push_back(c.axes(k / 3, k % 3));
  for (int k = 0; k < 3; ++k)
    factors.push_back(c.factors[k]);
  return CheckpointState()
      .whole("particle", static_cast<std::int64_t>(i))
      .flag("applied", c.applied)
      .numbers("axes", axes)
      .numbers("factors", factors);
}

CheckpointState descriptors_state(std::size_t i, ShapeDescriptors d) {
  CheckpointState state;
  state.whole("particle", static_cast<std::int64_t>(i));
  const auto values = descriptor_scalars(d);
  for (std::size_t k = 0; k < descriptor_scalar_count; ++k)
    state.number(descriptor_scalar_names[k], *values[k]);
  state.numbers("projected_asr", d.projected_asr);
  return state;
}

// Reads one record's lists onto `work`, each continuing its list.
class RecordReader {
 public:
  RecordReader(std::size_t count, GenerateWork& work) : count_(count), work_(work) {}

  void read(const CheckpointFields& state) {
    for (const CheckpointFields& f : state.list("draws"))
      read_draw(f);
    for (const CheckpointFields& f : state.list("views"))
      read_views(f);
    for (const CheckpointFields& f : state.list("boxes"))
      read_correction(f);
    for (const CheckpointFields& f : state.list("descriptors"))
      read_descriptors(f);
  }

 private:
  // The particle of the next item of a list of `size`: it must be that one.
  void next_of(const CheckpointFields& f, std::size_t size, const char* what) const {
    const std::int64_t i = f.whole("particle");
    if (i != static_cast<std::int64_t>(size) || size >= count_)
      f.refuse("particle", fmt::format("is {}: {} of particle {} where particle {} of {} was due",
                                       i, what, i, size, count_));
  }
  void shaped(const CheckpointFields& f) const {
    if (work_.draws.size() != count_)
      f.refuse("particle", "is shaped before every particle was drawn");
  }

  void read_draw(const CheckpointFields& f) {
    next_of(f, work_.draws.size(), "a draw");
    BaseDraw d;
    d.seed = f.unsigned_whole("seed");
    d.redraws = static_cast<int>(f.whole("redraws", 0, 1000000));
    work_.draws.push_back(d);
  }

  void read_views(const CheckpointFields& f) {
    shaped(f);
    const auto pass = static_cast<std::size_t>(f.whole("pass", 0, 1));
    if (pass > work_.views.size() ||
        (pass == work_.views.size() && pass > 0 && work_.views.back().size() != count_))
      f.refuse("pass", fmt::format("is {}: silhouettes of a fit pass out of order", pass));
    if (pass == work_.views.size()) work_.views.emplace_back();
    std::vector<ChoiceViews>& views = work_.views[pass];
    next_of(f, views.size(), "silhouettes");
    const auto directions = static_cast<std::size_t>(f.whole("directions", 1, 10000));
    const std::vector<std::int64_t> bins = f.wholes("bins");
    if (bins.empty() || bins.size() % directions != 0 || bins.size() / directions > 10000)
      f.refuse("bins",
               fmt::format("holds {} bins, not whole shapes of {} views", bins.size(), directions));
    ChoiceViews v(bins.size() / directions, std::vector<std::uint16_t>(directions));
    for (std::size_t k = 0; k < bins.size(); ++k) {
      if (bins[k] < 0 || bins[k] > 0xffff) f.refuse("bins", fmt::format("holds bin {}", bins[k]));
      v[k / directions][k % directions] = static_cast<std::uint16_t>(bins[k]);
    }
    views.push_back(std::move(v));
  }

  void read_correction(const CheckpointFields& f) {
    shaped(f);
    next_of(f, work_.corrections.size(), "a box stretch");
    BoxCorrection c;
    c.applied = f.flag("applied");
    const std::vector<double> axes = f.numbers("axes"), factors = f.numbers("factors");
    if (axes.size() != 9) f.refuse("axes", fmt::format("holds {} numbers, not 9", axes.size()));
    if (factors.size() != 3)
      f.refuse("factors", fmt::format("holds {} numbers, not 3", factors.size()));
    for (int k = 0; k < 9; ++k)
      c.axes(k / 3, k % 3) = axes[static_cast<std::size_t>(k)];
    for (int k = 0; k < 3; ++k)
      c.factors[k] = factors[static_cast<std::size_t>(k)];
    work_.corrections.push_back(c);
  }

  void read_descriptors(const CheckpointFields& f) {
    const bool fitted = !work_.views.empty() && work_.views.back().size() == count_;
    if (!fitted && work_.corrections.size() != count_)
      f.refuse("particle", "is described before every particle was shaped");
    next_of(f, work_.descriptors.size(), "descriptors");
    ShapeDescriptors d;
    const auto values = descriptor_scalars(d);
    for (std::size_t k = 0; k < descriptor_scalar_count; ++k)
      *values[k] = f.number(descriptor_scalar_names[k]);
    d.projected_asr = f.numbers("projected_asr");
    if (d.projected_asr.size() > 10000)
      f.refuse("projected_asr", fmt::format("holds {} views", d.projected_asr.size()));
    work_.descriptors.push_back(std::move(d));
  }

  std::size_t count_;
  GenerateWork& work_;
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
  std::vector<CheckpointState> draws, views, boxes, descriptors;
  for (; draws_ < work.draws.size(); ++draws_)
    draws.push_back(draw_state(draws_, work.draws[draws_]));
  views_.resize(work.views.size(), 0);
  for (std::size_t pass = 0; pass < work.views.size(); ++pass)
    for (std::size_t& i = views_[pass]; i < work.views[pass].size(); ++i)
      views.push_back(views_state(pass, i, work.views[pass][i]));
  for (; corrections_ < work.corrections.size(); ++corrections_)
    boxes.push_back(correction_state(corrections_, work.corrections[corrections_]));
  for (; descriptors_ < work.descriptors.size(); ++descriptors_)
    descriptors.push_back(descriptors_state(descriptors_, work.descriptors[descriptors_]));
  write_checkpoint_record(checkpoint_record_path(folder_, record_prefix, work.steps()),
                          generate_stage, work.steps(),
                          CheckpointState()
                              .list("draws", std::move(draws))
                              .list("views", std::move(views))
                              .list("boxes", std::move(boxes))
                              .list("descriptors", std::move(descriptors)));
}

GenerateWork read_generate_checkpoints(const std::filesystem::path& folder, std::size_t count,
                                       std::int64_t& latest_step) {
  GenerateWork work;
  latest_step = 0;
  for (const auto& [step, file] : checkpoint_records(folder, record_prefix)) {
    const CheckpointRecord record = read_checkpoint_record(file, generate_stage);
    if (record.step != step)
      throw InputError(fmt::format("{}: key 'step' is {}, its name says {} (a damaged checkpoint)",
                                   file.string(), record.step, step));
    RecordReader(count, work).read(record.state());
    if (work.steps() != step)
      throw InputError(
          fmt::format("{}: its records end at step {}, its name says {} (a damaged checkpoint)",
                      file.string(), work.steps(), step));
    latest_step = step;
  }
  return work;
}

}  // namespace shapepress::geometry
