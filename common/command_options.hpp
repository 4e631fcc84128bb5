#pragma once
// The command-line options of a stage, each bound once to the field it fills (after COLMAP's
// option manager, as common/options.hpp binds the config keys). The one table
//  - adds the options to the stage's CLI11 subcommand, with --resume last, excluding them all;
//  - records what a run was started with (resume.json, common/resume.hpp) and rebuilds the
//    options from that record for --resume, refusing a damaged one by name;
//  - writes the effective options into run.json ("options");
//  - documents the options: docs/stages.md's option tables are generated from it (a test keeps
//    them equal).
// A stage builds its table with a function of its options struct, `CommandOptions
// compact_command(CompactCli&)`, called for each job on the struct at hand: the table binds
// fields by address, so the struct must outlive it.
//
// In a record an option is its name without the dashes; whole numbers are decimal, numbers
// hexadecimal floats (every bit back), flags 1 or 0. An option with no "not given" state (a
// number, a flag, a text with a default) is always recorded, and a record without it is damaged;
// the others (an empty text or list, an empty std::optional) are recorded when given.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "common/config.hpp"
#include "common/resume.hpp"

namespace CLI {
class App;
}

namespace shapepress {

class CommandOptions {
 public:
  explicit CommandOptions(std::string stage);

  // `name` is "--name", or a bare word for a positional argument.
  CommandOptions& text(std::string name, std::string* field, std::string help);
  // Repeatable (or a positional taking every remaining word).
  CommandOptions& texts(std::string name, std::vector<std::string>* field, std::string help);
  CommandOptions& whole(std::string name, int* field, std::string help);
  CommandOptions& whole(std::string name, std::int64_t* field, std::string help);
  CommandOptions& whole(std::string name, std::uint64_t* field, std::string help);
  CommandOptions& whole(std::string name, std::optional<std::int64_t>* field, std::string help);
  CommandOptions& whole(std::string name, std::optional<std::uint64_t>* field, std::string help);
  CommandOptions& number(std::string name, double* field, std::string help);
  CommandOptions& flag(std::string name, bool* field, std::string help);

  // Modifiers of the option added last.
  // Allowed values; the field's default stays allowed (0: "the config's").
  CommandOptions& range(Range range);
  CommandOptions& choices(std::vector<std::string> names);
  // The default shown in --help and the documentation.
  CommandOptions& show_default();
  // The config file: the record keeps it with its SHA-256 (a resume refuses a changed one).
  CommandOptions& config();
  // The run's output: not recorded; a resumed run's is the folder (or file) --resume names.
  CommandOptions& output();
  // A file whose SHA-256 the record keeps, like the config's; `file_of` maps the option's text
  // to the file read (a run folder to its force.csv).
  CommandOptions& hashed(std::function<std::filesystem::path(const std::string&)> file_of = {});
  // Not given together with the option `other` (added before).
  CommandOptions& excludes(std::string other);
  // The name in records written by earlier builds, which --resume still reads.
  CommandOptions& recorded_as(std::string key);

  // Adds the options to `app`, then --resume (into `resume`, with `resume_help`) excluding them.
  void add_to(CLI::App& app, std::string* resume, std::string resume_help) const;

  // What resume.json keeps of this run, started by `command_line` from the working folder.
  RunInvocation invocation(const std::string& command_line) const;
  // Fills the fields from the record at `record` of the run `run` (--resume's argument), whose
  // working folder becomes current; the output field is `run`, made absolute first. Returns the
  // command line the run was started with. InputError naming the record, the option and its text
  // when the record is damaged (common/resume.hpp resume_invocation for the rest).
  std::string resume(const std::filesystem::path& record, const std::string& run);

  // Every option with its effective value, typed, by its name without the dashes (run.json's
  // "options").
  nlohmann::ordered_json json() const;
  // The Markdown table of docs/stages.md.
  std::string markdown() const;
  const std::string& stage() const { return stage_; }

 private:
  using Field =
      std::variant<std::string*, std::vector<std::string>*, int*, std::int64_t*, std::uint64_t*,
                   std::optional<std::int64_t>*, std::optional<std::uint64_t>*, double*, bool*>;
  struct Option {
    std::string name, help, key;
    Field field;
    std::string default_text;  // the field's value when the table was made, as recorded
    std::optional<Range> range;
    std::vector<std::string> choices;
    bool show_default = false;
    bool config = false;
    bool output = false;
    bool hashed = false;
    std::function<std::filesystem::path(const std::string&)> file_of;
    std::vector<std::string> excludes;
  };
  CommandOptions& add(std::string name, Field field, std::string help);
  void restore(const Option& option, const std::vector<std::string>& values,
               const std::filesystem::path& record) const;

  std::string stage_;
  std::vector<Option> options_;
};

// The Markdown of `document` (docs/stages.md) with the table of each of `tables` put between its
// markers "<!-- options: STAGE -->" and "<!-- end options -->". InputError when a table's markers
// are missing.
std::string with_option_tables(std::string_view document,
                               const std::vector<CommandOptions>& tables);

}  // namespace shapepress
