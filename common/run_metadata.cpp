#include "common/run_metadata.hpp"

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/provenance.hpp"
#include "common/sha256.hpp"

namespace shapepress {

std::filesystem::path run_metadata_beside(const std::filesystem::path& output_file) {
  std::filesystem::path path = output_file;
  path += ".";
  path += run_metadata_name;
  return path;
}

RunMetadata::RunMetadata(std::string stage, std::string command_line)
    : stage_(std::move(stage)),
      command_line_(std::move(command_line)),
      working_directory_(std::filesystem::current_path()) {}

RunMetadata& RunMetadata::input(std::string_view role, const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(fmt::format("{}: no such file (the {} input)", path.string(), role));
  inputs_.push_back(
      {{"role", role}, {"path", path.generic_string()}, {"sha256", sha256_file(path)}});
  return *this;
}

RunMetadata& RunMetadata::output(const std::filesystem::path& relative) {
  outputs_.push_back(relative.generic_string());
  return *this;
}

RunMetadata& RunMetadata::fact(const std::string& key, nlohmann::ordered_json value) {
  // JSON has no NaN or infinity; null says "not finite" plainly, and a reader asking for a
  // number gets an error naming the key rather than a made-up value.
  if (value.is_number_float() && !std::isfinite(value.get<double>())) value = nullptr;
  facts_[key] = std::move(value);
  return *this;
}

RunMetadata& RunMetadata::options(nlohmann::ordered_json options) {
  options_ = std::move(options);
  return *this;
}

nlohmann::ordered_json RunMetadata::json() const {
  nlohmann::ordered_json out{{"schema", run_metadata_schema},
                             {"stage", stage_},
                             {"version", shapepress_version()},
                             {"revision", shapepress_git_revision()},
                             {"command", command_line_},
                             {"working_directory", working_directory_.generic_string()}};
  if (!options_.is_null()) out["options"] = options_;
  out["inputs"] = inputs_;
  out["outputs"] = outputs_;
  out["facts"] = facts_;
  return out;
}

void RunMetadata::write(const std::filesystem::path& path) const {
  write_file_atomically(path, json().dump(2) + "\n");
}

RunRecord RunRecord::read(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw InputError(fmt::format(
        "{}: missing; every run folder needs the run.json its stage writes (runs made before "
        "run.json existed must be run again)",
        path.string()));
  RunRecord record;
  record.path_ = path;
  try {
    record.json_ = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
  const nlohmann::json& j = record.json_;
  if (!j.is_object() || !j.contains("stage") || !j["stage"].is_string())
    throw InputError(fmt::format("{}: no \"stage\" string", path.string()));
  if (!j.contains("facts") || !j["facts"].is_object())
    throw InputError(fmt::format("{}: no \"facts\" object", path.string()));
  if (!j.contains("schema") || !j["schema"].is_number_integer() ||
      j["schema"].get<int>() > run_metadata_schema)
    throw InputError(
        fmt::format("{}: \"schema\" {} is not one this shapepress reads (<= {})", path.string(),
                    j.contains("schema") ? j["schema"].dump() : "missing", run_metadata_schema));
  record.stage_ = j["stage"].get<std::string>();
  return record;
}

RunRecord RunRecord::read(const std::filesystem::path& path, std::string_view stage) {
  RunRecord record = read(path);
  if (record.stage_ != stage)
    throw InputError(fmt::format("{}: made by {}, not by {}", path.string(), record.stage_, stage));
  return record;
}

bool RunRecord::has(const std::string& key) const {
  return json_.at("facts").contains(key);
}

const nlohmann::json& RunRecord::fact(const std::string& key, std::string_view expected) const {
  const nlohmann::json& facts = json_.at("facts");
  const auto it = facts.find(key);
  if (it == facts.end())
    throw InputError(fmt::format("{}: facts has no \"{}\" ({} run.json; {} expected)",
                                 path_.string(), key, stage_, expected));
  return *it;
}

double RunRecord::number(const std::string& key) const {
  const nlohmann::json& value = fact(key, "a number");
  if (!value.is_number())
    throw InputError(fmt::format("{}: facts \"{}\" is {}, expected a number", path_.string(), key,
                                 value.dump()));
  return value.get<double>();
}

std::int64_t RunRecord::integer(const std::string& key) const {
  const nlohmann::json& value = fact(key, "an integer");
  if (!value.is_number_integer())
    throw InputError(fmt::format("{}: facts \"{}\" is {}, expected an integer", path_.string(), key,
                                 value.dump()));
  return value.get<std::int64_t>();
}

std::string RunRecord::text(const std::string& key) const {
  const nlohmann::json& value = fact(key, "a string");
  if (!value.is_string())
    throw InputError(fmt::format("{}: facts \"{}\" is {}, expected a string", path_.string(), key,
                                 value.dump()));
  return value.get<std::string>();
}

std::filesystem::path RunRecord::input_file(const std::string& role) const {
  const nlohmann::json* found = nullptr;
  if (json_.contains("inputs") && json_["inputs"].is_array())
    for (const auto& input : json_["inputs"])
      if (input.is_object() && input.value("role", "") == role) found = &input;
  if (found == nullptr || !found->contains("path") || !(*found)["path"].is_string())
    throw InputError(fmt::format("{}: names no {} among its inputs", path_.string(), role));
  const std::filesystem::path given = (*found)["path"].get<std::string>();
  const std::string sha256 = found->value("sha256", "");
  std::vector<std::filesystem::path> candidates;
  if (given.is_absolute()) {
    candidates.push_back(given);
  } else {
    if (json_.contains("working_directory") && json_["working_directory"].is_string())
      candidates.push_back(std::filesystem::path(json_["working_directory"].get<std::string>()) /
                           given);
    candidates.push_back(given);
    const std::filesystem::path folder = path_.parent_path();
    candidates.push_back(folder / given);
    candidates.push_back(folder / ".." / given);
  }
  std::string tried;
  for (const std::filesystem::path& candidate : candidates) {
    tried += (tried.empty() ? "" : ", ") + candidate.string();
    if (std::filesystem::is_regular_file(candidate) && sha256_file(candidate) == sha256)
      return candidate.lexically_normal();
  }
  throw InputError(
      fmt::format("{}: its {} input {} is gone or changed since the run (SHA-256 {}; tried {})",
                  path_.string(), role, given.string(), sha256, tried));
}

}  // namespace shapepress
