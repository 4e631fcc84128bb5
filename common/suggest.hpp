#pragma once
// "did you mean" for mistyped stages, options and config keys.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace shapepress {

std::size_t edit_distance(std::string_view a, std::string_view b);
// The closest candidate within a distance that still looks like a typo, if any.
std::optional<std::string> closest_match(std::string_view word,
                                         std::span<const std::string> candidates);

}  // namespace shapepress
