// shapepress: from images of a powder to simulated tablet-compaction curves.
// One binary, one table of stages (app/stages.cpp); each stage parses its own options and
// calls its library. main() owns the global options, the exit codes and the error messages.
#include <omp.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "app/stages.hpp"
#include "common/error.hpp"
#include "common/logging.hpp"
#include "common/options.hpp"
#include "common/provenance.hpp"
#include "common/run_lock.hpp"
#include "common/suggest.hpp"

namespace {

using shapepress::ExitCode;

int usage_error(const std::string& message, const std::string& hint) {
  std::fprintf(stderr, "shapepress: error: %s\n", message.c_str());
  if (!hint.empty()) std::fprintf(stderr, "%s\n", hint.c_str());
  return static_cast<int>(ExitCode::bad_input);
}

std::string join_command_line(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) line += ' ';
    line += argv[i];
  }
  return line;
}

// What stands before the stage name: global options (and their values), then the stage.
struct CommandWords {
  std::optional<std::string> stage;
  std::optional<std::string> unknown_option;  // a mistyped global option before the stage
};

CommandWords scan_command_words(int argc, char** argv) {
  static constexpr std::array<std::string_view, 2> with_value{"--threads", "--log-level"};
  static constexpr std::array<std::string_view, 5> flags{"--help", "-h", "--version", "--quiet",
                                                         "-q"};
  CommandWords words;
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    std::string_view name = arg.substr(0, arg.find('='));
    if (std::find(with_value.begin(), with_value.end(), name) != with_value.end()) {
      if (name == arg) ++i;
      continue;
    }
    if (std::find(flags.begin(), flags.end(), arg) != flags.end()) continue;
    if (arg.starts_with('-')) {
      words.unknown_option = std::string(arg);
      return words;
    }
    words.stage = std::string(arg);
    return words;
  }
  return words;
}

std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* a = &app; a != nullptr; a = a->get_parent())
    for (const CLI::Option* option : a->get_options())
      for (const std::string& name : option->get_lnames())
        names.push_back("--" + name);
  return names;
}

// The first word a stage did not understand, with the closest of its options.
int unknown_argument_error(const CLI::App& sub, const std::string& extra) {
  std::optional<std::string> guess =
      shapepress::closest_match(extra.substr(0, extra.find('=')), option_names(sub));
  return usage_error(
      fmt::format("'{}' is not an option or argument of 'shapepress {}'", extra, sub.get_name()),
      guess ? fmt::format("Did you mean '{}'? (shapepress {} --help)", *guess, sub.get_name())
            : fmt::format("shapepress {} --help lists its options", sub.get_name()));
}

// What a stage's run writes into: its --out, else the run its --resume continues (advise's
// --resume is a flag beside its --out).
std::optional<std::string> run_output(const CLI::App& sub) {
  for (const char* name : {"--out", "--resume"}) {
    const CLI::Option* option = sub.get_option_no_throw(name);
    if (option != nullptr && option->get_expected_min() > 0 && option->count() > 0 &&
        !option->results().front().empty())
      return option->results().front();
  }
  return std::nullopt;
}

void add_global_options(CLI::App& app, shapepress::RunContext& context, std::string& log_level) {
  using namespace shapepress;
  app.set_version_flag("--version", fmt::format("shapepress {} ({})", shapepress_version(),
                                                shapepress_git_revision()));
  app.add_option("--threads", context.threads, "OpenMP threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("-q,--quiet", context.quiet, "no progress lines, only errors");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")
      ->capture_default_str();
  app.fallthrough();  // global options may also follow the stage name
  app.require_subcommand(0, 1);
}

// A stage's subcommand and what runs it.
struct StageCommand {
  CLI::App* sub;
  shapepress::StageRunner run;
  shapepress::RunOutput output;
};

std::vector<StageCommand> add_stages(CLI::App& app, std::span<const shapepress::Stage> stages) {
  std::vector<StageCommand> commands;
  for (const shapepress::Stage& stage : stages) {
    CLI::App* sub = app.add_subcommand(std::string(stage.name), std::string(stage.summary));
    sub->allow_extras();  // reported below with a suggestion instead of CLI11's bare message
    commands.push_back({sub, stage.setup(*sub), stage.output});
    if (stage.config_options) {
      // Runs as soon as it is parsed, before the stage's required options are checked.
      sub->add_flag_callback(
             "--help-config",
             [options = stage.config_options] {
               std::fputs(shapepress::options_text(options()).c_str(), stdout);
               throw CLI::Success();
             },
             "print the config file's keys (units, ranges, defaults) and exit")
          ->trigger_on_parse();
    }
  }
  return commands;
}

