#pragma once
// The table of stages the `shapepress` binary offers. A stage is listed only when it is real.
#include <span>
#include <string>
#include <string_view>

#include "common/stage.hpp"

namespace shapepress {

std::span<const Stage> registered_stages();

// shapepress help-config [--markdown] [STAGE]: the config keys of the stages that read a config,
// as text or as the Markdown of docs/config-reference.md (a test keeps that file equal to it).
StageRunner setup_help_config_cli(CLI::App& app);
// The Markdown of docs/config-reference.md.
std::string config_reference_markdown();

// shapepress help-options DOCUMENT: DOCUMENT (docs/stages.md) with each stage's option table
// between its markers, as the stages' tables give them now (a test keeps the file equal to it).
StageRunner setup_help_options_cli(CLI::App& app);
// `document` with the option tables put in (common/command_options.hpp with_option_tables).
std::string with_stage_option_tables(std::string_view document);

}  // namespace shapepress
