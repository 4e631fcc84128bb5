#include "scenarios/compact_checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "common/error.hpp"
#include "common/resume.hpp"
#include "simulate/checkpoint.hpp"

namespace shapepress::scenarios {
namespace {

constexpr std::string_view history_magic = "shapepress compact checkpoint 1";

}  // namespace

void write_compact_checkpoint(const std::filesystem::path& out, const Engine& engine,
                              const ScenarioState& scenario, const Provenance& provenance,
                              const CheckpointHistory& history) {
  std::string text = fmt::format("{}\nsteps {}\n", history_magic, history.compaction.steps);
  const double loop_seconds = history.compaction.loop_seconds +
                              std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                            history.compaction.loop_started)
                                  .count();
  if (std::isfinite(loop_seconds)) text += fmt::format("loop_s {}\n", exact_text(loop_seconds));
  text += fmt::format("records {}\n", history.compaction.records.size());
  for (const PunchRecord& r : history.compaction.records)
    text +=
        fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", r.step, exact_text(r.time),
                    exact_text(r.gap), exact_text(r.strain), exact_text(r.top_force),
                    exact_text(r.bottom_force), exact_text(r.stress), exact_text(r.solid_fraction),
                    exact_text(r.solid_fraction_spheres), static_cast<int>(r.phase),
                    exact_text(r.kinetic_energy), exact_text(r.punch_work), r.sphere_contacts,
                    r.wall_contacts, exact_text(r.contacts_per_particle), r.intact_bonds);
  text += fmt::format("snapshots {}\n", history.snapshots.size());
  for (const SnapshotIndexEntry& e : history.snapshots)
    text += fmt::format("{} {} {} {} {} {} {}\n", e.file.generic_string(), exact_text(e.time),
                        e.spheres, e.walls, e.stress ? 1 : 0, e.bonds, e.clumps);
  const std::filesystem::path folder = out / std::string(checkpoint_folder);
  write_checkpoint(folder, engine, scenario, provenance, text);
  remove_checkpoints(folder, settle_checkpoint_prefix);
}

void write_settle_checkpoint(const std::filesystem::path& out, const Engine& engine,
                             const Provenance& provenance) {
  write_checkpoint(out / std::string(checkpoint_folder), engine, {}, provenance,
                   "shapepress compact settle checkpoint 1\n", settle_checkpoint_prefix);
}

CheckpointHistory read_checkpoint_history(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != history_magic)
    throw InputError(fmt::format("{}: not a compact checkpoint history", path.string()));
  // A word read ahead, to see whether an optional line is there, is the next count's name.
  std::string word;
  const auto count = [&](std::string_view what) {
    long long n = -1;
    const bool read =
        (!word.empty() || static_cast<bool>(in >> word)) && static_cast<bool>(in >> n);
    if (!read || word != what || n < 0)
      throw InputError(
          fmt::format("{}: no '{}' count (a damaged checkpoint)", path.string(), what));
    word.clear();
    return static_cast<std::size_t>(n);
  };
  const auto next = [&] {
    std::string token;
    if (!(in >> token))
      throw InputError(fmt::format("{}: truncated (a damaged checkpoint)", path.string()));
    return token;
  };
  CheckpointHistory h;
  h.compaction.steps = static_cast<std::int64_t>(count("steps"));
  // Checkpoints written before the loop's wall time was kept have no loop_s line: unknown.
  h.compaction.loop_seconds = NAN;
  word = next();
  if (word == "loop_s") {
    h.compaction.loop_seconds = parse_exact(next(), path);
    word.clear();
  }
  const std::size_t records = count("records");
  const auto real = [&] { return parse_exact(next(), path); };
  const auto whole = [&] { return static_cast<std::int64_t>(parse_exact(next(), path)); };
  for (std::size_t k = 0; k < records; ++k) {
    PunchRecord r;
    r.step = whole();
    r.time = real(), r.gap = real(), r.strain = real(), r.top_force = real();
    r.bottom_force = real(), r.stress = real(), r.solid_fraction = real();
    r.solid_fraction_spheres = real();
    r.phase = static_cast<PunchPhase>(whole());
    r.kinetic_energy = real(), r.punch_work = real();
    r.sphere_contacts = whole(), r.wall_contacts = whole();
    r.contacts_per_particle = real();
    r.intact_bonds = whole();
    h.compaction.records.push_back(r);
  }
  const std::size_t snapshots = count("snapshots");
  for (std::size_t k = 0; k < snapshots; ++k) {
    SnapshotIndexEntry e;
    e.file = next();
    e.time = real();
    e.spheres = static_cast<std::size_t>(whole());
    e.walls = static_cast<std::size_t>(whole());
    e.stress = whole() != 0;
    e.bonds = static_cast<std::size_t>(whole());
    e.clumps = static_cast<std::size_t>(whole());
    h.snapshots.push_back(e);
  }
  return h;
}

}  // namespace shapepress::scenarios
