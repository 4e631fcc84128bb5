#pragma once
// The one checkpoint format of the resumable stages (pack, compact, plate, generate;
// docs/stages.md, "Checkpoints and --resume"). A checkpoint record is a JSON file
// <prefix>_<step, 10 digits>.json in the run's checkpoint folder, written atomically:
//
//   {"format": "shapepress checkpoint", "version": 1, "stage": "compact", "step": 1200,
//    "state": {...}}
//
// `state` is what the stage has done so far, written through CheckpointState and read back
// through CheckpointFields, field by field and typed. A double is a JSON number with every bit
// (the shortest text that reads back to it), NaN and ±infinity the strings "nan", "inf" and
// "-inf" (JSON has none), so a resumed run continues from the very numbers it stopped at.
// A record that is not JSON or is cut short, of another stage or version, without a key or with
// a value of the wrong type is refused with an InputError naming the file and the key (exit 2).
// When records are due, the signals, resume.json and the run around them: common/resume.hpp.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace shapepress {

inline constexpr std::string_view checkpoint_format = "shapepress checkpoint";
inline constexpr std::int64_t checkpoint_version = 1;

// A stage's state, built field by field (keys in the order given).
class CheckpointState {
 public:
  CheckpointState& number(std::string_view key, double value);
  CheckpointState& numbers(std::string_view key, const std::vector<double>& values);
  CheckpointState& whole(std::string_view key, std::int64_t value);
  CheckpointState& unsigned_whole(std::string_view key, std::uint64_t value);
  CheckpointState& wholes(std::string_view key, const std::vector<std::int64_t>& values);
  CheckpointState& flag(std::string_view key, bool value);
  CheckpointState& text(std::string_view key, std::string value);
  CheckpointState& list(std::string_view key, std::vector<CheckpointState> items);
  const nlohmann::ordered_json& json() const { return json_; }

 private:
  nlohmann::ordered_json json_ = nlohmann::ordered_json::object();
};

// A read-only view of an object of a record (its state, or an item of a list in it) that names
// the file and the key ("state.records[3].gap") when a field is missing or of the wrong type.
// The record it views must outlive it.
class CheckpointFields {
 public:
  CheckpointFields(const nlohmann::json& object, std::filesystem::path file, std::string where);

  double number(std::string_view key) const;
  std::vector<double> numbers(std::string_view key) const;
  std::int64_t whole(std::string_view key) const;
  // A whole number in [least, most] (a count, an enumeration).
  std::int64_t whole(std::string_view key, std::int64_t least, std::int64_t most) const;
  std::uint64_t unsigned_whole(std::string_view key) const;
  std::vector<std::int64_t> wholes(std::string_view key) const;
  bool flag(std::string_view key) const;
  std::string text(std::string_view key) const;
  std::vector<CheckpointFields> list(std::string_view key) const;

  // InputError naming the file and the field `key` of this object, with `why`: for what only
  // the stage can judge (a phase out of order, a count that does not fit the run).
  [[noreturn]] void refuse(std::string_view key, std::string_view why) const;
  const std::filesystem::path& file() const { return file_; }

 private:
  const nlohmann::json& at(std::string_view key) const;
  std::string key_name(std::string_view key) const;

  const nlohmann::json* object_;
  std::filesystem::path file_;
  std::string where_;
};

// A record read back: which stage wrote it, at which step, and its state.
struct CheckpointRecord {
  std::filesystem::path file;
  std::string stage;
  std::int64_t step = 0;
  nlohmann::json document;
  CheckpointFields state() const;
};

// <folder>/<prefix>_<step, 10 digits>.json.
std::filesystem::path checkpoint_record_path(const std::filesystem::path& folder,
                                             std::string_view prefix, std::int64_t step);
// Writes the record atomically.
void write_checkpoint_record(const std::filesystem::path& file, std::string_view stage,
                             std::int64_t step, const CheckpointState& state);
// Reads the record of `stage` at `file`; InputError naming the file (and the key) when it is
// missing, not JSON or cut short, of another format, version or stage.
CheckpointRecord read_checkpoint_record(const std::filesystem::path& file, std::string_view stage);

// The records <prefix>_N.json in `folder`, by N increasing.
std::vector<std::pair<std::int64_t, std::filesystem::path>> checkpoint_records(
    const std::filesystem::path& folder, std::string_view prefix);
// Whether `folder` holds any record (a .json file besides resume.json): what a resumed run can
// continue from.
bool holds_checkpoints(const std::filesystem::path& folder);

}  // namespace shapepress
