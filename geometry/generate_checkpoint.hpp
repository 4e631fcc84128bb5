#pragma once
// generate's checkpoints (docs/stages.md, "generate", "Checkpoints and --resume"): the
// per-particle work of generate_population and describe_population (GenerateWork) in files
// particles_N.history of a checkpoint folder, N the run's step count when it was written. Each
// file holds only what was done since the one before (a population's silhouettes run to
// megabytes: rewriting them all at every checkpoint would grow with the square of the run), so
// every file stays until the run ends whole; each is written atomically, and a resumed run reads
// them all in order. Doubles are hexadecimal floats, so a resumed run gets every bit back.
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

// Every particles_N.history in `folder`, in order: the work of a run of `count` particles so
// far (empty without a checkpoint). InputError naming the file when one is damaged or does not
// continue the ones before it. `latest_step` is set to the newest file's N (0: none).
GenerateWork read_generate_checkpoints(const std::filesystem::path& folder, std::size_t count,
                                       std::int64_t& latest_step);

}  // namespace shapepress::geometry
