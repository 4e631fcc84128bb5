#pragma once
// generate's checkpoints (docs/stages.md, "generate", "Checkpoints and --resume"): the
// per-particle work of generate_population and describe_population (GenerateWork) in checkpoint
// records particles_N.json of the stage "generate" (common/checkpoint.hpp) in a checkpoint
// folder, N the run's step count when it was written. Each record holds only what was done since
// the one before (its lists draws, views, boxes and descriptors, each item naming its particle;
// a population's silhouettes run to megabytes: rewriting them all at every checkpoint would grow
// with the square of the run), so every record stays until the run ends whole; a resumed run
// reads them all in order, every number with every bit.
#include <cstdint>
#include <filesystem>

#include "geometry/generate.hpp"

namespace shapepress::geometry {

// Writes what `work` holds beyond what was written (or read back) before.
class GenerateCheckpoints {
 public:
  // `written`: the work already in `folder` (read_generate_checkpoints), none for a fresh run.
  GenerateCheckpoints(std::filesystem::path folder, const GenerateWork& written);
  void write(const GenerateWork& work);

 private:
  std::filesystem::path folder_;
  std::size_t draws_ = 0, corrections_ = 0, descriptors_ = 0;
  std::vector<std::size_t> views_;
};

// Every particles_N.json in `folder`, in order: the work of a run of `count` particles so far
// (empty without a checkpoint). InputError naming the file and the key when one is damaged or
// does not continue the ones before it. `latest_step` is set to the newest file's N (0: none).
GenerateWork read_generate_checkpoints(const std::filesystem::path& folder, std::size_t count,
                                       std::int64_t& latest_step);

}  // namespace shapepress::geometry
