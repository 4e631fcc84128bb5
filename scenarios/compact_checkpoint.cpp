#include "scenarios/compact_checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress::scenarios {
namespace {

constexpr std::string_view history_magic = "shapepress compact checkpoint 1";

std::filesystem::path folder_of(const std::filesystem::path& out) {
  return out / std::string(checkpoint_folder);
}

std::filesystem::path invocation_path(const std::filesystem::path& out) {
  return folder_of(out) / "resume.json";
}

// Hexadecimal floats: the history must give back every bit of a record (the summary and the
// quasi-static check are judged over them as the uninterrupted run judges them).
std::string exact(double value) {
  return fmt::format("{:a}", value);
}

double parse_exact(const std::string& token, const std::filesystem::path& path) {
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0')
    throw InputError(
        fmt::format("{}: '{}' is not a number (a damaged checkpoint)", path.string(), token));
  return value;
}

}  // namespace

void write_invocation(const std::filesystem::path& out, const CompactInvocation& i) {
  const nlohmann::ordered_json json{{"command", i.command_line},
                                    {"working_directory", i.working_directory.string()},
                                    {"config", i.config},
                                    {"packing", i.packing},
                                    {"restart", i.restart},
                                    {"steps", i.steps},
                                    {"config_sha256", i.config_sha256}};
  write_file_atomically(invocation_path(out), json.dump(2) + "\n");
}

CompactInvocation read_invocation(const std::filesystem::path& out) {
  const std::filesystem::path path = invocation_path(out);
  std::ifstream in(path);
  if (!in)
    throw InputError(fmt::format(
        "{}: no compaction to resume here ({} is missing: the folder is not a compact --out, or "
        "the run finished)",
        out.string(), path.string()));
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    CompactInvocation i;
    i.command_line = j.at("command").get<std::string>();
    i.working_directory = j.at("working_directory").get<std::string>();
    i.config = j.at("config").get<std::string>();
    i.packing = j.at("packing").get<std::string>();
    i.restart = j.at("restart").get<std::string>();
    i.steps = j.at("steps").get<std::int64_t>();
    i.config_sha256 = j.at("config_sha256").get<std::string>();
    return i;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not a resume record ({})", path.string(), e.what()));
  }
}

void write_checkpoint(const std::filesystem::path& out, const Engine& engine,
                      const ScenarioState& scenario, const Provenance& provenance,
                      const CheckpointHistory& history, std::size_t keep) {
  const std::filesystem::path folder = folder_of(out);
  const std::string stem = fmt::format("step_{:010d}", engine.step_index());
  write_snapshot(folder / (stem + ".h5"), engine, scenario, provenance);
  std::string text = fmt::format("{}\nsteps {}\nrecords {}\n", history_magic,
                                 history.compaction.steps, history.compaction.records.size());
  for (const PunchRecord& r : history.compaction.records)
    text += fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", r.step, exact(r.time),
                        exact(r.gap), exact(r.strain), exact(r.top_force), exact(r.bottom_force),
                        exact(r.stress), exact(r.solid_fraction), exact(r.solid_fraction_spheres),
                        static_cast<int>(r.phase), exact(r.kinetic_energy), exact(r.punch_work),
                        r.sphere_contacts, r.wall_contacts, exact(r.contacts_per_particle),
                        r.intact_bonds);
  text += fmt::format("snapshots {}\n", history.snapshots.size());
  for (const SnapshotIndexEntry& e : history.snapshots)
    text += fmt::format("{} {} {} {} {} {} {}\n", e.file.generic_string(), exact(e.time), e.spheres,
                        e.walls, e.stress ? 1 : 0, e.bonds, e.clumps);
  write_file_atomically(folder / (stem + ".history"), text);

  // The newest `keep` whole checkpoints stay; older ones, and snapshots whose history never
  // came (a kill between the two files), go.
  std::vector<CheckpointFiles> whole;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".history" &&
        std::filesystem::exists(p.parent_path() / (p.stem().string() + ".h5")))
      whole.push_back({0, p.parent_path() / (p.stem().string() + ".h5"), p});
  }
  std::sort(whole.begin(), whole.end(), [](const auto& a, const auto& b) {
    return a.history.filename() > b.history.filename();
  });
  for (std::size_t k = keep; k < whole.size(); ++k) {
    std::filesystem::remove(whole[k].history, ec);
    std::filesystem::remove(whole[k].snapshot, ec);
  }
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path p = entry.path();
    if (p.extension() == ".h5" && p.stem().string() < stem &&
        !std::filesystem::exists(p.parent_path() / (p.stem().string() + ".history")))
      std::filesystem::remove(p, ec);
  }
}

std::optional<CheckpointFiles> latest_checkpoint(const std::filesystem::path& out) {
  static const std::regex name(R"(step_(\d{10})\.history)");
  std::optional<CheckpointFiles> latest;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder_of(out), ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const std::filesystem::path snapshot =
        entry.path().parent_path() / ("step_" + m[1].str() + ".h5");
    if (!std::filesystem::exists(snapshot)) continue;
    const std::int64_t step = std::stoll(m[1].str());
    if (!latest || step > latest->step) latest = CheckpointFiles{step, snapshot, entry.path()};
  }
  return latest;
}

CheckpointHistory read_checkpoint_history(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != history_magic)
    throw InputError(fmt::format("{}: not a compact checkpoint history", path.string()));
  const auto count = [&](std::string_view what) {
    std::string word;
    long long n = -1;
    if (!(in >> word >> n) || word != what || n < 0)
      throw InputError(
          fmt::format("{}: no '{}' count (a damaged checkpoint)", path.string(), what));
    return static_cast<std::size_t>(n);
  };
  CheckpointHistory h;
  h.compaction.steps = static_cast<std::int64_t>(count("steps"));
  const std::size_t records = count("records");
  const auto next = [&] {
    std::string token;
    if (!(in >> token))
      throw InputError(fmt::format("{}: truncated (a damaged checkpoint)", path.string()));
    return token;
  };
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
  if (h.compaction.records.empty())
    throw InputError(fmt::format("{}: no records (a damaged checkpoint)", path.string()));
  return h;
}

void remove_stale_temporaries(const std::filesystem::path& folder) {
  static const std::regex temporary(R"(\..+\.tmp\.\d+)");
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (std::regex_match(entry.path().filename().string(), temporary))
      std::filesystem::remove(entry.path(), ec);
}

}  // namespace shapepress::scenarios
