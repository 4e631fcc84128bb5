#include "scenarios/plate_checkpoint.hpp"

#include <fmt/format.h>

#include <fstream>
#include <mutex>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "scenarios/plate_run.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

constexpr std::string_view history_magic = "shapepress plate checkpoint 1";
constexpr std::string_view finished_magic = "shapepress plate fill 1";

// One lock for the folder's files: the fills of an ensemble write them from their threads.
std::mutex& files_lock() {
  static std::mutex lock;
  return lock;
}

std::string prefix(int fill) {
  return fmt::format("fill{}", fill);
}

std::filesystem::path finished_file(const std::filesystem::path& folder, int fill) {
  return folder / (prefix(fill) + ".rows");
}

std::string rows_text(const std::vector<PlateRow>& rows) {
  std::string text = fmt::format("rows {}\n", rows.size());
  for (const PlateRow& r : rows)
    text += fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", exact_text(r.time),
                        exact_text(r.deformation), exact_text(r.approach), exact_text(r.top_force),
                        exact_text(r.bottom_force), exact_text(r.hertz_force), r.contacts,
                        r.intact_bonds, exact_text(r.kinetic_energy), exact_text(r.work),
                        exact_text(r.cpu_seconds), exact_text(r.wall_seconds),
                        exact_text(r.top_force_sd), exact_text(r.top_force_min),
                        exact_text(r.top_force_max));
  return text;
}

// Reads `key value` pairs and rows back from a checkpoint's text, naming the file when damaged.
class Reader {
 public:
  explicit Reader(std::filesystem::path path) : path_(std::move(path)), in_(path_) {}
  void expect_magic(std::string_view magic) {
    std::string line;
    if (!in_ || !std::getline(in_, line) || line != magic)
      throw InputError(fmt::format("{}: not a plate checkpoint", path_.string()));
  }
  std::string word(std::string_view key) {
    std::string name, value;
    if (!(in_ >> name >> value) || name != key)
      throw InputError(fmt::format("{}: no '{}' (a damaged checkpoint)", path_.string(), key));
    return value;
  }
  double number(std::string_view key) { return parse_exact(word(key), path_); }
  std::string line(std::string_view key) {
    std::string name, rest;
    if (!(in_ >> name) || name != key || !std::getline(in_ >> std::ws, rest))
      throw InputError(fmt::format("{}: no '{}' (a damaged checkpoint)", path_.string(), key));
    return rest;
  }
  std::vector<PlateRow> rows() {
    const auto count = static_cast<std::size_t>(number("rows"));
    std::vector<PlateRow> rows(count);
    for (PlateRow& r : rows) {
      std::string t[15];
      for (std::string& token : t)
        if (!(in_ >> token))
          throw InputError(
              fmt::format("{}: a row cut short (a damaged checkpoint)", path_.string()));
      const auto at = [&](int k) { return parse_exact(t[k], path_); };
      r = PlateRow{at(0),
                   at(1),
                   at(2),
                   at(3),
                   at(4),
                   at(5),
                   static_cast<std::int64_t>(at(6)),
                   static_cast<std::int64_t>(at(7)),
                   at(8),
                   at(9),
                   at(10),
                   at(11),
                   at(12),
                   at(13),
                   at(14)};
    }
    return rows;
  }

 private:
  std::filesystem::path path_;
  std::ifstream in_;
};

}  // namespace

PlateCheckpoints::PlateCheckpoints(std::filesystem::path folder, CheckpointPolicy policy,
                                   Provenance provenance, bool final_snapshot)
    : folder_(std::move(folder)),
      policy_(policy),
      provenance_(std::move(provenance)),
      final_snapshot_(final_snapshot) {}

std::optional<PlateRunOutcome> PlateCheckpoints::finished(int fill) const {
  const std::lock_guard<std::mutex> lock(files_lock());
  const std::filesystem::path path = finished_file(folder_, fill);
  if (!std::filesystem::exists(path)) return std::nullopt;
  Reader in(path);
  in.expect_magic(finished_magic);
  PlateRunOutcome o;
  o.spheres = static_cast<std::size_t>(in.number("spheres"));
  o.bonds = static_cast<std::size_t>(in.number("bonds"));
  o.requested_spheres = static_cast<std::size_t>(in.number("requested_spheres"));
  o.sub_sphere_radius = in.number("sub_sphere_radius");
  o.time_step = in.number("time_step");
  o.description = in.line("description");
  o.rows = in.rows();
  return o;
}

void PlateCheckpoints::finish(int fill, const PlateRunOutcome& o) const {
  const std::lock_guard<std::mutex> lock(files_lock());
  if (fill == 0 && final_snapshot_) write_plate_snapshot(folder_, o, provenance_);
  write_file_atomically(
      finished_file(folder_, fill),
      fmt::format("{}\nspheres {}\nbonds {}\nrequested_spheres {}\nsub_sphere_radius {}\n"
                  "time_step {}\ndescription {}\n",
                  finished_magic, o.spheres, o.bonds, o.requested_spheres,
                  exact_text(o.sub_sphere_radius), exact_text(o.time_step), o.description) +
          rows_text(o.rows));
  simulate::remove_checkpoints(folder_, prefix(fill));
}

PlateHooks PlateCheckpoints::hooks(int fill) const {
  PlateHooks hooks;
  {
    const std::lock_guard<std::mutex> lock(files_lock());
    if (const auto latest = simulate::latest_checkpoint(folder_, prefix(fill))) {
      Reader in(latest->history);
      in.expect_magic(history_magic);
      PlateProgress progress;
      progress.cpu_seconds = in.number("cpu_s");
      progress.wall_seconds = in.number("wall_s");
      progress.rows = in.rows();
      hooks.resume = PlateResumePoint{read_snapshot(latest->snapshot), std::move(progress)};
    }
  }
  // Each fill keeps its own clock: the fills' checkpoints come at their own steps.
  auto clock = std::make_shared<CheckpointClock>(policy_);
  hooks.after_step = [this, fill, clock](const Engine& engine,
                                         const std::function<PlateProgress()>& progress) {
    if (!clock->due(engine.step_index())) return true;
    const PlateProgress p = progress();
    const std::string text = fmt::format("{}\ncpu_s {}\nwall_s {}\n", history_magic,
                                         exact_text(p.cpu_seconds), exact_text(p.wall_seconds)) +
                             rows_text(p.rows);
    {
      const std::lock_guard<std::mutex> lock(files_lock());
      simulate::write_checkpoint(folder_, engine, {}, provenance_, text, prefix(fill));
    }
    clock->taken();
    return SignalCheckpoints::received() == 0;
  };
  return hooks;
}

}  // namespace shapepress::scenarios