// A mistyped global option or stage name, with the closest known one (exit 2); none when both
// are known.
std::optional<int> misspelled_command(const CLI::App& app, const CommandWords& words,
                                      const std::vector<std::string>& stage_names) {
  if (words.unknown_option) {
    std::vector<std::string> names = option_names(app);
    std::optional<std::string> guess = shapepress::closest_match(*words.unknown_option, names);
    return usage_error(fmt::format("'{}' is not a shapepress option", *words.unknown_option),
                       guess ? fmt::format("Did you mean '{}'? (shapepress --help)", *guess)
                             : "shapepress --help lists the options");
  }
  if (words.stage &&
      std::find(stage_names.begin(), stage_names.end(), *words.stage) == stage_names.end()) {
    std::optional<std::string> guess = shapepress::closest_match(*words.stage, stage_names);
    return usage_error(
        fmt::format("'{}' is not a shapepress stage", *words.stage),
        guess ? fmt::format("Did you mean '{}'? (shapepress --help lists the stages)", *guess)
              : "shapepress --help lists the stages");
  }
  return std::nullopt;
}

// A mistyped option of the stage is reported before CLI11 complains about a required value it
// hid ("--confg x" leaves --config missing).
std::optional<int> misspelled_stage_option(CLI::App& app, const std::string& stage, int argc,
                                           char** argv) {
  CLI::App* sub = app.get_subcommand(stage);
  std::vector<std::string> names = option_names(*sub);
  bool after_stage = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (!after_stage) {
      after_stage = arg == stage;
      continue;
    }
    if (arg == "--") break;
    if (arg.starts_with("--") &&
        std::find(names.begin(), names.end(), arg.substr(0, arg.find('='))) == names.end())
      return unknown_argument_error(*sub, arg);
  }
  return std::nullopt;
}

// Runs the parsed stage; its errors become the exit codes (2 bad input, others by kind).
int run_stage(const StageCommand& command, const shapepress::RunContext& context,
              const std::string& log_level) {
  using namespace shapepress;
  CLI::App& sub = *command.sub;
  if (!sub.remaining().empty()) return unknown_argument_error(sub, sub.remaining().front());
  try {
    configure_logging(log_level, context.quiet);
    if (context.threads > 0) omp_set_num_threads(context.threads);
    // Held until the stage returns: every stage's outputs, checkpoints and --resume go
    // through here, so two runs never write one output (issue 42).
    std::optional<RunFolderLock> lock;
    if (const std::optional<std::string> out = run_output(sub))
      lock.emplace(*out, command.output, context.command_line);
    return command.run(context);
  } catch (const InputError& e) {
    std::fprintf(stderr, "shapepress %s: error: %s\n", sub.get_name().c_str(), e.what());
    return static_cast<int>(ExitCode::bad_input);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shapepress %s: failed: %s\n", sub.get_name().c_str(), e.what());
    return static_cast<int>(exit_code_for(e));
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shapepress;
  RunContext context;
  context.command_line = join_command_line(argc, argv);
  std::string log_level = "info";

  CLI::App app{
      "shapepress: from images of a real powder to simulated tablet-compaction curves.\n"
      "Each stage reads and writes files; run 'shapepress STAGE --help' for its options.",
      "shapepress"};
  add_global_options(app, context, log_level);
  std::span<const Stage> stages = registered_stages();
  const std::vector<StageCommand> commands = add_stages(app, stages);
  std::vector<std::string> stage_names;
  for (const Stage& stage : stages)
    stage_names.emplace_back(stage.name);

  CommandWords words = scan_command_words(argc, argv);
  if (std::optional<int> error = misspelled_command(app, words, stage_names)) return *error;
  if (words.stage)
    if (std::optional<int> error = misspelled_stage_option(app, *words.stage, argc, argv))
      return *error;

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    return usage_error(e.what(), "Run 'shapepress STAGE --help' for the stage's options.");
  }

  for (const StageCommand& command : commands)
    if (command.sub->parsed()) return run_stage(command, context, log_level);
  std::fputs(app.help().c_str(), stdout);
  return stages.empty() ? 0 : static_cast<int>(ExitCode::bad_input);
}
