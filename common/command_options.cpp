#include "common/command_options.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <type_traits>

#include "common/error.hpp"
#include "common/sha256.hpp"

namespace shapepress {
namespace {

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};
template <class T>
struct whole_of {
  using type = T;
};
template <class T>
struct whole_of<std::optional<T>> {
  using type = T;
};

// A value as a record keeps it; nothing for "not given".
template <class T>
std::vector<std::string> recorded(const T& value) {
  if constexpr (std::is_same_v<T, std::string>) {
    if (value.empty()) return {};
    return {value};
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    return value;
  } else if constexpr (is_optional<T>::value) {
    if (!value) return {};
    return {std::to_string(*value)};
  } else if constexpr (std::is_same_v<T, bool>) {
    return {value ? "1" : "0"};
  } else if constexpr (std::is_same_v<T, double>) {
    return {exact_text(value)};
  } else {
    return {std::to_string(value)};
  }
}

// A field that can be "not given" (and so may be missing from a record).
template <class T>
constexpr bool may_be_absent() {
  return std::is_same_v<T, std::vector<std::string>> || is_optional<T>::value;
}

template <class Whole>
std::optional<Whole> parse_whole_text(const std::string& text) {
  Whole value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end) return std::nullopt;
  return value;
}

std::string option_key(const std::string& name) {
  return name.substr(name.find_first_not_of('-'));
}

// A Markdown table cell: a bar would end it, and "<name>" would be read as HTML.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text)
    out += c == '|' ? std::string("\\|") : c == '<' ? std::string("&lt;") : std::string(1, c);
  return out.empty() ? "-" : out;
}

// Range::describe() for a whole number: every digit ("in [1, 1000000]", not 1e+06).
std::string whole_range_text(const Range& r) {
  const bool has_min = std::isfinite(r.min), has_max = std::isfinite(r.max);
  if (has_min && has_max)
    return fmt::format("in {}{:.0f}, {:.0f}{}", r.min_inclusive ? '[' : '(', r.min, r.max,
                       r.max_inclusive ? ']' : ')');
  if (has_min) return fmt::format("{} {:.0f}", r.min_inclusive ? ">=" : ">", r.min);
  return r.describe();
}

}  // namespace

CommandOptions::CommandOptions(std::string stage) : stage_(std::move(stage)) {}

CommandOptions& CommandOptions::add(std::string name, Field field, std::string help) {
  Option option;
  option.key = option_key(name);
  option.name = std::move(name);
  option.help = std::move(help);
  option.field = field;
  std::visit(
      [&](auto* f) {
        const std::vector<std::string> text = recorded(*f);
        option.default_text = text.size() == 1 ? text.front() : std::string();
      },
      field);
  options_.push_back(std::move(option));
  return *this;
}

