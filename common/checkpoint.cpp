#include "common/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace shapepress {
namespace {

// JSON has no NaN or infinity: they are words.
nlohmann::ordered_json exact_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return value;
}

std::string shown(const nlohmann::json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

}  // namespace

CheckpointState& CheckpointState::number(std::string_view key, double value) {
  json_[std::string(key)] = exact_number(value);
  return *this;
}

CheckpointState& CheckpointState::numbers(std::string_view key, const std::vector<double>& values) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (double value : values)
    list.push_back(exact_number(value));
  json_[std::string(key)] = std::move(list);
  return *this;
}

CheckpointState& CheckpointState::whole(std::string_view key, std::int64_t value) {
  json_[std::string(key)] = value;
  return *this;
}

CheckpointState& CheckpointState::unsigned_whole(std::string_view key, std::uint64_t value) {
  json_[std::string(key)] = value;
  return *this;
}

CheckpointState& CheckpointState::wholes(std::string_view key,
                                         const std::vector<std::int64_t>& values) {
  json_[std::string(key)] = values;
  return *this;
}

CheckpointState& CheckpointState::flag(std::string_view key, bool value) {
  json_[std::string(key)] = value;
  return *this;
}

CheckpointState& CheckpointState::text(std::string_view key, std::string value) {
  json_[std::string(key)] = std::move(value);
  return *this;
}

CheckpointState& CheckpointState::list(std::string_view key, std::vector<CheckpointState> items) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (CheckpointState& item : items)
    list.push_back(std::move(item.json_));
  json_[std::string(key)] = std::move(list);
  return *this;
}

CheckpointFields::CheckpointFields(const nlohmann::json& object, std::filesystem::path file,
                                   std::string where)
    : object_(&object), file_(std::move(file)), where_(std::move(where)) {}

std::string CheckpointFields::key_name(std::string_view key) const {
  return where_.empty() ? std::string(key) : where_ + "." + std::string(key);
}

void CheckpointFields::refuse(std::string_view key, std::string_view why) const {
  throw InputError(
      fmt::format("{}: key '{}' {} (a damaged checkpoint)", file_.string(), key_name(key), why));
}

const nlohmann::json& CheckpointFields::at(std::string_view key) const {
  if (!object_->is_object()) refuse(key, "is in something that is not an object");
  const auto found = object_->find(key);
  if (found == object_->end()) refuse(key, "is missing");
  return *found;
}

namespace {

// A number of a record: a JSON number, or NaN and ±infinity by name; none when it is not one.
std::optional<double> number_of(const nlohmann::json& value) {
  if (value.is_number()) return value.get<double>();
  if (value == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (value == "inf") return std::numeric_limits<double>::infinity();
  if (value == "-inf") return -std::numeric_limits<double>::infinity();
  return std::nullopt;
}

std::optional<std::int64_t> whole_of(const nlohmann::json& value) {
  if (value.is_number_integer() && !value.is_number_unsigned()) return value.get<std::int64_t>();
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() <=
          static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    return static_cast<std::int64_t>(value.get<std::uint64_t>());
  return std::nullopt;
}

}  // namespace

double CheckpointFields::number(std::string_view key) const {
  const nlohmann::json& value = at(key);
  const std::optional<double> x = number_of(value);
  if (!x) refuse(key, fmt::format("is {}, not a number", shown(value)));
  return *x;
}

std::vector<double> CheckpointFields::numbers(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_array()) refuse(key, fmt::format("is {}, not a list of numbers", shown(value)));
  std::vector<double> numbers;
  numbers.reserve(value.size());
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::optional<double> x = number_of(value[k]);
    if (!x)
      refuse(fmt::format("{}[{}]", key, k), fmt::format("is {}, not a number", shown(value[k])));
    numbers.push_back(*x);
  }
  return numbers;
}

std::int64_t CheckpointFields::whole(std::string_view key) const {
  const nlohmann::json& value = at(key);
  const std::optional<std::int64_t> n = whole_of(value);
  if (!n) refuse(key, fmt::format("is {}, not a whole number", shown(value)));
  return *n;
}

std::int64_t CheckpointFields::whole(std::string_view key, std::int64_t least,
                                     std::int64_t most) const {
  const std::int64_t n = whole(key);
  if (n < least || n > most) refuse(key, fmt::format("is {}, not in [{}, {}]", n, least, most));
  return n;
}

