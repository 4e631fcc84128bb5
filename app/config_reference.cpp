#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/stages.hpp"
#include "common/command_options.hpp"
#include "common/error.hpp"
#include "common/options.hpp"

namespace shapepress {

std::string config_reference_markdown() {
  std::string out =
      "# Config reference\n\n"
      "Generated from the stages' option tables by `shapepress help-config --markdown` "
      "(scripts/update-config-reference.sh); a test fails when this file differs from what "
      "the tables give, so edit the tables, not this file. `shapepress STAGE --help-config` "
      "prints the same keys.\n\n"
      "A quantity is a number in the SI unit shown or a string with a unit (\"30 MPa\", "
      "\"0.1 mm\"). A key a stage does not use is an error, never silently ignored. Every run "
      "writes the config it used, every key with its value, as effective.toml in its output "
      "folder (calibrate: calibrated.toml, with the fitted values).\n\n";
  for (const Stage& stage : registered_stages())
    if (stage.config_options) out += options_markdown(stage.config_options());
  return out;
}

namespace {

struct HelpConfigCli {
  bool markdown = false;
  std::string stage;
};

int run(const HelpConfigCli& cli) {
  if (cli.markdown && cli.stage.empty()) {
    std::fputs(config_reference_markdown().c_str(), stdout);
    return 0;
  }
  bool found = false;
  for (const Stage& stage : registered_stages()) {
    if (!stage.config_options || (!cli.stage.empty() && stage.name != cli.stage)) continue;
    const StageOptions options = stage.config_options();
    std::fputs((cli.markdown ? options_markdown(options) : options_text(options) + "\n").c_str(),
               stdout);
    found = true;
  }
  if (!found) throw InputError("'" + cli.stage + "' is not a stage that reads a config");
  return 0;
}

}  // namespace

std::string with_stage_option_tables(std::string_view document) {
  std::vector<CommandOptions> tables;
  for (const Stage& stage : registered_stages())
    if (stage.command_options) tables.push_back(stage.command_options());
  return with_option_tables(document, tables);
}

StageRunner setup_help_options_cli(CLI::App& app) {
  auto document = std::make_shared<std::string>();
  app.add_option("document", *document, "docs/stages.md, printed with its option tables made anew")
      ->required();
  return [document](const RunContext&) {
    std::ifstream in(*document);
    if (!in) throw InputError(*document + ": cannot be read");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::fputs(with_stage_option_tables(text).c_str(), stdout);
    return 0;
  };
}

StageRunner setup_help_config_cli(CLI::App& app) {
  auto cli = std::make_shared<HelpConfigCli>();
  app.add_flag("--markdown", cli->markdown, "Markdown tables (docs/config-reference.md)");
  app.add_option("stage", cli->stage, "one stage (default: every stage with a config)");
  return [cli](const RunContext&) { return run(*cli); };
}

}  // namespace shapepress
