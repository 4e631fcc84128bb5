#pragma once
// run.json: the typed record every stage writes beside its outputs (issue 17, point 4). Facts
// that later stages need (H0, the die area, the sub-sphere count, the fills, ...) travel here as
// JSON numbers and strings under fixed keys, not as prose in CSV comment lines: rewording a
// comment for people can no longer break a reader. The CSV comments stay, for people.
//
//   {"schema": 1, "stage": "compact", "version": "0.1.0", "revision": "3f2a9c1e0b7d",
//    "command": "shapepress compact --config c.toml --out run",
//    "options": {"config": "c.toml", "packing": null, "steps": null, "out": "run"},
//    "inputs": [{"role": "config", "path": "c.toml", "sha256": "…"}],
//    "outputs": ["punch.csv"],
//    "facts": {"reference_gap_m": 0.0102, "die_area_m2": 1e-4, "particles": 500, …}}
//
// Fact keys carry their SI unit as a suffix, like the CSV columns (_m, _m2, _m3, _s, _N, _Pa);
// counts and names have none.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace shapepress {

// The file name in a run folder. Stages whose --out is a file (fill's templates, describe's CSV)
// write "<that file>.run.json" beside it instead: two outputs may share a folder.
inline constexpr std::string_view run_metadata_name = "run.json";
// Bumped when a key changes meaning or is removed (adding keys does not bump it).
inline constexpr int run_metadata_schema = 1;

// Where the run.json of an output file (not folder) goes: "templates/bms.h5.run.json".
std::filesystem::path run_metadata_beside(const std::filesystem::path& output_file);

class RunMetadata {
 public:
  RunMetadata(std::string stage, std::string command_line);

  // An input file, hashed now: the content the stage read, even if the file changes later.
  // `role` says what it was ("config", "packing", "reference", "image", ...). InputError naming
  // the file if it cannot be read.
  RunMetadata& input(std::string_view role, const std::filesystem::path& path);
  // An output, relative to the run folder (or the file name), so a moved folder stays valid.
  RunMetadata& output(const std::filesystem::path& relative);
  // A typed fact (kept in the order given, so run.json reads like the stage's own summary):
  // numbers stay numbers, names strings, lists arrays; a non-finite number is
  // written as null (JSON has no NaN), which a reader asking for a number rejects.
  RunMetadata& fact(const std::string& key, nlohmann::ordered_json value);

  const nlohmann::ordered_json& facts() const { return facts_; }
  // The effective command-line options of the run, typed (common/command_options.hpp): a stage
  // with an options table gives them; the key is absent otherwise.
  RunMetadata& options(nlohmann::ordered_json options);
  nlohmann::ordered_json json() const;
  // Atomically (common/atomic_file.hpp), so a killed stage never leaves half a run.json.
  void write(const std::filesystem::path& path) const;

 private:
  std::string stage_, command_line_;
  // Where the stage ran: its relative input paths are relative to it.
  std::filesystem::path working_directory_;
  nlohmann::ordered_json inputs_ = nlohmann::ordered_json::array();
  nlohmann::ordered_json outputs_ = nlohmann::ordered_json::array();
  nlohmann::ordered_json facts_ = nlohmann::ordered_json::object();
  nlohmann::ordered_json options_;
};

// A run.json read back. Every accessor throws InputError naming the file and the key when the
// fact is missing or has the wrong type: a reader never guesses a value.
class RunRecord {
 public:
  // InputError naming the file when it is missing, not JSON, or lacks stage/facts.
  static RunRecord read(const std::filesystem::path& path);
  // The same, and InputError naming both when another stage made it.
  static RunRecord read(const std::filesystem::path& path, std::string_view stage);

  const std::filesystem::path& path() const { return path_; }
  const std::string& stage() const { return stage_; }
  const nlohmann::json& json() const { return json_; }
  bool has(const std::string& key) const;
  double number(const std::string& key) const;
  std::int64_t integer(const std::string& key) const;
  std::string text(const std::string& key) const;
  // The input of `role` as a file that exists now and holds what the run read (its SHA-256). A
  // relative path is tried from the run's working directory ("working_directory"), the current
  // one, the run's folder and the folder above it (a run made from inside its bed's folder, before
  // run.json named its working directory). InputError naming the run.json, the role and every
  // place tried when none holds it.
  std::filesystem::path input_file(const std::string& role) const;

 private:
  const nlohmann::json& fact(const std::string& key, std::string_view expected) const;
  std::filesystem::path path_;
  std::string stage_;
  nlohmann::json json_;
};

}  // namespace shapepress