std::uint64_t CheckpointFields::unsigned_whole(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_number_unsigned() && !(value.is_number_integer() && value.get<std::int64_t>() >= 0))
    refuse(key, fmt::format("is {}, not a whole number >= 0", shown(value)));
  return value.get<std::uint64_t>();
}

std::vector<std::int64_t> CheckpointFields::wholes(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_array())
    refuse(key, fmt::format("is {}, not a list of whole numbers", shown(value)));
  std::vector<std::int64_t> wholes;
  wholes.reserve(value.size());
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::optional<std::int64_t> n = whole_of(value[k]);
    if (!n)
      refuse(fmt::format("{}[{}]", key, k),
             fmt::format("is {}, not a whole number", shown(value[k])));
    wholes.push_back(*n);
  }
  return wholes;
}

bool CheckpointFields::flag(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_boolean()) refuse(key, fmt::format("is {}, not true or false", shown(value)));
  return value.get<bool>();
}

std::string CheckpointFields::text(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_string()) refuse(key, fmt::format("is {}, not a text", shown(value)));
  return value.get<std::string>();
}

std::vector<CheckpointFields> CheckpointFields::list(std::string_view key) const {
  const nlohmann::json& value = at(key);
  if (!value.is_array()) refuse(key, fmt::format("is {}, not a list", shown(value)));
  std::vector<CheckpointFields> items;
  items.reserve(value.size());
  const std::string name = key_name(key);
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (!value[k].is_object())
      refuse(fmt::format("{}[{}]", key, k), fmt::format("is {}, not an object", shown(value[k])));
    items.emplace_back(value[k], file_, fmt::format("{}[{}]", name, k));
  }
  return items;
}

CheckpointFields CheckpointRecord::state() const {
  return CheckpointFields(document.at("state"), file, "state");
}

std::filesystem::path checkpoint_record_path(const std::filesystem::path& folder,
                                             std::string_view prefix, std::int64_t step) {
  return folder / fmt::format("{}_{:010d}.json", prefix, step);
}

void write_checkpoint_record(const std::filesystem::path& file, std::string_view stage,
                             std::int64_t step, const CheckpointState& state) {
  const nlohmann::ordered_json document{{"format", checkpoint_format},
                                        {"version", checkpoint_version},
                                        {"stage", stage},
                                        {"step", step},
                                        {"state", state.json()}};
  write_file_atomically(file, document.dump() + "\n");
}

CheckpointRecord read_checkpoint_record(const std::filesystem::path& file, std::string_view stage) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot be read (a checkpoint record)", file.string()));
  CheckpointRecord record;
  record.file = file;
  try {
    record.document = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format(
        "{}: not a checkpoint record: not JSON or cut short, at byte {} (a damaged checkpoint)",
        file.string(), e.byte));
  } catch (const nlohmann::json::exception& e) {  // a number past a double's range
    throw InputError(fmt::format("{}: not a checkpoint record: {} (a damaged checkpoint)",
                                 file.string(), e.what()));
  }
  const CheckpointFields top(record.document, file, "");
  if (top.text("format") != checkpoint_format)
    top.refuse("format", fmt::format("is not '{}'", checkpoint_format));
  const std::int64_t version = top.whole("version");
  if (version != checkpoint_version)
    throw InputError(fmt::format(
        "{}: key 'version' is {}; this build reads checkpoints of version {} (resume the run "
        "with the build that wrote it, or start it again)",
        file.string(), version, checkpoint_version));
  record.stage = top.text("stage");
  if (record.stage != stage)
    throw InputError(fmt::format("{}: key 'stage' is '{}', not '{}' (another stage's checkpoint)",
                                 file.string(), record.stage, stage));
  record.step = top.whole("step");
  if (record.step < 0) top.refuse("step", fmt::format("is {}, below 0", record.step));
  if (!record.document.contains("state") || !record.document.at("state").is_object())
    top.refuse("state", "is missing or not an object");
  return record;
}

std::vector<std::pair<std::int64_t, std::filesystem::path>> checkpoint_records(
    const std::filesystem::path& folder, std::string_view prefix) {
  const std::regex name(std::string(prefix) + R"(_(\d{10})\.json)");
  std::vector<std::pair<std::int64_t, std::filesystem::path>> records;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, m, name)) records.emplace_back(std::stoll(m[1].str()), entry.path());
  }
  std::sort(records.begin(), records.end());
  return records;
}

bool holds_checkpoints(const std::filesystem::path& folder) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().extension() == ".json" && entry.path().filename() != "resume.json")
      return true;
  return false;
}

}  // namespace shapepress