CommandOptions& CommandOptions::text(std::string name, std::string* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::texts(std::string name, std::vector<std::string>* field,
                                      std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::whole(std::string name, int* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::whole(std::string name, std::int64_t* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::whole(std::string name, std::uint64_t* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::whole(std::string name, std::optional<std::int64_t>* field,
                                      std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::whole(std::string name, std::optional<std::uint64_t>* field,
                                      std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::number(std::string name, double* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}
CommandOptions& CommandOptions::flag(std::string name, bool* field, std::string help) {
  return add(std::move(name), field, std::move(help));
}

CommandOptions& CommandOptions::range(Range range) {
  options_.back().range = range;
  return *this;
}
CommandOptions& CommandOptions::choices(std::vector<std::string> names) {
  options_.back().choices = std::move(names);
  return *this;
}
CommandOptions& CommandOptions::show_default() {
  options_.back().show_default = true;
  return *this;
}
CommandOptions& CommandOptions::config() {
  options_.back().config = true;
  return *this;
}
CommandOptions& CommandOptions::output() {
  options_.back().output = true;
  return *this;
}
CommandOptions& CommandOptions::hashed(
    std::function<std::filesystem::path(const std::string&)> file_of) {
  options_.back().hashed = true;
  options_.back().file_of = std::move(file_of);
  return *this;
}
CommandOptions& CommandOptions::excludes(std::string other) {
  options_.back().excludes.push_back(std::move(other));
  return *this;
}
CommandOptions& CommandOptions::recorded_as(std::string key) {
  options_.back().key = std::move(key);
  return *this;
}

void CommandOptions::add_to(CLI::App& app, std::string* resume, std::string resume_help) const {
  std::vector<CLI::Option*> added;
  for (const Option& o : options_) {
    CLI::Option* option = std::visit(
        [&](auto* f) -> CLI::Option* {
          using T = std::remove_pointer_t<decltype(f)>;
          if constexpr (std::is_same_v<T, bool>)
            return app.add_flag(o.name, *f, o.help);
          else
            return app.add_option(o.name, *f, o.help);
        },
        o.field);
    if (!o.choices.empty()) option->check(CLI::IsMember(o.choices));
    if (o.range) {
      const Range& r = *o.range;
      const bool whole = !std::holds_alternative<double*>(o.field);
      if (r.max == std::numeric_limits<double>::infinity() && r.min == 0.0)
        option->check(r.min_inclusive ? CLI::Validator(CLI::NonNegativeNumber)
                                      : CLI::Validator(CLI::PositiveNumber));
      else if (whole)
        option->check(
            CLI::Range(static_cast<std::int64_t>(r.min), static_cast<std::int64_t>(r.max)));
      else
        option->check(CLI::Range(r.min, r.max));
    }
    if (o.show_default) option->capture_default_str();
    for (const std::string& other : o.excludes)
      option->excludes(app.get_option(other));
    added.push_back(option);
  }
  CLI::Option* resumed = app.add_option("--resume", *resume, std::move(resume_help));
  for (CLI::Option* option : added)
    resumed->excludes(option);
}

RunInvocation CommandOptions::invocation(const std::string& command_line) const {
  RunInvocation record;
  record.command_line = command_line;
  record.working_directory = std::filesystem::current_path();
  for (const Option& o : options_) {
    if (o.output) continue;
    const std::vector<std::string> values =
        std::visit([](auto* f) { return recorded(*f); }, o.field);
    if (o.config) {
      record.config = values.empty() ? std::string() : values.front();
      record.config_sha256 = sha256_file(record.config);
      continue;
    }
    if (values.empty()) continue;
    record.arguments[o.key] = values;
    if (o.hashed) {
      const std::string file =
          (o.file_of ? o.file_of(values.front()) : std::filesystem::path(values.front())).string();
      record.inputs.push_back({o.key, file, sha256_file(file)});
    }
  }
  return record;
}

void CommandOptions::restore(const Option& o, const std::vector<std::string>& values,
                             const std::filesystem::path& record) const {
  const auto damaged = [&](const std::string& text) {
    return InputError(fmt::format("{}: argument '{}' is '{}' (a damaged resume record)",
                                  record.string(), o.key, text));
  };
  std::visit(
      [&](auto* f) {
        using T = std::remove_pointer_t<decltype(f)>;
        if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          *f = values;
          return;
        } else {
          if (values.size() != 1)
            throw InputError(
                fmt::format("{}: argument '{}' has {} values (a damaged resume "
                            "record)",
                            record.string(), o.key, values.size()));
          const std::string& text = values.front();
          // A default outside the range means "not given" (0: the config's value).
          bool is_default = text == o.default_text;
          if (!o.choices.empty() && !is_default &&
              std::find(o.choices.begin(), o.choices.end(), text) == o.choices.end())
            throw damaged(text);
          if constexpr (std::is_same_v<T, std::string>) {
            *f = text;
          } else if constexpr (std::is_same_v<T, bool>) {
            if (text != "0" && text != "1") throw damaged(text);
            *f = text == "1";
          } else {
            double value = 0.0;
            if constexpr (std::is_same_v<T, double>) {
              char* end = nullptr;
              value = std::strtod(text.c_str(), &end);
              if (text.empty() || *end != '\0') throw damaged(text);
              *f = value;
            } else {
              using Whole = typename whole_of<T>::type;
              const std::optional<Whole> whole = parse_whole_text<Whole>(text);
              if (!whole) throw damaged(text);
              value = static_cast<double>(*whole);
              *f = *whole;
            }
            is_default = is_default || value == std::strtod(o.default_text.c_str(), nullptr);
            if (o.range && !is_default && !o.range->contains(value)) throw damaged(text);
          }
        }
      },
      o.field);
}

std::string CommandOptions::resume(const std::filesystem::path& record, const std::string& run) {
  const std::string output = std::filesystem::absolute(run).string();
  const RunInvocation invocation = resume_invocation(record, run);
  for (const Option& o : options_) {
    if (o.output) {
      std::get<std::string*>(o.field)->assign(output);
      continue;
    }
    if (o.config) {
      std::get<std::string*>(o.field)->assign(invocation.config);
      continue;
    }
    const auto it = invocation.arguments.find(o.key);
    if (it != invocation.arguments.end()) {
      restore(o, it->second, record);
      continue;
    }
    const bool optional =
        std::visit([](auto* f) { return may_be_absent<std::remove_pointer_t<decltype(f)>>(); },
                   o.field) ||
        (std::holds_alternative<std::string*>(o.field) && o.default_text.empty());
    if (!optional)
      throw InputError(
          fmt::format("{}: no argument '{}' (a damaged resume record)", record.string(), o.key));
  }
  return invocation.command_line;
}

nlohmann::ordered_json CommandOptions::json() const {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const Option& o : options_)
    std::visit(
        [&](auto* f) {
          using T = std::remove_pointer_t<decltype(f)>;
          if constexpr (is_optional<T>::value)
            out[option_key(o.name)] = *f ? nlohmann::ordered_json(**f) : nlohmann::ordered_json();
          else
            out[option_key(o.name)] = *f;
        },
        o.field);
  return out;
}

std::string CommandOptions::markdown() const {
  std::string out = "| option | value | default | meaning |\n|---|---|---|---|\n";
  for (const Option& o : options_) {
    const std::string value = std::visit(
        [&](auto* f) -> std::string {
          using T = std::remove_pointer_t<decltype(f)>;
          if (!o.choices.empty()) return fmt::format("{}", fmt::join(o.choices, " | "));
          if constexpr (std::is_same_v<T, bool>) return "flag";
          if constexpr (std::is_same_v<T, std::vector<std::string>>) return "text, repeated";
          if constexpr (std::is_same_v<T, std::string>) return "text";
          if constexpr (std::is_same_v<T, double>)
            return o.range ? "number " + o.range->describe() : "number";
          return o.range ? "whole number " + whole_range_text(*o.range) : "whole number";
        },
        o.field);
    std::string shown = o.show_default ? o.default_text : std::string();
    if (o.show_default && std::holds_alternative<double*>(o.field))
      shown = fmt::format("{}", *std::get<double*>(o.field));
    out += fmt::format("| `{}` | {} | {} | {} |\n", o.name, cell(value), cell(shown), cell(o.help));
  }
  return out;
}

std::string with_option_tables(std::string_view document,
                               const std::vector<CommandOptions>& tables) {
  std::string out(document);
  constexpr std::string_view end_marker = "<!-- end options -->";
  for (const CommandOptions& table : tables) {
    const std::string begin_marker = fmt::format("<!-- options: {} -->\n", table.stage());
    const std::size_t begin = out.find(begin_marker);
    const std::size_t end = begin == std::string::npos ? begin : out.find(end_marker, begin);
    if (end == std::string::npos)
      throw InputError(fmt::format("no '{}' ... '{}' in the document for the options of {}",
                                   begin_marker.substr(0, begin_marker.size() - 1), end_marker,
                                   table.stage()));
    const std::size_t from = begin + begin_marker.size();
    out.replace(from, end - from, table.markdown());
  }
  return out;
}

}  // namespace shapepress
