#pragma once
// pack.toml: the keys of the `pack` stage, one OptionTable per section (common/options.hpp).
#include <filesystem>
#include <string>

#include "common/config.hpp"
#include "common/options.hpp"
#include "common/resume.hpp"
#include "packing/pack.hpp"

namespace shapepress::packing {

struct PackConfig {
  PackRequest request;
  std::string summary;  // shape-stats summary.json the sizes came from; empty: size_quantiles
  CheckpointPolicy checkpoints;  // [run]: for pack --resume
};

// InputError naming the file and key. A `sizes.summary` path is taken relative to the config's
// folder when it is not absolute. `summary`, when given, is the sizes' source instead of the
// config's [sizes] summary or size_quantiles (`pack --summary`, a study's measured statistics).
PackConfig read_pack_config(const ConfigTable& root, const std::filesystem::path& config_path,
                            const std::filesystem::path& summary = {});
// The effective config: every key with its value (reads back to the same request).
std::string pack_config_toml(const PackConfig& config);
StageOptions pack_config_options();

// The volume-weighted x10/x50/x90 of a `shape-stats` summary.json (its Q3 of the equivalent
// circle diameter). InputError naming the file when it is not such a summary.
// The keys of a size distribution given by quantiles (size_quantiles, size_quantile_levels,
// size_weighting) in config section `section`, shared by [sizes] here and compact's [generate].
OptionTable<SizeQuantiles> size_quantile_table(std::string section, std::string diameters_help,
                                               std::string absent_text, std::string weighting_help);

SizeQuantiles read_summary_sizes(const std::filesystem::path& path);

}  // namespace shapepress::packing
